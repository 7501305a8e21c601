// Discrete PID with conditional integration and explicit activation flags, as the reference's
// helper behaves (stability-control spec Appendix A, §4.5).
//
// Per step, with input u and the flags below:
//   if update_pd: d ← LPF(a_d)(u)   (a_d = derivative_filter_pole; 0 → d = u)
//                 D = k_d·(d − d_prev)/T_s·use_pd;  d_prev ← d
//   else:         d, d_prev frozen, D = 0
//   P = k_p·d·use_pd
//   if reset_i: I ← 0
//   c = I + k_i·u·T_s·update_i;  if I_min < c < I_max (strict): I ← c   (else I keeps its value:
//                                                                          conditional integration)
//   output = P + I·use_i + D
// The integrator acts on the raw u, P and D on the filtered d. d_prev is updated on every step with
// update_pd, also while use_pd = 0, so there is no derivative kick when the loop is switched on.
// Units: whatever u and the gains are in; the output has the gains' output unit.
#pragma once

#include <limits>

namespace scw::controller {

struct PidGains {
  double kp = 0.0;
  double ki = 0.0;
  double kd = 0.0;
  double integrator_min = -std::numeric_limits<double>::infinity();
  double integrator_max = std::numeric_limits<double>::infinity();
  double sample_time = 0.01;            ///< T_s [s], > 0
  double derivative_filter_pole = 0.0;  ///< pole of the filter on u for P and D (0: none)
};

struct PidFlags {
  bool update_pd = true;
  bool use_pd = true;
  bool update_i = true;
  bool reset_i = false;
  bool use_i = true;

  /// The ESC pattern: update_pd = 1, use_pd = update_i = use_i = active, reset_i = ¬active.
  static constexpr PidFlags Gated(bool active) { return {true, active, active, !active, active}; }
};

struct PidState {
  double filtered = 0.0;       ///< d (filter output)
  double filtered_prev = 0.0;  ///< d of the previous update
  double integrator = 0.0;     ///< I

  /// Every member once (controller/common/state_visit.h).
  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Real(s.filtered);
    v.Real(s.filtered_prev);
    v.Real(s.integrator);
  }
};

class Pid {
 public:
  Pid() = default;
  explicit Pid(const PidGains& gains) noexcept : gains_(gains) {}
  const PidGains& gains() const noexcept { return gains_; }

  double Step(double u, const PidFlags& flags, PidState* s) const noexcept;

 private:
  PidGains gains_{};
};

}  // namespace scw::controller
