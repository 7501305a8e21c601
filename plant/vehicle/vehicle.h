// Reduced double-track vehicle: the plant the controllers are tuned against.
//
// Contract
// --------
// Axes and signs: ISO 8855 (x forward, y left, z up); yaw rate > 0 = turning left; steering > 0 =
// left; wheel order FL, FR, RL, RR; SI units. Source: spec ../shared/spec/plant-and-track.md §2
// (Open Car Dynamics double track, reduced), §2.3 (MF5.2), §3.1 (powertrain), §9.
//
// Inputs (Actuators, held over one step h):
//   steer_req [rad] road-wheel angle request; brake_pressure_req [bar] per wheel; throttle [0..1].
//   They pass through the actuator models (plant/actuator: delay, lag, rate limit) and the
//   gearbox logic (plant/powertrain) before they act on the body.
//
// Continuous state x (StateIndex, names in kStateNames for CSV headers):
//   x, y [m], psi [rad]         pose of the CoG in the world frame
//   v_x, v_y [m/s], r [rad/s]   body-frame CoG velocity and yaw rate
//   omega_i [rad/s]             wheel spin speeds (spool: omega_RL = omega_RR)
//   kappa_i [-], alpha_i [rad]  relaxed (lagged) tyre slips fed to MF5.2
//   ax_lt, ay_lt [m/s^2]        lagged accelerations that drive the load transfer
//   ax_lt_rate, ay_lt_rate      their rates [m/s^3]: the roll/pitch modes' second state, used only
//                               with chassis.load_transfer_frequency > 0 (else they stay 0)
//
// Equations (h = fixed step, see Step):
//   Body:  v_x' = F_x/m + r v_y,  v_y' = F_y/m - r v_x,  r' = M_z/I_z,
//          x' = v_x cos psi - v_y sin psi,  y' = v_x sin psi + v_y cos psi,  psi' = r,
//          F_x = sum F_x,i - 1/2 rho c_D A u_x|u_x|,  F_y = sum F_y,i + F_y,aero,
//          M_z = sum (p_x,i F_y,i - p_y,i F_x,i) + d_Y F_y,aero with wheel positions
//          p_i = (+-l_f|-l_r, +-b/2).
//   Aero (the car's velocity relative to the air; Environment::wind_x/_y = w, world frame):
//          (w_x, w_y) = R(psi)^T w  (the wind in the body frame),
//          u_x = v_x - w_x,  u_y = v_y - w_y,  |u_r| = sqrt(u_x^2 + u_y^2),
//          drag along the body x-axis from the longitudinal air speed: -1/2 rho c_D A u_x|u_x|
//            (not the vector form -1/2 rho c_D A u_x|u_r|, which would change the still-air drag
//            whenever v_y != 0 and so today's results; the two differ by |u_r|/|u_x| - 1, 4 % in
//            a 15 m/s crosswind at 50 m/s),
//          downforce from the longitudinal air speed: 1/2 rho c_L A u_x^2 (see Loads),
//          side force F_y,aero = -1/2 rho c_Y A (u_y - v_y)|u_r| = 1/2 rho c_Y A w_y |u_r| at the
//            centre of pressure d_Y = aero.side_force_arm ahead of the CoG (yaw moment
//            d_Y F_y,aero). Only the wind's share of u_y counts: the still-air side force of the
//            car's own side slip is left out, as it was before wind existed (~0.1 kN at 50 m/s
//            and 3 deg side slip). So zero wind gives exactly zero side force and the still-air
//            model, and a wind equal to the car's velocity (u_r = 0) gives no aero force at all.
//          In still air u_x = v_x. The side force enters F_y and so the lateral load transfer as
//          if it acted at CoG height.
//   Loads (quasi-static, per-axle downforce, lagged transfer):
//          F_z,i = m g l_{r|f}/(2l) + 1/2 rho c_L,{f|r}A u_x^2 / 2
//                  -+ m ax_lt h/(2l)                 (front loses, rear gains under drive)
//                  -+ e_{f|r} m ay_lt h / b_{f|r}    (left loses, right gains when ay > 0)
//          with e_f = roll_stiffness_share_front, e_r = 1 - e_f, clipped at F_z >= 0 (lift-off);
//          ax_lt' = (F_x/m - ax_lt)/tau_lt, ay_lt' = (F_y/m - ay_lt)/tau_lt. The lag stands in for
//          the roll/pitch modes and removes the algebraic loop load -> force -> acceleration.
//          With chassis.load_transfer_frequency f_n > 0 the modes are second order instead
//          (omega_n = 2 pi f_n, damping ratio zeta = chassis.load_transfer_damping_ratio):
//          ay_lt'' = omega_n^2 (F_y/m - ay_lt) - 2 zeta omega_n ay_lt', the same for ax_lt, so the
//          load transfer overshoots a step in acceleration as a sprung body's does; Step
//          advances the rate first, then the acceleration with the new rate (symplectic Euler).
//   Tyres: wheel-plane velocities (v_x,t, v_y,t) from the body motion rotated by the steer angle
//          (fronts, parallel steer). Kinematic slips
//            kappa_kin = clamp((omega r_e - v_x,t)/max(|v_x,t|, v_k), +-slip_limit),
//            alpha_kin = -atan(v_y,t / max(|v_x,t|, v_a)),
//          relaxed: kappa' = (kappa_kin - kappa)/T_k, T_k = sigma_k / max(|v_x,t|, v_relax),
//          same for alpha with sigma_a. Forces: plant/tire/magic_formula.h with per-wheel
//          lambda_mu = grip.mu * grip.{front|rear}_mu_{x|y} * grip.wheel_mu_{x|y}[i]. Right-side
//          tyres are evaluated mirrored (alpha -> -alpha, F_y -> -F_y) so one set serves both.
//          At standstill the slip floors make the tyres act as stiff dampers: no NaN, no chatter.
//   Wheels: I_i omega_i' = T_drive,i - F_x,t,i r_e - T_fric,i, with the friction torque
//          T_fric = (k_b p_i + c_rr F_z,i r_e) acting against the rotation and never reversing it
//          (Coulomb friction with stiction, solved implicitly in Step). Spool: the rear wheels
//          form one body with inertia 2 I_r + I_e (i_g i_f)^2; LSD: see powertrain/differential.h.
//   Drive: T_axle = T_e(omega_e, throttle) i_g i_f eta; omega_e = omega_rear i_g i_f (engaged
//          gear) or the clutch-slip speed when that is higher (the launch clutch then passes only
//          positive torque and the engine inertia is decoupled); zero during a shift.
//
// Integrator (Step): fixed step h = simulation.time_step, semi-implicit (symplectic) Euler:
//   1. actuators and gearbox advance one step; 2. forces from the current state; 3. velocities and
//   wheel speeds advance explicitly (friction torques implicitly, with stiction), then positions
//   with the new velocities; 4. the relaxation states advance implicitly (backward Euler) towards
//   the kinematic slips of the *new* velocities. This is one tyre evaluation per step, stable for
//   the stiff, lightly damped wheel/tyre mode at low speed, and deterministic. The convergence test
//   (test/plant/vehicle_test.cc) shows that halving h changes lap-relevant quantities < 0.5 %.
//   Derivatives() gives the same right-hand side in continuous form (friction smoothed over
//   +-0.1 rad/s) for linearisation and tests.
//
// Outputs: Measure() -> plant::Measurement (sensors/measurement.h); State::out holds the
//   per-step diagnostics (forces, loads, slips) of the last step.
//
// Ownership: Vehicle is immutable after construction (validated parameters and derived
// constants) and can serve many runs in parallel; the mutable State belongs to the caller.
// Step() is noexcept, allocates nothing and reads no clock. A non-finite state sets
// kStatusNonFinite and freezes the state at its last finite value.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string_view>

