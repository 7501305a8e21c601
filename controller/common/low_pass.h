// Discrete first-order low-pass filter (stability-control spec §0.2, Appendix A).
//
//   y_k = a·y_{k−1} + (1 − a)·u_k,   pole a ∈ [0, 1]   (a = 0: pass-through, a = 1: frozen)
//
// Two ways to give the filter, because the reference names them confusingly (spec §10.2 #9):
//  * pole form: ESC.tS_psi_dot, ESC.tS_beta, SlipControl.slip_angle_filter_pole,
//    SlipControl.TC.slip_filter_pole are POLES a although some are called "tS";
//  * time-constant form: countersteer_system.slip_angle_filter_Ts and the pure-pursuit
//    curvature_filter_Ts are TIME CONSTANTS T [s]; a = exp(−T_s / max(T, 1e-6)).
// The two are related by τ = −T_s / ln(a) (Appendix B: 0.7 ↔ 28 ms, 0.8 ↔ 45 ms, 0.92 ↔ 120 ms,
// 0.90 ↔ 95 ms at T_s = 0.01 s; T = 0.15 s ↔ a = 0.9355).
//
// The filter object is immutable (holds the pole only); the output y is state owned by the
// caller and also is the filter's memory. Initial outputs are chosen by the caller (Appendix A).
#pragma once

namespace scw::controller {

/// Pole a = exp(−sample_time / max(time_constant, 1e-6)) [–]; sample_time [s], time_constant [s].
double PoleFromTimeConstant(double time_constant, double sample_time) noexcept;

/// Time constant τ = −sample_time / ln(a) [s]; 0 for a ≤ 0, +inf for a ≥ 1.
double TimeConstantFromPole(double pole, double sample_time) noexcept;

class LowPass {
 public:
  /// Pass-through (pole 0).
  constexpr LowPass() = default;
  /// Pole form; the pole is clamped to [0, 1] as the reference does for its pole parameters.
  explicit LowPass(double pole) noexcept;
  /// Time-constant form: T [s] (floored at 1e-6 s) at sample time T_s [s].
  static LowPass FromTimeConstant(double time_constant, double sample_time) noexcept;

  double pole() const noexcept { return pole_; }

  /// Advances the filter by one sample: *y ← a·(*y) + (1 − a)·u; returns the new output.
  double Step(double u, double* y) const noexcept {
    *y = pole_ * *y + (1.0 - pole_) * u;
    return *y;
  }

 private:
  double pole_ = 0.0;
};

}  // namespace scw::controller
