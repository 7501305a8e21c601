#include "controller/common/interp.h"

#include <limits>

namespace scw::controller {

double Interp(double x, std::span<const double> xp, std::span<const double> fp) noexcept {
  const std::size_t n = xp.size();
  if (n != fp.size() || n == 0) return std::numeric_limits<double>::quiet_NaN();
  if (n == 1) return fp[0];
  std::size_t i = 0;
  while (i + 2 < n && x > xp[i + 1]) ++i;
  return fp[i] + (x - xp[i]) * (fp[i + 1] - fp[i]) / (xp[i + 1] - xp[i]);
}

}  // namespace scw::controller