#include "params/schema/per_wheel.h"
#include "params/schema/vehicle_params.h"
#include "plant/actuator/actuators.h"
#include "plant/powertrain/differential.h"
#include "plant/powertrain/engine.h"
#include "plant/powertrain/gearbox.h"
#include "plant/sensors/measurement.h"
#include "plant/sensors/sensor_noise.h"
#include "plant/tire/magic_formula.h"
#include "plant/vehicle/environment.h"

namespace scw::plant {

enum StateIndex : int {
  kX = 0,
  kY,
  kPsi,
  kVx,
  kVy,
  kYawRate,
  kOmegaFL,
  kOmegaFR,
  kOmegaRL,
  kOmegaRR,
  kKappaFL,
  kKappaFR,
  kKappaRL,
  kKappaRR,
  kAlphaFL,
  kAlphaFR,
  kAlphaRL,
  kAlphaRR,
  kAxLoadTransfer,
  kAyLoadTransfer,
  kAxLoadTransferRate,
  kAyLoadTransferRate,
  kNumStates
};

/// CSV column names of the continuous state (index = StateIndex).
inline constexpr std::array<std::string_view, kNumStates> kStateNames = {
    "x",        "y",        "psi",        "v_x",       "v_y",      "yaw_rate",
    "omega_fl", "omega_fr", "omega_rl",   "omega_rr",  "kappa_fl", "kappa_fr",
    "kappa_rl", "kappa_rr", "alpha_fl",   "alpha_fr",  "alpha_rl", "alpha_rr",
    "ax_lt",    "ay_lt",    "ax_lt_rate", "ay_lt_rate"};
/// Units of the continuous state (index = StateIndex).
inline constexpr std::array<std::string_view, kNumStates> kStateUnits = {
    "m", "m", "rad", "m/s", "m/s", "rad/s", "rad/s", "rad/s", "rad/s", "rad/s", "-",
    "-", "-", "-",   "rad", "rad", "rad",   "rad",   "m/s^2", "m/s^2", "m/s^3", "m/s^3"};

using StateVector = Eigen::Matrix<double, kNumStates, 1>;

/// Actuator requests, held over one plant step.
struct Actuators {
  double steer_req = 0.0;                 ///< road-wheel angle request [rad], > 0 = left
  PerWheel<double> brake_pressure_req{};  ///< [bar] per wheel, >= 0
  double throttle = 0.0;                  ///< [0..1]
};

/// What acts on the continuous dynamics during a step (actuator and gearbox outputs).
struct PlantInputs {
  double steer = 0.0;                 ///< actual road-wheel angle [rad]
  PerWheel<double> brake_pressure{};  ///< actual calliper pressure [bar]
  double throttle = 0.0;              ///< [0..1]
  int gear = 1;                       ///< engaged gear
  bool torque_cut = false;            ///< shift in progress: no driveline torque
};

/// Per-step diagnostics of the last step (forces evaluated at the start of the step).
struct StepOutputs {
  double a_x = 0.0;  ///< body-frame specific force [m/s^2]
  double a_y = 0.0;
  PerWheel<double> fz{};            ///< vertical loads [N]
  PerWheel<double> fx{};            ///< tyre-frame longitudinal force [N]
  PerWheel<double> fy{};            ///< tyre-frame lateral force [N]
  PerWheel<double> kappa{};         ///< relaxed slip fed to the tyre [-]
  PerWheel<double> alpha{};         ///< relaxed slip angle fed to the tyre [rad]
  PerWheel<double> brake_torque{};  ///< brake torque capacity k_b p [N*m]
  double engine_speed = 0.0;        ///< [rad/s] (after the step)
  double engine_torque = 0.0;       ///< crankshaft torque [N*m]
  double axle_torque = 0.0;         ///< torque into the rear axle [N*m]
};

enum Status : unsigned {
  kStatusOk = 0,
  kStatusNonFinite = 1u << 0,  ///< the state became non-finite; it is frozen at the last value
};

/// Mutable simulation state (owned by the caller; made by Vehicle::MakeState).
struct State {
  double time = 0.0;  ///< [s]
  StateVector x = StateVector::Zero();
  SteeringActuatorState steering;
  BrakeActuatorState brakes;
  GearboxState gearbox;
  double throttle = 0.0;  ///< applied throttle [0..1]
  StepOutputs out;
  unsigned status = kStatusOk;
};

/// The sensors' reading of state `s` (plant/sensors/measurement.h): pose, body velocities, yaw
/// rate, the last step's specific force, wheel speeds, the actuators' actual angle and pressures,
/// gear, engine speed, loads and throttle; with `noise` the sensor noise of `sensors` is added.
/// Every plant measures through it (plant/vehicle/plant_model.h), so they share one sensor model.
Measurement MeasureState(const State& s, const params::SensorParams& sensors,
                         SensorNoiseState* noise) noexcept;

/// Start condition: pose, straight-line speed (wheels rolling freely, gear chosen from speed).
struct InitialCondition {
  double x = 0.0;
  double y = 0.0;
  double psi = 0.0;
  double speed = 0.0;  ///< [m/s] along the heading
};

class Vehicle {
 public:
  /// Validates the parameters (throws scw::ConfigError listing every problem).
  explicit Vehicle(const params::VehicleParams& p);

