#include "controller/common/tustin_lag.h"

#include <algorithm>

namespace scw::controller {

TustinLag::TustinLag(double time_constant, double sample_time) noexcept
    : time_constant_(std::max(time_constant, 1e-6)), sample_time_(sample_time) {}

double TustinLag::Step(double u, State* s) const noexcept {
  const double two_t = 2.0 * time_constant_;
  const double y = (sample_time_ * (u + s->u_prev) + (two_t - sample_time_) * s->y_prev) /
                   (sample_time_ + two_t);
  s->u_prev = u;
  s->y_prev = y;
  return y;
}

}  // namespace scw::controller
