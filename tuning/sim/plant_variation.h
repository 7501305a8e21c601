// The scenario's `plant` section applied to the simulated car (params/schema/
// plant_variation_params.h): the actuator model (the vehicle file's = the real car, or the
// paper's simulator at its current or its IV-2024 defaults), the brake's dead-time/lag split at
// a fixed total response, the steering dead time, the rear tyre's force beyond its peak and the
// yaw inertia.
//
//   ApplyPlantVariation(vehicle, plant) -> the simulated car's VehicleParams
//
// in this order: actuators, brake dead time, steering delay, rear tyre fall-off, yaw inertia.
// With every field at its default the result is `vehicle` bit for bit.
//
// Brake dead time at a fixed total response. The total response T is the time the selected
// brake actuator (delay d0, lag tau0, rate limit r, at the vehicle's plant step h) needs to reach
// 63.2 % of an 80 bar step (plant::BrakeStepResponseTime, what `scw vehicle balance` prints).
// For a dead time d the lag tau is found by bisection such that the actuator with (d, tau, r)
// reaches the same 63.2 % at T, to within one plant step (in fact exactly: the response time is
// a whole number of steps and tau is taken from the middle of the interval that gives T). The
// response time grows monotonically with tau, so tau exists iff the actuator with (d, 0, r) is
// not later than T: d <= T - t_r, t_r = the time the rate limit alone needs (28.1 ms at 1800
// bar/s, 29 steps at 1 ms).
//
// Rear tyre fall-off. The Magic Formula F = D sin(C atan(B x - E (B x - atan B x))) tends to the
// sliding force D sin(C pi/2) at large slip (E < 1). A fall-off s scales the loss beyond the
// peak: the rear tyre's Mf52Params::falloff is multiplied by s, and the tyre model then gives
// D - s (D - F) beyond the slip of the peak (plant/tire/magic_formula.h), longitudinal and
// lateral. The curve up to the peak, the peak D and the slip stiffness stay exactly; the sliding
// force becomes D (1 - s (1 - sin(C pi/2))). C <= 1 or C >= 2 has no peak with a positive sliding
// force (only s = 1 is accepted then); s with 1 - s (1 - sin(C pi/2)) <= 0 would make the sliding
// force zero or negative.
//
// Errors are ConfigError with the path `plant.<key>` and the feasible range. ApplyPlantVariation
// checks the whole section before it changes anything and lists every violation at once.
#pragma once

#include "params/schema/plant_variation_params.h"
#include "params/schema/vehicle_params.h"

namespace scw::tuning {

/// The paper's simulator's brakes: Open Car Dynamics has no brake-pressure dynamics (its wheel-
/// torque and drive-force inputs have no delay and no lag; TUMFTM/Open-Car-Dynamics, ros2/
/// ocd_drivetrain_wheel_torque_communication_handler_cpp/src/comm_handler.cpp,
/// ros2/ocd_drivetrain_fx_communication_handler_cpp/src/comm_handler.cpp), so the requested
/// pressure acts at once: delay 0, lag 0, the schema's largest rate (100 000 bar/s, 100 bar per
/// 1 ms step). Torque gains and the pressure limit stay the vehicle's.
params::BrakeParams PaperSimBrakes(const params::BrakeParams& vehicle);

/// The paper's simulator's steering: the PT1 actuator with rate limit of Open Car Dynamics at its
/// shipped defaults (T_PT1 0.06 s, 0.5 rad/s; lib/ocd_steering_actuator_pt1_cpp/src/
/// steering_actuator_pt1_model.cpp) behind the 60 ms pure delay of its ROS communication handler
/// (delay.steering.actuation_delay_us = 60000; ros2/ocd_steering_actuator_pt1_communication_
/// handler_cpp/src/comm_handler.cpp). The angle limit stays the vehicle's (the planner and the
/// controllers use it). Version 1.0.0 had 50 ms, T_PT1 0.05 s and 1.0 rad/s (PaperSimV1Steering).
params::SteeringParams PaperSimSteering(const params::SteeringParams& vehicle);

/// The paper's simulator as its cited IV-2024 code had it (Open Car Dynamics 1.0.0, commit
/// 53cc85fe; the paper's simulator reference sagmeister2024sim), `plant.actuators: paper_sim_v1`.
/// Its "simple drivetrain" took the longitudinal request behind a 10 ms pure delay
/// (delay.acceleration.actuation_delay_us = 10000) and a PT1 with T = 0.03 s (src/.../
/// simple_drivetrain_cpp/src/drivetrain_simple_eqns.cpp), read here as the brake pressure's
/// delay 0.01 s and lag 0.03 s with no rate limit (the schema's largest). Torque gains and the
/// pressure limit stay the vehicle's.
params::BrakeParams PaperSimV1Brakes(const params::BrakeParams& vehicle);

/// Open Car Dynamics 1.0.0's steering: 50 ms pure delay (delay.steering.actuation_delay_us =
/// 50000), PT1 T = 0.05 s, 1.0 rad/s (src/.../vehicle_dynamics_helpers_cpp/src/
/// steering_actuator.cpp, double_track_model.cpp). The angle limit stays the vehicle's.
params::SteeringParams PaperSimV1Steering(const params::SteeringParams& vehicle);

/// The actuator models `plant.actuators` accepts, as the error names them.
inline constexpr const char* kActuatorModels = "vehicle|paper_sim|paper_sim_v1";

/// Time [s] for the brakes to reach 63.2 % of an 80 bar step at plant step h.
double BrakeTotalResponse(const params::BrakeParams& brakes, double h);

/// The dead times [s] that can keep the total response of `brakes` (at plant step h).
struct DeadTimeRange {
  double total = 0.0;  ///< the total response T [s]
  double min = 0.0;    ///< 0
  double max = 0.0;    ///< T - t_r (negative: not even zero dead time keeps T)
};
DeadTimeRange FeasibleBrakeDeadTimes(const params::BrakeParams& brakes, double h);

/// `brakes` with dead time `dead_time` and the lag that keeps its total response (at plant step
/// h); `brakes` itself for its own dead time. Throws ConfigError (path plant.brake_dead_time)
/// outside FeasibleBrakeDeadTimes.
params::BrakeParams BrakesWithDeadTime(const params::BrakeParams& brakes, double h,
                                       double dead_time);

/// `tire` with its loss of force beyond the peak scaled by `falloff` (Mf52Params::falloff; see
/// the header comment). Throws ConfigError (path plant.rear_tire_falloff) where PCY1 or PCX1 lies
/// outside (1, 2) and falloff is not 1, or where the sliding force would reach zero.
params::Mf52Params WithFalloff(const params::Mf52Params& tire, double falloff);

/// The simulated car: `vehicle` with `plant` applied (see above). Throws one ConfigError listing
/// every problem of `plant` (unknown actuators, infeasible dead time, infeasible fall-off) before
/// anything is applied. The result is not validated as a vehicle here (the caller does).
params::VehicleParams ApplyPlantVariation(const params::VehicleParams& vehicle,
                                          const params::PlantVariationParams& plant);

}  // namespace scw::tuning
