// Quasi-steady double-track evaluation of the plant: which combinations of speed, longitudinal and
// lateral acceleration the car can hold, found algebraically from the plant's own equations (the
// TUM g-g-v idea, plant-and-track spec §6.3, on our reduced double track).
//
// Contract. For a speed v [m/s] (along the body x axis), a longitudinal specific force a_x and a
// lateral specific force a_y [m/s^2] (body frame, as an accelerometer measures them: tyre forces
// plus aero drag over the mass; a_x > 0 accelerates, a_y > 0 turns left), Solve() looks for a
// steady state of the plant (plant/vehicle/vehicle.h) with
//   Σ F_x,body − D(v) = m a_x,   Σ F_y,body = m a_y,   M_z = 0,   r = a_y / v,
// where the tyre forces come from the plant's MF5.2 combined-slip tyres (plant/tire) at the
// plant's quasi-static wheel loads (aero downforce, longitudinal and lateral load transfer with the
// roll-stiffness split, evaluated at a_x and a_y), with slips from the plant's wheel kinematics
// (relaxation settled). Unknowns: the lateral velocity v_y, the road-wheel angle δ and the
// longitudinal actuation, which follows the car's hardware:
//   driving (the tyres must deliver more than the rolling resistance): front wheels roll freely
//     (F_x = −c_rr F_z); the rear axle drives through the plant's differential: a spool makes both
//     rear wheels turn at one speed, an LSD splits the axle torque with the plant's locking torque
//     (plant/powertrain/differential.h) at the wheels' speed difference (both wheel speeds are
//     solved for); the axle torque must not exceed the engine's full-load torque in the
//     best gear at v (rev limit respected);
//   braking: one pressure per axle, the force split front/rear by `brake_bias_front` (the
//     longitudinal controller's bias, controller/motion/longitudinal.h), so each wheel of an axle
//     carries the same brake force; a wheel whose force exceeds what its tyre gives at its slip
//     angle locks (infeasible).
// The axle lateral forces follow from the force and moment balance (including the yaw moment of
// left/right longitudinal force differences); the rear axle slip angle and δ are the first (lowest)
// solutions below each axle's peak. A state is infeasible when an axle or a wheel would have to
// exceed its tyre's peak, or the engine's torque; δ beyond the steering lock is reported separately
// (`steer_limited`), as the g-g-v simulation does.
//
// Limits: MaxLateral(v) is the largest a_y with a_x = 0 (holding speed, drag included; above the
// top speed at the smallest deceleration the car can hold);
// MaxDrive(v, a_y) and MaxBrake(v, a_y) the largest a_x and −a_x at a given a_y (bisection over
// feasibility, relative precision 1e-3). UndersteerGradient(v) is dδ/da_y − l/v² at small a_y
// [rad/(m/s^2)] (finite difference of two solved states, a_y = 0.5 and 1.5 m/s^2).
// Deterministic, allocation-free after construction, thread-safe (const).
#pragma once

#include "params/schema/per_wheel.h"
#include "params/schema/vehicle_params.h"
#include "plant/powertrain/differential.h"
#include "plant/vehicle/vehicle.h"

namespace scw::plant {

struct QuasiSteadyOptions {
  double brake_bias_front = 0.58;  ///< front share of the braking force [-]
  /// Steering-lock bound: if true, a state needing |δ| above the lock counts as infeasible.
  bool respect_steering_lock = true;
};

struct QuasiSteadyState {
  bool feasible = false;
  bool steer_limited = false;  ///< would need more than the steering lock
  double v_y = 0.0;            ///< [m/s]
  double steer = 0.0;          ///< road-wheel angle [rad]
  double axle_torque = 0.0;    ///< driving torque into the rear axle [N*m] (≥ 0)
  double brake_force = 0.0;    ///< total brake force [N] (≥ 0)
  PerWheel<double> fz{}, kappa{}, alpha{}, fx{}, fy{};  ///< tyre frame, as StepOutputs
  /// Use of each tyre's pure-slip friction: |F| / (μ F_z) with μ = max(μx, μy) at its load [-].
  PerWheel<double> usage{};
};

class QuasiSteadyModel {
 public:
  explicit QuasiSteadyModel(const params::VehicleParams& p, const QuasiSteadyOptions& o = {});

  QuasiSteadyState Solve(double v, double a_x, double a_y) const noexcept;
  double MaxLateral(double v) const noexcept;
  /// 0 if the car can hold speed v on a straight, else (above its top speed) the coasting
  /// deceleration from drag and rolling resistance [m/s^2].
  double MinDeceleration(double v) const noexcept;
  double MaxDrive(double v, double a_y) const noexcept;
  double MaxBrake(double v, double a_y) const noexcept;
  double UndersteerGradient(double v) const noexcept;

  /// Aero drag plus rolling resistance (with downforce) on a straight at v [N].
  double RoadLoad(double v) const noexcept;
  /// Largest driving force at the rear wheels from the engine at v [N] (best gear, full load).
  double MaxEngineForce(double v) const noexcept;
  const Vehicle& vehicle() const noexcept { return veh_; }

 private:
  struct Work;
  bool SolveWheelFx(std::size_t i, double fz, double alpha, double vxt, double fx_target,
                    double* kappa) const noexcept;
  double TireFy(std::size_t i, double fz, double kappa, double alpha) const noexcept;
  double TireFx(std::size_t i, double fz, double kappa, double alpha) const noexcept;

  Vehicle veh_;
  QuasiSteadyOptions o_;
  DifferentialConfig diff_;
  double m_, lf_, lr_, l_, drag_k_, crr_;
  PerWheel<double> px_{}, py_{}, radius_{};
};

}  // namespace scw::plant