  const params::VehicleParams& params() const noexcept { return p_; }
  double time_step() const noexcept { return h_; }

  /// A state at rest or rolling straight at ic.speed; sizes the delay buffers (allocates).
  State MakeState(const InitialCondition& ic = {}) const;

  /// Advances the state by one step h on the nominal road in still air. noexcept,
  /// allocation-free, deterministic.
  void Step(const Actuators& u, State* s) const noexcept { StepOn<false>(u, nullptr, s); }
  /// The same on the road and in the wind of `env` (a non-finite or non-positive friction factor
  /// counts as 1, a non-finite wind as still air). The default Environment gives bit for bit the
  /// step above.
  void Step(const Actuators& u, const Environment& env, State* s) const noexcept {
    StepOn<true>(u, &env, s);
  }

  /// Continuous right-hand side x' = f(x, u) of the same model on the nominal road in still air
  /// (friction torques smoothed over |omega| < 0.1 rad/s). For linearisation and tests.
  StateVector Derivatives(const StateVector& x, const PlantInputs& u) const noexcept;

  /// Noise-free measurement of the state; with `noise` (and sensors.noise set) noise is added.
  Measurement Measure(const State& s, SensorNoiseState* noise = nullptr) const noexcept;

  /// Vertical tyre loads [N] for the continuous state x (quasi-static, lagged transfer) in still
  /// air.
  PerWheel<double> WheelLoads(const StateVector& x) const noexcept;

