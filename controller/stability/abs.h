// ABS wheel controller (stability-control spec §3.3, §3.4). One object per axle parameter set;
// one State per wheel. Brake pressures in bar, forces in N (long_fx: drive > 0, braking < 0), slips
// in percent (λ < 0 braking), slip rates in %/s.
//
// Per step, in this order (Step):
//  1. Target reduction rf: 0.9 if Inactive, else with c = −½ρA·c_L, Fz_lat = m·g + c·v_lat²:
//     rf = 0.9·clamp(1 − c·(v_lat² − v_x²)/Fz_lat, 0.33, 1) (rf = 0.9 if |Fz_lat| < 1e-6).
//  2. Threshold scale r = 1 − clamp(|α̃|/max(α_max, 1e-6), 0, 1)·f_red; slip error
//     e = clamp(|(r·λ_hr − λ)/max(|r·λ_hr|, 1e-6)|, 0.1, 1).
//  3. Brake-friction compensation: p_lat ← (μ_prev/μ)·p_lat; μ_prev ← μ (μ_prev starts at 0.3).
//  4. Transition NextAbsPhase (table below) and its ε action ApplyAbsAction.
//  5. F_out = max(ε·rf·F_lat, F); F_out = F if Inactive.
//  6. Safety limiter: push min(F_out, 0), min(F, 0) into two ring buffers of N samples; if
//     mean_out > k_s·mean_in and not Inactive: F_out = min(k_s·F, F_out), safety active.
//  7. Pressure: if ¬esc_active ∨ safety: Δp = k_w·(F_out − rf·F_lat), p = max(rf·p_lat − Δp, 0);
//     else p = max(rf·ε·p_lat, 0); p = p_in when Inactive; finally p = min(p_in, p).
//     k_w [bar/N] = k_axle/μ·b(v) (front) or k_axle/μ·(1 − b(v)) (rear), computed by the caller.
//
// Predicates (comparisons exactly as the reference):
//   ACT   = λ ≤ r·λ_hr ∧ λ̇ < 0 ∧ (F < F_min − 100 ∨ esc_active) ∧ allowed
//   DEACT = (F > F_min ∧ ¬esp_trigger) ∨ (λ > r·λ_hr ∧ esp_trigger) ∨ ¬allowed
// Transition table (first matching row wins):
//   Inactive: ACT → Hold [kLatch: F_lat ← F, p_lat ← p_in, v_lat ← v_x,
//                         esp_trigger ← (F ≥ F_min − 100), ε ← ε_R0]; else Inactive
//   Hold:     DEACT → Inactive; λ < r·λ_hr ∧ λ̇ < 0 → Reduce [kReduceStep];
//             λ > r·λ_hi ∧ λ̇ > 0 → Increase [kEnterIncrease]; else Hold
//   Reduce:   DEACT → Inactive; λ > r·λ_hi ∧ λ̇ > 0 → Increase [kEnterIncrease];
//             λ̇ > 0 ∨ λ > r·λ_rh → Hold; else Reduce [kReduceStep]
//   Increase: DEACT → Inactive; λ < r·λ_hr ∧ λ̇ < 0 → Reduce [kCapToInitial];
//             (λ̇ < 0 ∨ λ < r·λ_ih) ∧ λ < r·λ_safe → Hold;
//             ε > 0.999 ∧ (λ > r·λ_safe ∨ (λ > r·λ_rh ∧ λ̇ > 0)) → Increase [kTargetIncrease];
//             ε > 0.999 → Increase [none]; else Increase [kIncreaseStep]
// ε actions (Δ = e·step if use_error_in_increase else step):
//   kReduceStep ε ← clamp(ε − e·Δ_R, 0, 1); kIncreaseStep ε ← clamp(ε + Δ_I, 0, 1);
//   kEnterIncrease as kIncreaseStep then ε ← max(ε_I0, ε); kCapToInitial ε ← min(ε, ε_R0);
//   kTargetIncrease ε ← ε + Δ_T (no upper clamp: ε may exceed 1); kLatch ε ← ε_R0.
// The reference's "re-latch if ε > 1.001" after kCapToInitial is unreachable (spec §10.2 #7) and is
// therefore not implemented.
#pragma once

#include <cstddef>

#include "controller/common/per_wheel_ops.h"
#include "controller/common/ring_buffer_mean.h"
#include "controller/stability/slip_phase.h"
#include "params/schema/stability_params.h"

