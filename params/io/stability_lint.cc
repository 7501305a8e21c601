#include "params/io/stability_lint.h"

#include <algorithm>
#include <cmath>

namespace scw::params {
namespace {

// Piecewise-linear through (xs, ys), end segments extended (the car's interpolation).
double Extrapolated(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
  const std::size_t n = xs.size();
  std::size_t i = 0;
  while (i + 2 < n && x > xs[i + 1]) ++i;
  const double t = (x - xs[i]) / (xs[i + 1] - xs[i]);
  return ys[i] + t * (ys[i + 1] - ys[i]);
}

void CheckSchedule(const std::string& key, const std::vector<double>& xs,
                   const std::vector<double>& ys, const LintOptions& o, bool must_be_positive,
                   std::vector<Problem>* out) {
  if (xs.size() < 2 || xs.size() != ys.size()) return;
  const double top = *std::max_element(ys.begin(), ys.end());
  double first_nonpos = NAN, worst = -HUGE_VAL, worst_v = 0;
  for (double v = o.v_min; v <= o.v_max + 1e-9; v += 0.5) {
    const double y = Extrapolated(xs, ys, v);
    if (must_be_positive && y <= 0 && std::isnan(first_nonpos)) first_nonpos = v;
    if (y > worst) worst = y, worst_v = v;
  }
  if (!std::isnan(first_nonpos))
    out->push_back({key, "extrapolates to a value <= 0 from " + FormatNumber(first_nonpos) +
                             " m/s on (the car extends the outer segments linearly): the "
                             "condition |x| > threshold is then always true"});
  if (top > 0 && worst > o.growth * top)
    out->push_back({key, "extrapolates to " + FormatNumber(worst) + " at " + FormatNumber(worst_v) +
                             " m/s, more than " + FormatNumber(o.growth) +
                             "x its largest breakpoint value " + FormatNumber(top)});
}

}  // namespace

double ScheduledMinimum(const StabilityParams& p, const std::string& key, const LintOptions& o) {
  const auto& e = p.ESC;
  const std::vector<double>* ys = nullptr;
  if (key == "ESC.beta_threshold_activate") ys = &e.beta_threshold_activate;
  if (key == "ESC.psi_dot_error_threshold_activate") ys = &e.psi_dot_error_threshold_activate;
  if (key == "ESC.beta_error_threshold_activate") ys = &e.beta_error_threshold_activate;
  const auto& xs = e.threshold_velocities;
  if (!ys || ys->size() != xs.size() || xs.size() < 2) return NAN;
  const double lo = std::max(o.v_min, e.min_activation_velocity), hi = o.v_max;
  if (!(lo <= hi)) return NAN;
  // A piecewise-linear function takes its minimum over [lo, hi] at an end or a breakpoint.
  double m = std::min(Extrapolated(xs, *ys, lo), Extrapolated(xs, *ys, hi));
  for (std::size_t i = 0; i < xs.size(); ++i)
    if (xs[i] > lo && xs[i] < hi) m = std::min(m, (*ys)[i]);
  return m > 0 && std::isfinite(m) ? m : NAN;
}

std::vector<Problem> LintStability(const StabilityParams& p, const LintOptions& o) {
  std::vector<Problem> out;
  const auto& e = p.ESC;
  CheckSchedule("ESC.beta_threshold_activate", e.threshold_velocities, e.beta_threshold_activate, o,
                true, &out);
  CheckSchedule("ESC.psi_dot_error_threshold_activate", e.threshold_velocities,
                e.psi_dot_error_threshold_activate, o, true, &out);
  CheckSchedule("ESC.beta_error_threshold_activate", e.threshold_velocities,
                e.beta_error_threshold_activate, o, true, &out);
  // Brake bias b(v) = clamp(bias + shift(v), 0, 1).
  const auto& s = p.brake_bias_shift;
  if (s.values.size() >= 2 && s.values.size() == s.vel_interp_mps.size()) {
    for (double v = o.v_min; v <= o.v_max + 1e-9; v += 0.5) {
      const double b = p.P_VDC_brake_bias_front + Extrapolated(s.vel_interp_mps, s.values, v);
      if (b <= 0.0 || b >= 1.0) {
        out.push_back({"brake_bias_shift.values",
                       "brake bias with the extrapolated shift reaches " + FormatNumber(b) +
                           " at " + FormatNumber(v) + " m/s and is clamped to [0, 1]"});
        break;
      }
    }
  }
  // Inverted hysteresis: deactivation threshold at or above the activation threshold.
  auto hysteresis = [&](const std::string& key, const std::vector<double>& act, double deact) {
    if (act.size() != e.threshold_velocities.size() || act.size() < 2) return;
    for (double v = std::max(o.v_min, e.min_activation_velocity); v <= o.v_max + 1e-9; v += 0.5)
      if (deact >= Extrapolated(e.threshold_velocities, act, v)) {
        out.push_back({key, "deactivation threshold " + FormatNumber(deact) +
                                " is at or above the activation threshold from " + FormatNumber(v) +
                                " m/s on (inverted hysteresis)"});
        return;
      }
  };
  hysteresis("ESC.beta_threshold_deactivate", e.beta_threshold_activate,
             e.beta_threshold_deactivate);
  hysteresis("ESC.psi_dot_error_threshold_deactivate", e.psi_dot_error_threshold_activate,
             e.psi_dot_error_threshold_deactivate);
  hysteresis("ESC.beta_error_threshold_deactivate", e.beta_error_threshold_activate,
             e.beta_error_threshold_deactivate);
  return out;
}

}  // namespace scw::params
