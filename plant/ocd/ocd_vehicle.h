// Open-Car-Dynamics (OCD) as a plant of scw: the paper's own simulator (sagmeister2024sim) behind
// scw's plant interface (plant/vehicle/plant_model.h), beside scw's reduced double track.
//
// Contract
// --------
// Model: OCD's composition tam::ocd::VehicleModel<RWD_LSD drivetrain, steering, double-track
//   vehicle dynamics<MF52 tyres, default aerodynamics>> (../shared/spec/plant-and-track.md §2):
//   a 6-DOF sprung body on springs, dampers and anti-roll bars with four unsprung vertical DOF,
//   first-order tyre relaxation, MF5.2 combined-slip forces, the rear axle with a limited-slip
//   differential, integrated with OCD's fixed-step Dormand-Prince step. Its parameters come from
//   the vehicle file through the one mapping of plant/ocd/ocd_parameters.h (docs/ocd-plant.md).
// Inputs, per step of h = simulation.time_step (one OCD step of h, inputs held over it), through
//   OCD's public inputs only:
//   - steering: scw's steering actuator (plant/actuator: delay, lag, rate limit; the scenario's
//     plant.actuators chooses the vehicle file's or the paper's simulator's) gives the road-wheel
//     angle, which OCD's steering slot passes to both front wheels unchanged (a pass-through model
//     of OCD's steering-actuator interface, so no second actuator acts);
//   - drive: scw's engine map and gearbox (plant/powertrain: shift logic, torque cut, launch
//     clutch) give OCD's transmission_output_torque_Nm = T_e(omega_e, throttle) i_g i_f eta and
//     current_engine_inertia_at_wheels_kgm2 = I_e (i_g i_f)^2 (0 while the clutch slips), with
//     omega_e from the rear wheels' mean speed, as in scw's plant;
//   - brakes: scw's brake actuator gives the calliper pressures; OCD's brake_torque_per_wheel_Nm =
//     k_b p (brakes.torque_gain_front/_rear);
//   - environment: the world-frame wind rotated into the body frame is OCD's wind_mps; the road's
//     friction factor of each wheel scales that tyre's friction (LMUX, LMUY: the peak, as scw's
//     tires.grip_scaling peak does) or, with grip_scaling curve, OCD's lambda_mue (the whole
//     force).
// State (OcdState, derived from plant::State, owned by the caller): a per-run instance of OCD's
//   model (its state vector lives inside it) and scw's actuator, gearbox and throttle states. The
//   fields of plant::State hold what the rest of scw reads, from OCD's output after each step
//   (OCD's VehicleModelOutput, what OCD's own ROS node publishes: the values of its last ODE stage
//   at t + h): x[kX, kY, kPsi, kVx, kVy, kYawRate] pose and body velocities, x[kOmega*] wheel
//   speeds, x[kKappa*], x[kAlpha*] OCD's relaxed slips fed to its tyres, x[kAx/AyLoadTransfer]
//   OCD's body-frame specific force (its IMU accelerations), rates 0; out.a_x/a_y the same,
//   out.fz OCD's vertical tyre forces, out.fx/fy its tyre-frame forces (y left for every wheel),
//   out.kappa/alpha the relaxed slips, out.brake_torque k_b p, engine speed, engine and axle
//   torque.
// Measure: the same sensors and noise as scw's plant (plant/sensors, plant::MeasureState).
// Start: MakeState puts the car at the pose and speed of the InitialCondition with the wheels
//   rolling freely and the sprung body settled on its springs under the downforce at that speed
//   (heave, pitch and wheel positions of the static equilibrium), so a flying start does not
//   bounce.
// Ownership and threads: OcdVehicle is immutable after construction and serves parallel runs;
//   each run's OCD instance lives in its OcdState. OCD keeps no mutable global state that the
//   adapter touches (its parameter layer's initialisation table is only read, never written).
//   Deterministic: the same inputs give bit-identical states on any thread.
// Step is noexcept and reads no clock; unlike scw's plant it allocates: OCD's VehicleModel::step
//   builds a std::function for its integrator and looks its step size up by name at every step.
//   A non-finite OCD output sets kStatusNonFinite and freezes the state at its last finite value.
// Built only when OCD is found (CMake option SCW_WITH_OCD; docs/ocd-plant.md).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "params/schema/per_wheel.h"
#include "params/schema/vehicle_params.h"
#include "plant/actuator/actuators.h"
#include "plant/ocd/ocd_parameters.h"
#include "plant/powertrain/engine.h"
#include "plant/powertrain/gearbox.h"
#include "plant/sensors/measurement.h"
#include "plant/sensors/sensor_noise.h"
#include "plant/vehicle/environment.h"
#include "plant/vehicle/plant_model.h"
#include "plant/vehicle/vehicle.h"

