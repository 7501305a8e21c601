#include "tuning/sim/motion_factory.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <utility>
#include <vector>

#include "controller/motion/nmpc.h"
#include "controller/motion/pmpc.h"
#include "controller/motion/pure_pursuit.h"
#include "controller/planning/corridor.h"
#include "params/schema/grip_scaling.h"

namespace scw::tuning {
namespace {

namespace cm = controller::motion;

/// The planner's limits: the plant's g-g-v table × limit_fraction × GG.
cm::GgTable PlannerLimits(const ResolvedScenario& sc) {
  return sc.ggv.Scaled(sc.spec.gg_scale * sc.spec.limit_fraction);
}

/// The reference's corridor (controller/planning/corridor.h), capped at 60 % of the scenario's
/// lateral-error abort threshold (the MPC never plans towards an abort; the reference keeps
/// raceline_margin from the edges anyway).
cm::Corridor MakeCorridor(const ResolvedScenario& sc) {
  return controller::planning::MakeCorridor(*sc.track, *sc.path,
                                            0.6 * sc.spec.abort.max_lateral_error);
}

}  // namespace

std::vector<std::string> MotionControllerNames() { return {"pure_pursuit", "pmpc", "nmpc"}; }

std::unique_ptr<controller::motion::MotionController> MakeMotionController(
    const ResolvedScenario& sc) {
  const std::string& name = sc.spec.motion.controller;
  if (name == "pure_pursuit") {
    controller::motion::PurePursuitOptions ppo;
    ppo.max_curvature_lookahead = sc.spec.motion.max_curvature_lookahead;
    ppo.esc_target =
        sc.spec.motion.esc_target == "total" ? cm::EscTarget::kTotal : cm::EscTarget::kFeedback;
    return std::make_unique<controller::motion::PurePursuit>(sc.tracking, sc.path, ppo);
  }
  // The MPCs model the car the planner planned for: the scenario's grip unless the reference was
  // planned with nominal grip.
  params::VehicleParams model_vehicle = sc.vehicle;
  if (sc.spec.plan_with_nominal_grip) params::UnscaleGrip(sc.spec.grip, &model_vehicle.grip);
  const cm::SingleTrackParams st = cm::SingleTrackParamsFrom(model_vehicle);
  try {
    if (name == "pmpc") {
      cm::PmpcOptions o;
      static_cast<params::PmpcParams&>(o) = sc.spec.motion.pmpc;  // motion.pmpc.*
      if (PmpcWithinProvidedLimits(sc.spec)) {
        // Nothing above the planner's limits; the reference was planned at target_fraction of
        // them (ResolveReference), so the plan can follow it.
        o.nominal_fraction = 1.0;
        o.headroom = 1.0;
      }
      o.sample_time = sc.tracking.tS;
      o.solve_period = std::max(o.solve_period, o.sample_time);
      o.wheelbase = sc.vehicle.chassis.wheelbase;
      o.max_steering = sc.vehicle.steering.max_angle;
      o.understeer_gradient = cm::UndersteerGradient(st, 50.0);
      return std::make_unique<cm::PointMassMpc>(o, PlannerLimits(sc), MakeCorridor(sc), sc.path);
    }
    if (name == "nmpc") {
      cm::NmpcOptions o;
      static_cast<params::NmpcParams&>(o) = sc.spec.motion.nmpc;  // motion.nmpc.*
      o.max_steering = sc.vehicle.steering.max_angle;
      return std::make_unique<cm::SingleTrackMpc>(o, st, PlannerLimits(sc), MakeCorridor(sc),
                                                  sc.path);
    }
  } catch (const ConfigError& e) {
    std::vector<Problem> problems;
    for (const Problem& p : e.problems())
      problems.push_back(
          {"motion.controller", name + ": " + (p.path.empty() ? "" : p.path + ": ") + p.message});
    throw ConfigError(sc.source, std::move(problems));
  } catch (const std::exception& e) {
    throw ConfigError(sc.source, "motion.controller", name + ": " + e.what());
  }
  throw ConfigError(sc.source, "motion.controller", "unknown motion controller '" + name + "'");
}

}  // namespace scw::tuning
