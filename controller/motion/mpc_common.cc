#include "controller/motion/mpc_common.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace scw::controller::motion {
namespace {

double Table(const std::vector<double>& x, const std::vector<double>& y, double v) noexcept {
  if (v <= x.front()) return y.front();
  if (v >= x.back()) return y.back();
  const auto it = std::upper_bound(x.begin(), x.end(), v);
  const std::size_t i = static_cast<std::size_t>(it - x.begin());
  const double w = (v - x[i - 1]) / (x[i] - x[i - 1]);
  return y[i - 1] + w * (y[i] - y[i - 1]);
}

}  // namespace

void GgTable::Validate() const {
  const std::size_t n = speed.size();
  if (n == 0 || ay_max.size() != n || ax_drive_max.size() != n || ax_brake_max.size() != n)
    throw std::invalid_argument(
        "g-g table: speed, ay_max, ax_drive_max, ax_brake_max need the "
        "same non-zero length");
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0 && !(speed[i] > speed[i - 1]))
      throw std::invalid_argument("g-g table: speeds must be strictly ascending");
    if (!(ay_max[i] > 0.0) || !(ax_drive_max[i] >= 0.0) || !(ax_brake_max[i] > 0.0) ||
        !std::isfinite(ay_max[i] + ax_drive_max[i] + ax_brake_max[i]))
      throw std::invalid_argument("g-g table: limits must be finite, ay/brake > 0, drive >= 0");
  }
  if (!(exponent >= 1.0 && exponent <= 10.0))
    throw std::invalid_argument("g-g table: exponent must lie in [1, 10]");
}

double GgTable::AyMax(double v) const noexcept { return Table(speed, ay_max, v); }
double GgTable::AxDriveMax(double v) const noexcept { return Table(speed, ax_drive_max, v); }
double GgTable::AxBrakeMax(double v) const noexcept { return Table(speed, ax_brake_max, v); }

double GgTable::Combine(double ay_abs, double v) const noexcept {
  const double r = std::clamp(ay_abs / AyMax(v), 0.0, 1.0);
  return std::pow(std::max(0.0, 1.0 - std::pow(r, exponent)), 1.0 / exponent);
}

double InterpolateStations(const Path& path, const std::vector<double>& values, double s) noexcept {
  const auto& pts = path.points();
  const std::size_t n = pts.size();
  if (values.size() != n || n == 0) return 0.0;
  s = path.Wrap(s);
  const auto it = std::upper_bound(pts.begin(), pts.end(), s,
                                   [](double a, const PathPoint& p) { return a < p.s; });
  const std::size_t i = it == pts.begin() ? 0 : static_cast<std::size_t>(it - pts.begin()) - 1;
  const std::size_t j = i + 1 < n ? i + 1 : 0;
  const double s1 = i + 1 < n ? pts[j].s : path.length();
  const double w = s1 > pts[i].s ? std::clamp((s - pts[i].s) / (s1 - pts[i].s), 0.0, 1.0) : 0.0;
  return values[i] + w * (values[j] - values[i]);
}

void SolveStats::Add(double seconds) noexcept {
  if (!times_.empty())
    times_[static_cast<std::size_t>(count_ % static_cast<std::int64_t>(times_.size()))] = seconds;
  ++count_;
  max_ = std::max(max_, seconds);
  sum_ += seconds;
}

double SolveStats::Quantile(double q) const {
  const std::size_t n =
      static_cast<std::size_t>(std::min<std::int64_t>(count_, std::ssize(times_)));
  if (n == 0) return 0.0;
  std::vector<double> v(times_.begin(), times_.begin() + static_cast<std::ptrdiff_t>(n));
  const std::size_t k =
      std::min(n - 1, static_cast<std::size_t>(std::clamp(q, 0.0, 1.0) * static_cast<double>(n)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

double SolveStats::Median() const { return Quantile(0.5); }

}  // namespace scw::controller::motion
