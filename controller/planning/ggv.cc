#include "controller/planning/ggv.h"

#include <algorithm>
#include <cmath>

#include "params/schema/field.h"

namespace scw::controller::planning {
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

GgvTable GgvTable::Empty() {
  GgvTable g;
  params::ForEachField(g, [](const std::string&, std::vector<double>& column, const params::Meta&) {
    column.clear();
  });
  return g;
}

GgvTable GgvTable::Constant(double ay, double ax_drive, double ax_brake, double p) {
  GgvTable g;
  g.speed = {0.0};
  g.ay_max = {ay};
  g.ax_drive_max = {ax_drive};
  g.ax_brake_max = {ax_brake};
  g.drive_exponent = {p};
  g.brake_exponent = {p};
  return g;
}

void GgvTable::SetExponent(double p) {
  drive_exponent.assign(speed.size(), p);
  brake_exponent.assign(speed.size(), p);
}

GgvTable GgvTable::Scaled(double factor) const {
  GgvTable g = *this;
  for (double& a : g.ay_max) a *= factor;
  for (double& a : g.ax_drive_max) a *= factor;
  for (double& a : g.ax_brake_max) a *= factor;
  return g;
}

void GgvTable::Validate(const std::string& source) const {
  Problems pr;
  if (speed.empty()) pr.Add("speed", "needs at least one entry");
  for (std::size_t i = 0; i < speed.size(); ++i) {
    if (!std::isfinite(speed[i]) || speed[i] < 0.0)
      pr.Add("speed", "entry " + std::to_string(i) + " must be finite and ≥ 0");
    if (i > 0 && !(speed[i] > speed[i - 1]))
      pr.Add("speed", "must be strictly ascending (entry " + std::to_string(i) + ")");
  }
  auto sized = [&](const std::vector<double>& t, const char* key) {
    if (t.size() == speed.size()) return true;
    pr.Add(key, "needs one value per speed (" + std::to_string(speed.size()) + "), has " +
                    std::to_string(t.size()));
    return false;
  };
  auto check = [&](const std::vector<double>& t, const char* key, bool zero_ok) {
    if (!sized(t, key)) return;
    for (std::size_t i = 0; i < t.size(); ++i)
      if (!std::isfinite(t[i]) || t[i] < 0.0 || (!zero_ok && t[i] == 0.0) || t[i] > 200.0)
        pr.Add(key, "entry " + std::to_string(i) + " = " + params::FormatNumber(t[i]) +
                        (zero_ok ? " must be in [0, 200]" : " must be in (0, 200]"));
  };
  auto check_p = [&](const std::vector<double>& t, const char* key) {
    if (!sized(t, key)) return;
    for (std::size_t i = 0; i < t.size(); ++i)
      if (!(t[i] >= 1.0 && t[i] <= 10.0))
        pr.Add(key, "entry " + std::to_string(i) + " = " + params::FormatNumber(t[i]) +
                        " must be in [1, 10]");
  };
  check(ay_max, "ay_max", false);
  check(ax_drive_max, "ax_drive_max", true);
  check(ax_brake_max, "ax_brake_max", false);
  check_p(drive_exponent, "drive_exponent");
  check_p(brake_exponent, "brake_exponent");
  if (!pr.empty()) throw ConfigError(source, pr.items());
}

double GgvTable::AyMax(double v) const noexcept { return Lookup(speed, ay_max, v); }
double GgvTable::AxDriveMax(double v) const noexcept { return Lookup(speed, ax_drive_max, v); }
double GgvTable::AxBrakeMax(double v) const noexcept { return Lookup(speed, ax_brake_max, v); }
double GgvTable::DriveExponent(double v) const noexcept { return Lookup(speed, drive_exponent, v); }
double GgvTable::BrakeExponent(double v) const noexcept { return Lookup(speed, brake_exponent, v); }

double GgvTable::Combine(double r, double p) noexcept {
  if (!(r > 0.0)) return 1.0;
  if (r >= 1.0) return 0.0;
  if (p == 2.0) return std::sqrt(1.0 - r * r);
  if (p == 1.0) return 1.0 - r;
  return std::pow(1.0 - std::pow(r, p), 1.0 / p);
}

double GgvTable::DriveFactor(double ay_abs, double ay_limit, double v) const noexcept {
  if (!(ay_limit > 0.0)) return 0.0;
  return Combine(ay_abs / ay_limit, DriveExponent(v));
}

double GgvTable::BrakeFactor(double ay_abs, double ay_limit, double v) const noexcept {
  if (!(ay_limit > 0.0)) return 0.0;
  return Combine(ay_abs / ay_limit, BrakeExponent(v));
}

}  // namespace scw::controller::planning
