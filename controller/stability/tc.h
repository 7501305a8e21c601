// TC wheel controller (stability-control spec §3.3, §3.5). One object per axle parameter set; one
// State per wheel. ε is the RETAINED fraction of the requested drive force (lower ε → more brake
// pressure on the driven wheel). Slips in percent (λ > 0 driving), pressures in bar, forces in N,
// time t in seconds of SIMULATION time (the reference uses a wall clock, spec §10.2 #10).
//
// Per step (Step):
//  1. Input conditioning: λ_f ← LPF(a_λ)(λ) (a_λ = TC.slip_filter_pole from the first step; the
//     reference starts with pole 0 until its first parameter change, §10.2 #14);
//     λ̇ = (λ_f,new − λ_f,old)/max(T_s, 1e-6). Drive-force-change compensation: if not Inactive and
//     |F| ≥ 1e-6: ε ← clamp(1 − (F_prev/F)·(1 − ε), 0, 1). F_prev ← F (every step).
//  2. r, e as in abs.h with λ_f and the TC thresholds.
//  3. Transition NextTcPhase and its ε action.
//  4. F_out = ε·F; p_TC = k_w·(F − F_out) if F_out ≤ F else 0; p = max(p_in, p_TC);
//     F_out = F and p = p_in if Inactive or F < 0.
//  5. If λ_f ≥ r·λ_hr: t_exceed ← t (starts at −∞: "never").
//
// Predicates: ACT = λ_f ≥ r·λ_hr ∧ allowed ∧ F > 0; DEACT = (t − t_exceed) > T_deact ∨ ¬allowed.
// Transition table (first matching row wins):
//   Inactive: ACT → Hold [kLatch: ε ← ε_R0]; else Inactive
//   Hold:     DEACT → Inactive; λ_f > r·λ_hr ∧ λ̇ > 0 → Reduce [kReduceStep];
//             λ_f ≤ r·λ_hi ∧ λ̇ < 0 → Increase [kIncreaseStep]; else Hold
//   Reduce:   DEACT → Inactive; λ_f ≤ r·λ_hi ∧ λ̇ < 0 → Increase [kIncreaseStep];
//             λ̇ < 0 ∨ λ_f < r·λ_rh → Hold; else Reduce [kReduceStep]
//   Increase: DEACT → Inactive; λ_f > r·λ_hr ∧ λ̇ > 0 → Reduce [kCapToInitial];
//             (λ̇ > 0 ∨ λ_f > r·λ_ih) ∧ λ_f > r·λ_safe → Hold; else Increase [kIncreaseStep]
// ε actions: kReduceStep ε ← clamp(ε − e·Δ_R, 0, 1); kIncreaseStep ε ← clamp(ε + Δ, 0, 1) with
// Δ = e·Δ_I if use_error_in_increase else Δ_I; kCapToInitial ε ← min(ε, ε_R0).
// The reference also stores a latched pressure that it never uses (§10.2 #23); not kept here.
#pragma once

#include <limits>

#include "controller/stability/slip_phase.h"
#include "params/schema/stability_params.h"

namespace scw::controller {

enum class TcAction : std::uint8_t { kNone, kLatch, kReduceStep, kIncreaseStep, kCapToInitial };

struct TcSignals {
  double slip = 0.0;       ///< λ_f (filtered) [%]
  double slip_rate = 0.0;  ///< λ̇ of the filtered slip [%/s]
  double scale = 1.0;      ///< r [–]
  double long_fx = 0.0;    ///< F [N]
  bool allowed = false;
  double time_since_exceed = std::numeric_limits<double>::infinity();  ///< t − t_exceed [s]
};

struct TcTransition {
  SlipPhase next;
  TcAction action;
  bool operator==(const TcTransition&) const = default;
};

bool TcActivate(const TcSignals& s, const params::TcAxleParams& a) noexcept;
bool TcDeactivate(const TcSignals& s, double deactivation_duration) noexcept;

TcTransition NextTcPhase(SlipPhase phase, const TcSignals& s, const params::TcAxleParams& a,
                         double deactivation_duration) noexcept;

double ApplyTcAction(TcAction action, double epsilon, double error, const params::TcAxleParams& a,
                     bool use_error_in_increase) noexcept;

class TcWheelController {
 public:
  struct Input {
    bool allowed = false;
    double slip = 0.0;                ///< distributed, unfiltered TC slip [%]
    double slip_angle_abs = 0.0;      ///< |α̃| [rad]
    double pressure_in = 0.0;         ///< [bar]
    double pressure_per_force = 0.0;  ///< k_w [bar/N] (÷μ, × bias share)
    double long_fx = 0.0;             ///< F [N]
    double t = 0.0;                   ///< simulation time [s]
  };

  struct State {
    SlipPhase phase = SlipPhase::kInactive;
    double epsilon = 0.0;
    double slip_filtered = 0.0;                                  ///< λ_f [%]
    double force_prev = 0.0;                                     ///< F_prev [N]
    double t_exceed = -std::numeric_limits<double>::infinity();  ///< [s]

    /// Every member once (controller/common/state_visit.h).
    template <class Self, class V>
    static void Visit(Self& s, V& v) {
      v.Discrete(s.phase);
      v.Real(s.epsilon);
      v.Real(s.slip_filtered);
      v.Real(s.force_prev);
      v.Time(s.t_exceed);
    }
  };

  struct Output {
    double pressure = 0.0;      ///< [bar]
    double force_target = 0.0;  ///< F_out [N]
    double slip_filtered = 0.0;
  };

  TcWheelController(const params::StabilityParams& p, bool front);

  Output Step(const Input& in, State* s) const noexcept;

  const params::TcAxleParams& axle() const noexcept { return axle_; }

 private:
  params::TcAxleParams axle_;
  double filter_pole_;
  double sample_time_;
  double deactivation_duration_;
  double slip_angle_max_;
  double threshold_reduction_;
  bool use_error_in_increase_;
};

}  // namespace scw::controller
