#include "plant/track/ggv.h"

#include <algorithm>
#include <cmath>

#include "params/schema/field.h"

namespace scw::plant {
namespace {

double Lookup(const std::vector<double>& xs, const std::vector<double>& ys, double x) noexcept {
  if (xs.size() == 1 || x <= xs.front()) return ys.front();
  if (x >= xs.back()) return ys.back();
  const auto it = std::upper_bound(xs.begin(), xs.end(), x);
  const std::size_t i = static_cast<std::size_t>(it - xs.begin()) - 1;
  const double t = (x - xs[i]) / (xs[i + 1] - xs[i]);
  return ys[i] + t * (ys[i + 1] - ys[i]);
}

}  // namespace

GgvLimits GgvLimits::Constant(double ay, double ax_drive, double ax_brake, double p) {
  GgvLimits g;
  g.speed = {0.0};
  g.ay_max = {ay};
  g.ax_drive_max = {ax_drive};
  g.ax_brake_max = {ax_brake};
  g.exponent = p;
  return g;
}

void GgvLimits::Validate(const std::string& source) const {
  Problems pr;
  if (speed.empty()) pr.Add("speed", "needs at least one entry");
  for (std::size_t i = 0; i < speed.size(); ++i) {
    if (!std::isfinite(speed[i]) || speed[i] < 0.0)
      pr.Add("speed", "entry " + std::to_string(i) + " must be finite and ≥ 0");
    if (i > 0 && !(speed[i] > speed[i - 1]))
      pr.Add("speed", "must be strictly ascending (entry " + std::to_string(i) + ")");
  }
  auto check = [&](const std::vector<double>& t, const char* key, bool zero_ok) {
    if (t.size() != speed.size()) {
      pr.Add(key, "needs one value per speed (" + std::to_string(speed.size()) + "), has " +
                      std::to_string(t.size()));
      return;
    }
    for (std::size_t i = 0; i < t.size(); ++i)
      if (!std::isfinite(t[i]) || t[i] < 0.0 || (!zero_ok && t[i] == 0.0) || t[i] > 200.0)
        pr.Add(key, "entry " + std::to_string(i) + " = " + params::FormatNumber(t[i]) +
                        (zero_ok ? " must be in [0, 200]" : " must be in (0, 200]"));
  };
  check(ay_max, "ay_max", false);
  check(ax_drive_max, "ax_drive_max", true);
  check(ax_brake_max, "ax_brake_max", false);
  if (!(exponent >= 1.0 && exponent <= 10.0)) pr.Add("exponent", "must be in [1, 10]");
  if (!pr.empty()) throw ConfigError(source, pr.items());
}

double GgvLimits::AyMax(double v) const noexcept { return Lookup(speed, ay_max, v); }
double GgvLimits::AxDriveMax(double v) const noexcept { return Lookup(speed, ax_drive_max, v); }
double GgvLimits::AxBrakeMax(double v) const noexcept { return Lookup(speed, ax_brake_max, v); }

double GgvLimits::Combine(double ay_abs, double ay_limit) const noexcept {
  if (!(ay_limit > 0.0) || ay_abs >= ay_limit) return 0.0;
  const double r = ay_abs / ay_limit;
  if (exponent == 2.0) return std::sqrt(1.0 - r * r);
  if (exponent == 1.0) return 1.0 - r;
  return std::pow(1.0 - std::pow(r, exponent), 1.0 / exponent);
}

}  // namespace scw::plant
