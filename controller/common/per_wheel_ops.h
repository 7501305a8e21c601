// Element-wise arithmetic on PerWheel<double> (wheel order FL, FR, RL, RR; spec Appendix A).
// All functions are constexpr/noexcept and allocation-free; FromFrontRear / FromLeftRight live in
// params/schema/per_wheel.h.
#pragma once

#include <algorithm>
#include <cmath>

#include "params/schema/per_wheel.h"

namespace scw::controller {

using Wheels = PerWheel<double>;

template <class Fn>
constexpr Wheels Map(const Wheels& a, Fn&& fn) noexcept {
  return {fn(a[0]), fn(a[1]), fn(a[2]), fn(a[3])};
}
template <class Fn>
constexpr Wheels Zip(const Wheels& a, const Wheels& b, Fn&& fn) noexcept {
  return {fn(a[0], b[0]), fn(a[1], b[1]), fn(a[2], b[2]), fn(a[3], b[3])};
}

constexpr Wheels Add(const Wheels& a, const Wheels& b) noexcept {
  return Zip(a, b, [](double x, double y) { return x + y; });
}
constexpr Wheels Sub(const Wheels& a, const Wheels& b) noexcept {
  return Zip(a, b, [](double x, double y) { return x - y; });
}
constexpr Wheels Mul(const Wheels& a, const Wheels& b) noexcept {
  return Zip(a, b, [](double x, double y) { return x * y; });
}
constexpr Wheels Scale(const Wheels& a, double k) noexcept {
  return Map(a, [k](double x) { return k * x; });
}
constexpr Wheels Min(const Wheels& a, const Wheels& b) noexcept {
  return Zip(a, b, [](double x, double y) { return std::min(x, y); });
}
constexpr Wheels Max(const Wheels& a, const Wheels& b) noexcept {
  return Zip(a, b, [](double x, double y) { return std::max(x, y); });
}
/// Element-wise clamp to [lo, hi] (lo ≤ hi).
constexpr Wheels Clamp(const Wheels& a, double lo, double hi) noexcept {
  return Map(a, [lo, hi](double x) { return std::clamp(x, lo, hi); });
}
constexpr double MaxElement(const Wheels& a) noexcept {
  return std::max(std::max(a[0], a[1]), std::max(a[2], a[3]));
}
constexpr double MinElement(const Wheels& a) noexcept {
  return std::min(std::min(a[0], a[1]), std::min(a[2], a[3]));
}
inline bool AllFinite(const Wheels& a) noexcept {
  return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]) && std::isfinite(a[3]);
}

}  // namespace scw::controller
