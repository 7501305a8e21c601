// Builds the motion controller a scenario names (motion.controller). New motion controllers
// (point-mass MPC, single-track NMPC) register here; everything else (closed loop, sweeps,
// studies) picks them up through the scenario key.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "controller/motion/motion_controller.h"
#include "tuning/sim/scenario.h"

namespace scw::tuning {

/// Throws ConfigError for an unknown name or invalid parameters.
std::unique_ptr<controller::motion::MotionController> MakeMotionController(
    const ResolvedScenario& sc);

/// Names accepted by MakeMotionController.
std::vector<std::string> MotionControllerNames();

}  // namespace scw::tuning
