#include "controller/common/low_pass.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace scw::controller {

double PoleFromTimeConstant(double time_constant, double sample_time) noexcept {
  return std::exp(-sample_time / std::max(time_constant, 1e-6));
}

double TimeConstantFromPole(double pole, double sample_time) noexcept {
  if (!(pole > 0.0)) return 0.0;
  if (pole >= 1.0) return std::numeric_limits<double>::infinity();
  return -sample_time / std::log(pole);
}

LowPass::LowPass(double pole) noexcept
    : pole_(std::isnan(pole) ? 0.0 : std::clamp(pole, 0.0, 1.0)) {}

LowPass LowPass::FromTimeConstant(double time_constant, double sample_time) noexcept {
  return LowPass(PoleFromTimeConstant(time_constant, sample_time));
}

}  // namespace scw::controller