  /// Per-wheel friction scaling (lambda_mu_x, lambda_mu_y) after road, axle and wheel factors.
  const PerWheel<double>& lambda_mu_x() const noexcept { return lambda_x_; }
  const PerWheel<double>& lambda_mu_y() const noexcept { return lambda_y_; }

  /// The tyre model's input of wheel i (the slip angle in the wheel's own sign convention): its
  /// friction scalings times `road`, and with tires.grip_scaling "curve" the same factors on the
  /// slip stiffnesses (a road factor of exactly 1 and "peak" leave the input as without them).
  TireInput WheelTireInput(std::size_t i, double fz, double kappa, double alpha,
                           double road = 1.0) const noexcept {
    TireInput in{fz, kappa, alpha, lambda_x_[i], lambda_y_[i]};
    if (road != 1.0) {
      in.lambda_mu_x *= road;
      in.lambda_mu_y *= road;
    }
    if (curve_grip_) {
      in.stiffness_x = in.lambda_mu_x;
      in.stiffness_y = in.lambda_mu_y;
    }
    return in;
  }

  /// Body-frame offsets of the tyre contact points from the CoG [m] (x forward, y left).
  const PerWheel<double>& contact_x() const noexcept { return px_; }
  const PerWheel<double>& contact_y() const noexcept { return py_; }

  int brake_delay_steps() const noexcept { return brakes_.delay_steps(); }
  int steering_delay_steps() const noexcept { return steering_.delay_steps(); }
  const GearboxConfig& gearbox() const noexcept { return gearbox_; }
  const EngineMap& engine() const noexcept { return engine_; }

 private:
  struct Eval;  // forces and accelerations of one evaluation
  // kEnv false (env unused): the nominal road in still air, compiled without any of the
  // environment's work (friction factors, wind), the same instructions as before it existed.
  template <bool kEnv>
  void StepOn(const Actuators& u, const Environment* env, State* s) const noexcept;
  template <bool kEnv>
  void Evaluate(const StateVector& x, const PlantInputs& u, const Environment* env,
                Eval* e) const noexcept;
  // Wheel loads with the downforce of the longitudinal air speed u_x (air_speed_sq = u_x^2).
  PerWheel<double> Loads(const StateVector& x, double air_speed_sq) const noexcept;
  // c, s: cosine and sine of the road-wheel angle (computed once per evaluation).
  void SlipKinematics(const StateVector& x, double c, double s, PerWheel<double>* kappa,
                      PerWheel<double>* alpha, PerWheel<double>* inv_tau_k,
                      PerWheel<double>* inv_tau_a) const noexcept;
  double KinematicEngineSpeed(const StateVector& x, int gear) const noexcept;

  params::VehicleParams p_;
  double h_ = 0.001;
  // Derived constants.
  double m_ = 0.0, iz_ = 0.0, g_ = 0.0, lf_ = 0.0, lr_ = 0.0, l_ = 0.0, hcg_ = 0.0;
  PerWheel<double> px_{}, py_{}, radius_{}, inertia_{}, kb_{};
  PerWheel<double> fz_static_{}, lambda_x_{}, lambda_y_{};
  TireSet4 tire_set_;        // the front, front, rear, rear coefficient sets for TireForces4
  bool curve_grip_ = false;  // tires.grip_scaling == "curve"
  double share_f_ = 0.5, inv_bf_ = 0.0, inv_br_ = 0.0;
  double drag_k_ = 0.0, lift_kf_ = 0.0, lift_kr_ = 0.0, side_k_ = 0.0;  // 1/2 rho c A
  double side_arm_ = 0.0;  // centre of pressure of the side force ahead of the CoG [m]
  double inv_tau_lt_ = 0.0, lt_gain_ = 1.0;
  // Roll/pitch modes (chassis.load_transfer_frequency > 0): omega_n^2 and 2 zeta omega_n.
  bool lt_second_order_ = false;
  double lt_w2_ = 0.0, lt_2zw_ = 0.0;
  double crr_ = 0.0;
  double clutch_slip_speed_ = 0.0, engine_inertia_ = 0.0;
  EngineMap engine_;
  GearboxConfig gearbox_;
  DifferentialConfig diff_;
  SteeringActuator steering_;
  BrakeActuator brakes_;
};

}  // namespace scw::plant
