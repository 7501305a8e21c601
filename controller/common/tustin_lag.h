// First-order lag discretised with the Tustin (bilinear) transform (spec Appendix A, used by the
// pure-pursuit velocity-error filter §6.1):
//
//   G(s) = 1/(T·s + 1)  →  y_k = [T_s·(u_k + u_{k−1}) + (2T − T_s)·y_{k−1}] / (T_s + 2T)
//
// T [s] is floored at 1e-6; T_s [s] > 0. Zero initial states (State{}).
#pragma once

namespace scw::controller {

class TustinLag {
 public:
  struct State {
    double u_prev = 0.0;
    double y_prev = 0.0;
  };

  TustinLag(double time_constant, double sample_time) noexcept;
  double Step(double u, State* s) const noexcept;
  double time_constant() const noexcept { return time_constant_; }

 private:
  double time_constant_;
  double sample_time_;
};

}  // namespace scw::controller