namespace scw::controller {

/// Largest SlipControl.ABS.moving_average_fx_window_length the controller accepts (validated at
/// construction): the safety-limiter ring buffers have this fixed capacity (no allocation).
inline constexpr std::size_t kMaxFxWindowLength = 256;

enum class AbsAction : std::uint8_t {
  kNone,
  kLatch,
  kReduceStep,
  kIncreaseStep,
  kEnterIncrease,
  kCapToInitial,
  kTargetIncrease,
};

/// Everything the ABS transition depends on.
struct AbsSignals {
  double slip = 0.0;       ///< λ [%]
  double slip_rate = 0.0;  ///< λ̇ [%/s]
  double scale = 1.0;      ///< r [–]
  double long_fx = 0.0;    ///< F [N]
  bool esc_active = false;
  bool esp_trigger = false;  ///< latched at activation
  bool allowed = false;
  double epsilon = 0.0;  ///< current ε [–]
};

struct AbsTransition {
  SlipPhase next;
  AbsAction action;
  bool operator==(const AbsTransition&) const = default;
};

/// ACT and DEACT predicates (see header comment).
bool AbsActivate(const AbsSignals& s, const params::AbsAxleParams& a,
                 double min_long_force) noexcept;
bool AbsDeactivate(const AbsSignals& s, const params::AbsAxleParams& a,
                   double min_long_force) noexcept;

/// Pure transition function of the table above.
AbsTransition NextAbsPhase(SlipPhase phase, const AbsSignals& s, const params::AbsAxleParams& a,
                           double min_long_force) noexcept;

/// New ε after `action`; `error` is the normalised slip error e.
double ApplyAbsAction(AbsAction action, double epsilon, double error,
                      const params::AbsAxleParams& a, bool use_error_in_increase) noexcept;

/// r = 1 − clamp(|α̃|/max(α_max, 1e-6), 0, 1)·f_red.
double ThresholdScale(double slip_angle_abs, double slip_angle_max, double reduction) noexcept;
/// e = clamp(|(r·λ_hr − λ)/max(|r·λ_hr|, 1e-6)|, 0.1, 1).
double NormalisedSlipError(double slip, double scaled_hold_reduce) noexcept;

class AbsWheelController {
 public:
  struct Input {
    bool allowed = false;
    double slip = 0.0;                ///< λ [%] (distributed ABS slip)
    double slip_angle_abs = 0.0;      ///< |α̃| [rad]
    double slip_rate = 0.0;           ///< λ̇ [%/s]
    double pressure_in = 0.0;         ///< p_in [bar] (ESC output)
    double mu = 0.35;                 ///< pad friction (sanitised) [–]
    double pressure_per_force = 0.0;  ///< k_w [bar/N], already divided by μ and × bias share
    double long_fx = 0.0;             ///< F [N]
    bool esc_active = false;
    double v_x = 0.0;  ///< state-estimate speed [m/s]
  };

  struct State {
    SlipPhase phase = SlipPhase::kInactive;
    double epsilon = 0.0;
    bool esp_trigger = false;
    double f_latched = 0.0;  ///< F_lat [N]
    double p_latched = 0.0;  ///< p_lat [bar]
    double v_latched = 0.0;  ///< v_lat [m/s]
    double mu_prev = 0.3;
    RingBufferMean<kMaxFxWindowLength> force_out_mean;
    RingBufferMean<kMaxFxWindowLength> force_in_mean;

    /// Every member once (controller/common/state_visit.h).
    template <class Self, class V>
    static void Visit(Self& s, V& v) {
      v.Discrete(s.phase);
      v.Real(s.epsilon);
      v.Discrete(s.esp_trigger);
      v.Real(s.f_latched);
      v.Real(s.p_latched);
      v.Real(s.v_latched);
      v.Real(s.mu_prev);
      v.Buffer(s.force_out_mean);
      v.Buffer(s.force_in_mean);
    }
  };

  struct Output {
    double pressure = 0.0;          ///< [bar]
    double force_target = 0.0;      ///< F_out [N]
    double target_reduction = 0.9;  ///< rf [–]
    bool safety_active = false;
  };

  /// Axle parameters plus the shared ABS parameters and vehicle constants of `p`.
  AbsWheelController(const params::StabilityParams& p, bool front);

  Output Step(const Input& in, State* s) const noexcept;

  const params::AbsAxleParams& axle() const noexcept { return axle_; }

 private:
  params::AbsAxleParams axle_;
  double min_long_force_;
  double slip_angle_max_;
  double threshold_reduction_;
  bool use_error_in_increase_;
  std::size_t window_;
  double mass_;
  double downforce_coeff_;  ///< c = −½ρA·c_L [N·s²/m²]
};

}  // namespace scw::controller
