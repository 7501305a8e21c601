// The composed stability controller: a safety filter between the motion controller and the
// vehicle (stability-control spec §1). It consumes the requested steering, per-wheel brake
// pressures, throttle and gear and returns them modified by ESC (§4), ABS/TC slip control (§3)
// and countersteer (§5).
//
// Per step, in the node's order (§1.3):
//  1. Input sanitising and validity. Essential: t, v_x, v_y, yaw rate, steering request, the four
//     requested pressures and the throttle request must be finite (and plausible: |v| ≤ 200 m/s,
//     |ψ̇| ≤ 50 rad/s). Otherwise the step is a PASS-THROUGH: steering clamped to the steering
//     limits, pressures clamped to [0, ESC.max_brake_pressure], throttle to [0, 1] (non-finite
//     request elements → 0), gear passed, valid = false, state untouched. (The real node publishes
//     nothing then, spec §10.2 #13; a closed loop needs a defined output.) Optional signals that
//     are NaN/inf/implausible count as unavailable.
//     slip_angle_valid = essential inputs present; slip_valid = slip_angle_valid ∧ wheel speeds.
//  2. Slip estimation (slip_estimation.h), δ = measured steering if available else the request;
//     vertical loads from the external Fz if all four are given, else the quasi-static model.
//  3. Pad friction μ_i = interp(T_i; vehicle.brake.friction map) where the brake temperature T_i
//     is available, else vehicle.brake.friction_coeff; sanitised (non-finite → 1e-6, ≥ 1e-6).
//  4. ESC (esc.h) on the requested pressures → p_ESC (always clamped to [0, p_max]).
//  5. Slip control (slip_control.h) on p_ESC with long_fx (0 in release_compat mode) → final
//     pressures and throttle.
//  6. Countersteer (countersteer.h) → final steering (always clamped).
//  7. If any output is non-finite (cannot happen for sanitised inputs; guard only) or the state
//     went non-finite, the step falls back to the pass-through, valid = false, and the state is
//     re-initialised.
// Each subsystem is switched off by its own `enabled` key (ESC.enabled, SlipControl.ABS.enabled,
// SlipControl.TC.enabled, countersteer_system.enabled); the global pressure clamp, the TC throttle
// cut and the steering clamp stay, as on the car.
//
// Units and signs: SI, body frame at the CoG (x forward, y left, ψ̇ > 0 left), steering (tyre
// angle) > 0 left; pressures in bar (suffix _bar), slips in percent, long_fx drive > 0.
// Step is noexcept, allocation-free and uses only the input time stamp t (simulation time) for
// durations (TC deactivation, gear cooldowns, shift window); filters and derivatives assume the
// fixed period tS. Call it once per tS. Thread safety: a controller object is immutable and can be
// shared by any number of threads, each with its own State.
#pragma once

#include <limits>

#include "controller/stability/countersteer.h"
#include "controller/stability/esc.h"
#include "controller/stability/options.h"
#include "controller/stability/slip_control.h"
#include "controller/stability/slip_estimation.h"
#include "params/schema/stability_params.h"

