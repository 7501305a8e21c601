// Slip control: input conditioning, ABS and TC wheel controllers, output selection, gear-shift
// pressure reduction and throttle cut (stability-control spec §3.1, §3.2, §3.6–§3.8).
//
// Inputs (SlipControl::Input): per-wheel slips λ and virtual slips λ_virt [%], vertical loads Fz
// [N], slip angles α [rad] (all from slip estimation), slip_valid, the ESC output pressures p_ESC
// [bar] (the ABS/TC input, spec §1.3 step 8), sanitised pad friction μ, long_fx F [N] (drive > 0,
// braking < 0; 0 in release_compat mode), esc_active, state-estimate v_x [m/s], simulation time t
// [s], engaged gear and gear request (ints) and the throttle request [0..1].
//
// Per step:
//  1. λ̇_raw,i = (λ_i − λ_prev,i)/max(T_s, 1e-6) [%/s]; |α̃_i| = |LPF(slip_angle_filter_pole)(α_i)|.
//  2. Source slips (SelectSlipSource, table of §3.1 step 4; ABS picks the smaller slip, TC the
//     larger; per-axle load weighting λ_w = Σ Fz·λ / Σ Fz when Σ Fz > 1e-6; ties → right wheel).
//  3. Distribution by operation mode (DistributeSlips, SlipOperationMode; parameter values 0
//     individual, 1 axle split, 2 all together, 3 rear only; out-of-range → code default ABS 1 /
//     TC 3).
//  4. Gear flanks: a change of the engaged gear stamps t_gear, of the request t_req (detectors
//     start at 0, spec §10.2 #24, unless options.ignore_initial_gear_change).
//     ABS allowed = ABS.enabled ∧ slip_valid ∧ v_x > ABS.min_activation_velocity; rears also need
//     (t − t_gear) > ABS.activation_time_after_gearshift ∨ RL/RR ABS active (previous step).
//     TC allowed = TC.enabled ∧ slip_valid ∧ v_x > TC.min_activation_velocity; fronts also need
//     mode ≠ rear_only; rears (t − t_gear) > TC.activation_time_after_gearshift ∨ RL/RR TC active.
//  5. Four ABS wheels, then four TC wheels (FL→RR). Per-wheel pressure factor k_w = k_axle/μ_i·b(v)
//     (front) or k_axle/μ_i·(1 − b(v)) (rear), vehicle_model.h.
//  6. Selection (first match): abs_latched ∧ F < 0 ∧ ¬esc → ABS outputs (all four);
//     tc_latched ∧ F > 0 ∧ ¬esc → TC outputs (all four); esc → ABS outputs if abs_latched else
//     p_ESC, then rears from TC if tc_latched; otherwise p_ESC. tc_latched counts rear wheels only
//     in rear_only mode.
//  7. Gear shift: t_ms = ⌊(t − t_req)·1000⌋ (1 ns tolerance for float time stamps); if
//     T_init < t_ms < T_init + T_red (ms, strict) rears × clamp(reduction_factor, 0, 1).
//  8. Throttle cut: if slip_valid, throttle_out = throttle·[max_i λ_TC,i ≤ max_slip_throttle_cut]
//     with the distributed unfiltered TC slips (independent of TC.enabled and F).
// slip_control_active = abs_latched ∨ tc_latched (ESC not included).
#pragma once

#include "controller/common/per_wheel_ops.h"
#include "controller/stability/abs.h"
#include "controller/stability/tc.h"
#include "params/schema/stability_options.h"
#include "params/schema/stability_params.h"

