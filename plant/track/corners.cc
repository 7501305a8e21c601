#include "plant/track/corners.h"

#include <cmath>

namespace scw::plant {

std::vector<Corner> FindCorners(const Track& t) {
  constexpr double kOn = 1.0 / 250.0;  // [1/m] radius below 250 m
  constexpr double kMaxGap = 20.0;     // [m] straighter stretch a corner may contain
  std::vector<Corner> out;
  const auto& kappa = t.curvature();
  const std::size_t n = t.size();
  std::size_t start = 0;
  while (start < n && std::abs(kappa[start]) > kOn) ++start;
  if (start == n) return out;  // curved everywhere: no place to begin
  std::size_t i = 0;
  while (i < n) {
    const std::size_t a = (start + i) % n;
    if (std::abs(kappa[a]) <= kOn) {
      ++i;
      continue;
    }
    const double sign = kappa[a] > 0 ? 1.0 : -1.0;
    std::size_t j = i, last = i;
    double kmax = 0.0, s_apex = 0.0;
    while (j < n) {
      const std::size_t b = (start + j) % n;
      const double k = kappa[b] * sign;
      if (k > kOn) {
        last = j;
        if (k > kmax) {
          kmax = k;
          s_apex = t.s()[b];
        }
      } else if (static_cast<double>(j - last) * t.step() > kMaxGap) {
        break;
      }
      ++j;
    }
    Corner c;
    c.number = static_cast<int>(out.size()) + 1;
    c.left = sign > 0;
    c.s_from = t.s()[(start + i) % n];
    c.s_to = t.s()[(start + last) % n];
    c.min_radius = 1.0 / kmax;
    c.s_apex = s_apex;
    out.push_back(c);
    i = last + 1;
  }
  return out;
}

double CornerLength(const Corner& c, const Track& t) {
  double d = std::fmod(c.s_to - c.s_from, t.length());
  if (d < 0.0) d += t.length();
  return d + t.step();
}

bool IsShortCorner(const Corner& c, const Track& t) {
  return CornerLength(c, t) < kShortCornerLength;
}

}  // namespace scw::plant