namespace scw::controller {

inline constexpr double kNotAvailable = std::numeric_limits<double>::quiet_NaN();

/// One controller input sample: the signals of the node's topics (spec §1.2) and of a replay log
/// row (issue 10). Optional signals: NaN (the default) = not available.
struct StabilityInput {
  double t = 0.0;              ///< simulation time [s] (durations; must not go backwards)
  double v_x = 0.0;            ///< CoG longitudinal speed, body frame [m/s] (essential)
  double v_y = 0.0;            ///< CoG lateral speed, body frame, > 0 left [m/s] (essential)
  double yaw_rate = 0.0;       ///< [rad/s], > 0 left (essential)
  double a_x = kNotAvailable;  ///< [m/s²] (optional: blend, vertical loads)
  double a_y = kNotAvailable;  ///< [m/s²] (optional: vertical loads)
  double steering_measured = kNotAvailable;  ///< steering report, tyre angle [rad] (optional)
  double steering_request = 0.0;             ///< δ_req [rad] (essential)
  double ay_request = kNotAvailable;         ///< ESC target a_y,req [m/s²] (optional)
  double yaw_rate_request = kNotAvailable;   ///< ESC target ψ̇_req [rad/s] (optional)
  double beta_request = kNotAvailable;       ///< ESC target β_req [rad] (optional)
  PerWheel<double> brake_request_bar{};      ///< requested pressures [bar] (essential)
  double throttle_request = 0.0;             ///< [0..1] (essential)
  int gear_request = 0;                      ///< requested gear (flank: shift window)
  int gear = 0;                              ///< engaged gear (flank: cooldowns; virtual slips)
  double engine_speed = kNotAvailable;       ///< [rad/s] (optional: virtual slips)
  /// Wheel speeds ω [rad/s]; available (slip_valid) only if all four are finite.
  PerWheel<double> wheel_speed{kNotAvailable, kNotAvailable, kNotAvailable, kNotAvailable};
  /// Measured pressures [bar] (optional: reference-speed blend; a NaN wheel counts as 0 bar).
  PerWheel<double> brake_measured_bar{kNotAvailable, kNotAvailable, kNotAvailable, kNotAvailable};
  /// Brake temperatures [°C] (optional, per wheel: μ map, else vehicle.brake.friction_coeff).
  PerWheel<double> brake_temperature_degc{kNotAvailable, kNotAvailable, kNotAvailable,
                                          kNotAvailable};
  /// Requested total longitudinal force [N], drive > 0 (ignored with release_compat; NaN → 0).
  double long_fx = 0.0;
  /// External vertical loads [N]; when all four are finite and ≥ 0 they replace the internal
  /// quasi-static estimate.
  PerWheel<double> fz_external{kNotAvailable, kNotAvailable, kNotAvailable, kNotAvailable};
};

struct StabilityOutput {
  double steering = 0.0;         ///< [rad], within the steering limits
  PerWheel<double> brake_bar{};  ///< [bar], within [0, ESC.max_brake_pressure]
  double throttle = 0.0;         ///< [0..1] (request × throttle cut)
  int gear = 0;                  ///< = gear_request (pass-through)
  bool valid = false;            ///< false: essential input missing → pass-through
  bool slip_angle_valid = false;
  bool slip_valid = false;
  bool esc_active = false;
  bool cs_active = false;
  bool slip_control_active = false;  ///< any ABS or (relevant) TC wheel latched
  PerWheel<SlipPhase> abs_state{};   ///< 0 inactive, 1 reduce, 2 hold, 3 increase
  PerWheel<SlipPhase> tc_state{};
  double yaw_moment = 0.0;        ///< ESC demand M [N·m], > 0 turns left
  double yaw_rate_ref = 0.0;      ///< ESC's yaw-rate reference ψ̇_ref [rad/s] (0 in pass-through)
  PerWheel<double> slip_pct{};    ///< λ [%]
  PerWheel<double> slip_angle{};  ///< α [rad] (with low-speed fade)
  // Diagnostics.
  double v_ref = 0.0;     ///< [m/s]
  PerWheel<double> fz{};  ///< vertical loads used [N]
  PerWheel<double> mu{};  ///< pad friction used [–]
  bool throttle_cut = false;
  bool shift_reduction = false;
  double alpha_front_filtered = 0.0;  ///< countersteer ᾱ_F [rad]
  double alpha_rear_filtered = 0.0;   ///< countersteer ᾱ_R [rad]
  /// How close ESC's activation condition is (EscActivationMargin; > 1: it holds), computed
  /// whether or not ESC is enabled, so a run with ESC off shows it too (0 in pass-through).
  double esc_margin = 0.0;
  /// Its three terms (EscActivationRatios), to tell which one kept ESC off.
  EscActivationTerms esc_margin_terms{};
};

class StabilityController {
 public:
  using Input = StabilityInput;
  using Output = StabilityOutput;

  /// All mutable data of one run. A default-constructed State is the initial state.
  struct State {
    SlipEstimator::State slip{};
    Esc::State esc{};
    SlipControl::State slip_control{};
    Countersteer::State countersteer{};

    /// Every member once (controller/common/state_visit.h): the state guard of step 7 checks
    /// what this lists, so a new state member cannot escape it.
    template <class Self, class V>
    static void Visit(Self& s, V& v) {
      v.Nested(s.slip);
      v.Nested(s.esc);
      v.Nested(s.slip_control);
      v.Nested(s.countersteer);
    }
  };

  /// Validates `p` and `options`; throws scw::ConfigError listing every problem.
  explicit StabilityController(const params::StabilityParams& p,
                               const params::StabilityOptions& options = {});

  Output Step(const Input& in, State* s) const noexcept;

  /// The output of an invalid step (pass-through of the clamped request).
  Output PassThrough(const Input& in) const noexcept;

  const params::StabilityParams& params() const noexcept { return p_; }
  const params::StabilityOptions& options() const noexcept { return options_; }
  double sample_time() const noexcept { return p_.tS; }

 private:
  params::StabilityParams p_;
  params::StabilityOptions options_;
  SlipEstimator slip_estimator_;
  Esc esc_;
  SlipControl slip_control_;
  Countersteer countersteer_;
  bool friction_map_usable_;
};

}  // namespace scw::controller
