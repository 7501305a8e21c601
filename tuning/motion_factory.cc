#include "tuning/motion_factory.h"

#include "controller/motion/pure_pursuit.h"

namespace scw::tuning {

std::vector<std::string> MotionControllerNames() { return {"pure_pursuit"}; }

std::unique_ptr<controller::motion::MotionController> MakeMotionController(
    const ResolvedScenario& sc) {
  const std::string& name = sc.spec.motion.controller;
  if (name == "pure_pursuit") {
    controller::motion::PurePursuitOptions ppo;
    ppo.max_curvature_lookahead = sc.spec.motion.max_curvature_lookahead;
    return std::make_unique<controller::motion::PurePursuit>(sc.tracking, sc.path, ppo);
  }
  throw ConfigError(sc.source, "motion.controller", "unknown motion controller '" + name + "'");
}

}  // namespace scw::tuning
