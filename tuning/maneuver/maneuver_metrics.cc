#include "tuning/maneuver/maneuver_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace scw::tuning {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Index of the last sample with t_k ≤ tq (t.front() ≤ tq required).
std::size_t Below(const std::vector<double>& t, double tq) {
  const auto it = std::upper_bound(t.begin(), t.end(), tq);
  return static_cast<std::size_t>(it - t.begin()) - 1;
}

}  // namespace

double Interpolate(const std::vector<double>& t, const std::vector<double>& y, double tq) {
  if (t.empty() || !(tq >= t.front()) || !(tq <= t.back())) return kNaN;
  const std::size_t k = Below(t, tq);
  if (k + 1 >= t.size()) return y[k];
  const double u = (tq - t[k]) / (t[k + 1] - t[k]);
  return y[k] + u * (y[k + 1] - y[k]);
}

double FirstReach(const std::vector<double>& t, const std::vector<double>& y, double level,
                  double from) {
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] < from || std::abs(y[k]) < level) continue;
    if (k == 0 || t[k - 1] < from) return t[k];
    const double a = std::abs(y[k - 1]), b = std::abs(y[k]);
    return t[k - 1] + (t[k] - t[k - 1]) * (level - a) / (b - a);
  }
  return kNaN;
}

double ReturnToZero(const std::vector<double>& t, const std::vector<double>& y, double after) {
  for (std::size_t k = 1; k < t.size(); ++k) {
    if (t[k] <= after) continue;
    if (y[k] == 0.0) {
      // Reached between the samples: where the line through the two samples before meets zero
      // (a program that stops at zero is sampled after it got there), within (t_{k−1}, t_k].
      if (k >= 2 && y[k - 1] != 0.0 && t[k - 1] > after) {
        const double slope = (y[k - 1] - y[k - 2]) / (t[k - 1] - t[k - 2]);
        if (slope * y[k - 1] < 0.0) return std::clamp(t[k - 1] - y[k - 1] / slope, t[k - 1], t[k]);
      }
      return t[k];
    }
    if ((y[k - 1] < 0.0 && y[k] > 0.0) || (y[k - 1] > 0.0 && y[k] < 0.0)) {
      const double tz = t[k - 1] + (t[k] - t[k - 1]) * y[k - 1] / (y[k - 1] - y[k]);
      if (tz > after) return tz;
    }
  }
  return kNaN;
}

Peak FirstPeak(const std::vector<double>& t, const std::vector<double>& y, double from,
               double sign) {
  Peak best{kNaN, kNaN};
  double best_v = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] < from) continue;
    const double v = sign * y[k];
    if (v > best_v) {
      best_v = v;
      best = {t[k], y[k]};
    }
    if (v <= 0.0 || k == 0 || k + 1 >= t.size() || t[k - 1] < from) continue;
    if (v >= sign * y[k - 1] && v > sign * y[k + 1]) return {t[k], y[k]};
  }
  return best;
}

double DoubleIntegral(const std::vector<double>& t, const std::vector<double>& y, double t0,
                      double duration) {
  const double t1 = t0 + duration;
  const double y0 = Interpolate(t, y, t0);
  const double y1 = Interpolate(t, y, t1);
  if (std::isnan(y0) || std::isnan(y1)) return kNaN;
  double v = 0.0, d = 0.0, tp = t0, yp = y0;
  auto step = [&](double tn, double yn) {
    const double h = tn - tp;
    const double vn = v + 0.5 * h * (yp + yn);
    d += 0.5 * h * (v + vn);
    v = vn;
    tp = tn;
    yp = yn;
  };
  for (std::size_t k = 0; k < t.size(); ++k)
    if (t[k] > t0 && t[k] < t1) step(t[k], y[k]);
  step(t1, y1);
  return d;
}

LineFit FitLine(const std::vector<double>& x, const std::vector<double>& y, double lo, double hi) {
  double n = 0.0, sx = 0.0, sy = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k)
    if (x[k] >= lo && x[k] <= hi) {
      n += 1.0;
      sx += x[k];
      sy += y[k];
    }
  LineFit f{kNaN, kNaN, static_cast<int>(n)};
  if (n < 2.0) return f;
  const double mx = sx / n, my = sy / n;
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k)
    if (x[k] >= lo && x[k] <= hi) {
      sxx += (x[k] - mx) * (x[k] - mx);
      sxy += (x[k] - mx) * (y[k] - my);
    }
  if (sxx <= 0.0) return f;
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  return f;
}

SineWithDwellMetrics ComputeSineWithDwell(const std::vector<double>& t,
                                          const std::vector<double>& steer,
                                          const std::vector<double>& yaw_rate,
                                          const std::vector<double>& a_y, double bos_threshold,
                                          double dwell_end, double reversal, double direction) {
  SineWithDwellMetrics m;
  m.t_bos = FirstReach(t, steer, bos_threshold, t.empty() ? 0.0 : t.front());
  m.t_cos = ReturnToZero(t, steer, dwell_end);
  const Peak p = FirstPeak(t, yaw_rate, reversal, -direction);
  m.peak_yaw_rate = p.value;
  m.t_peak = p.time;
  m.ratio_1_00 = 100.0 * Interpolate(t, yaw_rate, m.t_cos + 1.0) / m.peak_yaw_rate;
  m.ratio_1_75 = 100.0 * Interpolate(t, yaw_rate, m.t_cos + 1.75) / m.peak_yaw_rate;
  m.lateral_displacement = direction * DoubleIntegral(t, a_y, m.t_bos, 1.07);
  return m;
}

StepResponse ComputeStepResponse(const std::vector<double>& t, const std::vector<double>& steer,
                                 const std::vector<double>& y, double steady_window) {
  StepResponse r;
  if (t.empty()) return {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
  const double final_steer = steer.back();
  const double t50 = FirstReach(t, steer, 0.5 * std::abs(final_steer), t.front());
  double sum = 0.0;
  int n = 0;
  for (std::size_t k = 0; k < t.size(); ++k)
    if (t[k] >= t.back() - steady_window) {
      sum += y[k];
      ++n;
    }
  r.steady_state = n > 0 ? sum / n : kNaN;
  const double s = r.steady_state < 0.0 ? -1.0 : 1.0;
  std::vector<double> sy(y.size());
  for (std::size_t k = 0; k < y.size(); ++k) sy[k] = s * y[k];
  // The first time s·y reaches 0.9 |y_ss| after t_50 (sy is positive there).
  double t90 = kNaN;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] < t50 || sy[k] < 0.9 * std::abs(r.steady_state)) continue;
    t90 = (k == 0 || t[k - 1] < t50)
              ? t[k]
              : t[k - 1] + (t[k] - t[k - 1]) * (0.9 * std::abs(r.steady_state) - sy[k - 1]) /
                               (sy[k] - sy[k - 1]);
    break;
  }
  r.response_time = t90 - t50;
  double best = -std::numeric_limits<double>::infinity(), t_best = kNaN;
  for (std::size_t k = 0; k < t.size(); ++k)
    if (t[k] >= t50 && sy[k] > best) {
      best = sy[k];
      t_best = t[k];
    }
  r.peak = s * best;
  r.peak_time = t_best - t50;
  r.overshoot_pct = 100.0 * (best - std::abs(r.steady_state)) / std::abs(r.steady_state);
  r.gain = r.steady_state / final_steer;
  return r;
}

}  // namespace scw::tuning