namespace scw::plant::ocd {

/// OCD's model instance of one run (defined where OCD's headers are included).
struct OcdModel;
struct OcdModelDelete {
  void operator()(OcdModel* m) const noexcept;
};

/// The state of one run on OCD: scw's common state fields (filled from OCD's output) and OCD's
/// own model instance. Move-only.
struct OcdState : State {
  std::unique_ptr<OcdModel, OcdModelDelete> model;
  /// Road friction factors currently applied to the tyre models (grip_scaling peak).
  PerWheel<double> road_mu{1.0, 1.0, 1.0, 1.0};
};

class OcdVehicle {
 public:
  /// Validates the parameters and checks that OCD can represent them (throws scw::ConfigError
  /// listing every problem, plant/ocd/ocd_parameters.h CheckRepresentable).
  explicit OcdVehicle(const params::VehicleParams& p);

  const params::VehicleParams& params() const noexcept { return p_; }
  double time_step() const noexcept { return h_; }
  const PerWheel<double>& contact_x() const noexcept { return px_; }
  const PerWheel<double>& contact_y() const noexcept { return py_; }
  /// The OCD parameters this plant sets (MapVehicle of its vehicle file).
  const std::vector<OcdParameter>& ocd_parameters() const noexcept { return parameters_; }

  /// A new OCD instance with the mapped parameters at the start condition (allocates).
  OcdState MakeState(const InitialCondition& ic = {}) const;

  /// One step of h on the nominal road in still air.
  void Step(const Actuators& u, OcdState* s) const noexcept { StepIn(u, nullptr, s); }
  /// One step of h in `env` (road friction per wheel, wind); the default Environment gives the
  /// step above.
  void Step(const Actuators& u, const Environment& env, OcdState* s) const noexcept {
    StepIn(u, &env, s);
  }

  Measurement Measure(const State& s, SensorNoiseState* noise = nullptr) const noexcept;

  /// The value OCD's parameter layer holds for `name` in the run of `s` (tests, diagnostics;
  /// throws std::out_of_range for a name OCD does not declare).
  double OcdValue(const OcdState& s, const std::string& name) const;
  /// Every parameter name OCD declares in the run of `s` (tests: that the mapping covers them).
  std::vector<std::string> OcdNames(const OcdState& s) const;

 private:
  void StepIn(const Actuators& u, const Environment* env, OcdState* s) const noexcept;
  double KinematicEngineSpeed(const StateVector& x, int gear) const noexcept;

  params::VehicleParams p_;
  double h_ = 0.001;
  std::vector<OcdParameter> parameters_;
  PerWheel<double> px_{}, py_{}, radius_{}, kb_{};
  PerWheel<double> lmux_{}, lmuy_{};  // the tyre models' mapped friction scalings
  PerWheel<std::string> lmux_name_{}, lmuy_name_{};
  bool curve_grip_ = false;
  double clutch_slip_speed_ = 0.0, engine_inertia_ = 0.0;
  EngineMap engine_;
  GearboxConfig gearbox_;
  SteeringActuator steering_;
  BrakeActuator brakes_;
};

static_assert(PlantModel<OcdVehicle>, "OcdVehicle must satisfy the plant interface");

}  // namespace scw::plant::ocd
