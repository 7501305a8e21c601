#include "plant/powertrain/engine.h"

#include <algorithm>

namespace scw::plant {
namespace {

// Index i and weight t such that x lies in [v[i], v[i+1]] (clamped at the ends).
inline void Bracket(const std::vector<double>& v, double x, std::size_t* i, double* t) noexcept {
  const std::size_t n = v.size();
  if (x <= v.front()) {
    *i = 0;
    *t = 0.0;
    return;
  }
  if (x >= v.back()) {
    *i = n - 2;
    *t = 1.0;
    return;
  }
  const auto it = std::upper_bound(v.begin(), v.end(), x);
  *i = static_cast<std::size_t>(it - v.begin()) - 1;
  *t = (x - v[*i]) / (v[*i + 1] - v[*i]);
}

}  // namespace

EngineMap::EngineMap(const params::EngineParams& p)
    : throttle_(p.map_throttle),
      torque_(p.map_torque),
      limit_(RpmToRadPerSec(p.rev_limit_rpm)),
      inv_band_(1.0 / RpmToRadPerSec(p.rev_limiter_band_rpm)) {
  speed_.reserve(p.map_speed_rpm.size());
  for (double rpm : p.map_speed_rpm) speed_.push_back(RpmToRadPerSec(rpm));
}

double EngineMap::Torque(double omega_e, double throttle) const noexcept {
  throttle = std::clamp(throttle, 0.0, 1.0);
  std::size_t i = 0, j = 0;
  double ti = 0.0, tj = 0.0;
  Bracket(speed_, omega_e, &i, &ti);
  Bracket(throttle_, throttle, &j, &tj);
  const std::size_t cols = throttle_.size();
  const double* r0 = &torque_[i * cols];
  const double* r1 = r0 + cols;
  const double a = r0[j] + tj * (r0[j + 1] - r0[j]);
  const double b = r1[j] + tj * (r1[j + 1] - r1[j]);
  double torque = a + ti * (b - a);
  if (torque > 0.0 && omega_e > limit_)
    torque *= std::max(0.0, 1.0 - (omega_e - limit_) * inv_band_);
  return torque;
}

}  // namespace scw::plant