namespace scw::controller {

/// Slip, |filtered slip angle| and slip rate per wheel as handed to the wheel controllers.
struct WheelSlipSignals {
  Wheels slip{};            ///< [%]
  Wheels slip_angle_abs{};  ///< [rad]
  Wheels slip_rate{};       ///< [%/s]
};

/// ABS selects the smaller (more negative) slip, TC the larger.
enum class SlipSelector : std::uint8_t { kMin, kMax };

/// Slip distribution of ABS or TC (§3.1 step 6). The integer values are those of the car's
/// `operation_mode` parameter, the only place the integer form is used.
enum class SlipOperationMode : std::uint8_t {
  kIndividual = 0,   ///< each wheel its own slip
  kAxleSplit = 1,    ///< the selected wheel of each axle for both wheels of the axle
  kAllTogether = 2,  ///< the selected wheel of the car for all four
  kRearOnly = 3,     ///< rear axle as one unit, fronts neutralised
};

/// The `operation_mode` parameter; a value outside 0..3 gives `fallback` (the node's code
/// defaults: ABS kAxleSplit, TC kRearOnly).
constexpr SlipOperationMode SlipOperationModeFromInt(int mode, SlipOperationMode fallback) {
  return (mode >= 0 && mode <= 3) ? static_cast<SlipOperationMode>(mode) : fallback;
}
constexpr int ToInt(SlipOperationMode m) { return static_cast<int>(m); }

/// §3.1 step 4/5 table. `slip_rate` is the raw rate of the raw slips.
WheelSlipSignals SelectSlipSource(SlipSelector selector, bool use_virtual_slips, bool load_weighted,
                                  const Wheels& slip, const Wheels& virtual_slip, const Wheels& fz,
                                  const Wheels& slip_rate, const Wheels& slip_angle_abs) noexcept;

/// §3.1 step 6.
WheelSlipSignals DistributeSlips(SlipOperationMode mode, SlipSelector selector,
                                 const WheelSlipSignals& source) noexcept;

class SlipControl {
 public:
  struct Input {
    Wheels slip_pct{};
    Wheels virtual_slip_pct{};
    Wheels fz{};
    Wheels slip_angle{};
    bool slip_valid = false;
    Wheels pressure_in{};  ///< p_ESC [bar]
    Wheels mu{0.35, 0.35, 0.35, 0.35};
    double long_fx = 0.0;
    bool esc_active = false;
    double v_x = 0.0;
    double t = 0.0;
    int gear = 0;
    int gear_request = 0;
    double throttle = 0.0;
  };

  struct Output {
    Wheels pressure{};  ///< [bar]
    double throttle = 0.0;
    PerWheel<SlipPhase> abs_phase{};
    PerWheel<SlipPhase> tc_phase{};
    bool abs_latched = false;
    bool tc_latched = false;
    bool active = false;  ///< slip_control_active
    bool throttle_cut = false;
    bool shift_reduction = false;
    WheelSlipSignals abs_input{};  ///< distributed ABS signals
    WheelSlipSignals tc_input{};   ///< distributed TC signals (unfiltered slips)
    Wheels abs_pressure{};
    Wheels tc_pressure{};
  };

  struct State {
    Wheels prev_slip{};
    Wheels slip_angle_filtered{};
    PerWheel<AbsWheelController::State> abs{};
    PerWheel<TcWheelController::State> tc{};
    int gear_seen = 0;
    int gear_request_seen = 0;
    bool gear_initialised = false;
    double t_gear = -std::numeric_limits<double>::infinity();
    double t_gear_request = -std::numeric_limits<double>::infinity();

    /// Every member once (controller/common/state_visit.h).
    template <class Self, class V>
    static void Visit(Self& s, V& v) {
      v.Reals(s.prev_slip);
      v.Reals(s.slip_angle_filtered);
      v.NestedEach(s.abs);
      v.NestedEach(s.tc);
      v.Discrete(s.gear_seen);
      v.Discrete(s.gear_request_seen);
      v.Discrete(s.gear_initialised);
      v.Time(s.t_gear);
      v.Time(s.t_gear_request);
    }
  };

  /// Throws ConfigError if `p` or `options` is invalid or the ABS window exceeds
  /// kMaxFxWindowLength.
  explicit SlipControl(const params::StabilityParams& p,
                       const params::StabilityOptions& options = {});

  Output Step(const Input& in, State* s) const noexcept;

  SlipOperationMode abs_mode() const noexcept { return abs_mode_; }
  SlipOperationMode tc_mode() const noexcept { return tc_mode_; }

 private:
  params::StabilityParams p_;
  params::StabilityOptions options_;
  SlipOperationMode abs_mode_;
  SlipOperationMode tc_mode_;
  double sample_time_;
  double k_axle_front_;
  double k_axle_rear_;
  AbsWheelController abs_front_;
  AbsWheelController abs_rear_;
  TcWheelController tc_front_;
  TcWheelController tc_rear_;
};

}  // namespace scw::controller
