// The maneuver metrics reproduce values worked out by hand on synthetic signals
// (tuning/maneuver/maneuver_metrics.h): beginning and completion of steer, the first yaw-rate peak,
// the yaw-rate ratios, the lateral displacement at 1.07 s, the line fit and the step response.
#include "tuning/maneuver/maneuver_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tuning/maneuver/programs.h"

namespace scw::tuning {
namespace {

std::vector<double> Grid(double t0, double t1, double dt) {
  std::vector<double> t;
  for (long k = 0; t0 + k * dt <= t1 + 1e-12; ++k) t.push_back(t0 + k * dt);
  return t;
}

/// Piecewise linear through (t_i, y_i).
double Piecewise(const std::vector<std::pair<double, double>>& pts, double t) {
  if (t <= pts.front().first) return pts.front().second;
  for (std::size_t i = 1; i < pts.size(); ++i)
    if (t <= pts[i].first) {
      const auto [t0, y0] = pts[i - 1];
      const auto [t1, y1] = pts[i];
      return y0 + (y1 - y0) * (t - t0) / (t1 - t0);
    }
  return pts.back().second;
}

TEST(ManeuverMetrics, InterpolateReachAndReturn) {
  const std::vector<double> t = {0.0, 1.0, 2.0, 3.0};
  const std::vector<double> y = {0.0, 2.0, -2.0, 0.0};
  EXPECT_DOUBLE_EQ(Interpolate(t, y, 0.25), 0.5);
  EXPECT_DOUBLE_EQ(Interpolate(t, y, 1.5), 0.0);
  EXPECT_TRUE(std::isnan(Interpolate(t, y, 3.5)));
  EXPECT_DOUBLE_EQ(FirstReach(t, y, 1.0, 0.0), 0.5);
  // From 1.2 s on, the first sample at or above the level (none before it to interpolate with).
  EXPECT_DOUBLE_EQ(FirstReach(t, y, 1.0, 1.2), 2.0);
  EXPECT_DOUBLE_EQ(ReturnToZero(t, y, 1.0), 1.5);
  EXPECT_TRUE(std::isnan(FirstReach(t, y, 5.0, 0.0)));
}

TEST(ManeuverMetrics, FirstPeakIsTheFirstLocalPeakInTheGivenDirection) {
  const std::vector<double> t = Grid(0.0, 5.0, 0.01);
  std::vector<double> y;
  const std::vector<std::pair<double, double>> pts = {
      {0.0, 0.0}, {0.5, 0.4}, {1.0, 0.0}, {1.5, -0.5}, {2.0, -0.3}, {2.5, -0.8}, {5.0, 0.0}};
  for (double ti : t) y.push_back(Piecewise(pts, ti));
  const Peak p = FirstPeak(t, y, 0.7, -1.0);  // negative direction, from the reversal
  EXPECT_NEAR(p.time, 1.5, 1e-9);
  EXPECT_NEAR(p.value, -0.5, 1e-9);  // the first local peak, not the larger one at 2.5 s
  const Peak q = FirstPeak(t, y, 0.0, 1.0);
  EXPECT_NEAR(q.value, 0.4, 1e-9);
}

TEST(ManeuverMetrics, DisplacementIsTheDoubleIntegralFromBos) {
  // a_y = 2 m/s² from t0 on: ½·2·1.07² = 1.1449 m, whatever the sampling.
  const std::vector<double> t = Grid(0.0, 3.0, 0.01);
  const std::vector<double> ay(t.size(), 2.0);
  EXPECT_NEAR(DoubleIntegral(t, ay, 0.0332, 1.07), 1.1449, 1e-12);
  // a_y = 0 before t0 does not count: a step at 0.5 s seen from 0.5 s.
  std::vector<double> step(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) step[k] = t[k] >= 0.5 - 1e-12 ? 2.0 : 0.0;
  EXPECT_NEAR(DoubleIntegral(t, step, 0.5, 1.07), 1.1449, 1e-12);
  EXPECT_TRUE(std::isnan(DoubleIntegral(t, ay, 2.5, 1.07)));
}

TEST(ManeuverMetrics, SineWithDwellOnSyntheticSignals) {
  // The program itself at 100 Hz (a = 0.05 rad, left first) and a yaw rate drawn by hand.
  const SineWithDwell swd{0.05, 0.7, 0.5};
  const std::vector<double> t = Grid(-0.5, 5.0, 0.01);
  std::vector<double> steer, r, ay;
  const std::vector<std::pair<double, double>> yaw = {{0.0, 0.0},  {0.36, 0.3}, {0.714, 0.0},
                                                      {1.2, -0.5}, {2.5, -0.1}, {3.5, 0.0}};
  for (double ti : t) {
    steer.push_back(swd.At(ti));
    r.push_back(Piecewise(yaw, ti));
    ay.push_back(ti >= 0.0 ? 3.0 : 0.0);
  }
  const double ratio = 12.0;
  const double bos_threshold = 5.0 * M_PI / 180.0 / ratio;
  const SineWithDwellMetrics m = ComputeSineWithDwell(
      t, steer, r, ay, bos_threshold, swd.DwellStart() + swd.dwell, swd.Reversal(), 1.0);
  // BOS: a·sin(2π f t) = 5°/12 → t = asin(0.0072722/0.05) / (2π·0.7) = 0.033186 s.
  EXPECT_NEAR(m.t_bos, std::asin(bos_threshold / 0.05) / (2.0 * M_PI * 0.7), 2e-5);
  EXPECT_NEAR(m.t_bos, 0.033186, 1e-5);
  // COS: the steering returns to zero at 1/f + 0.5 s = 1.928571 s.
  EXPECT_NEAR(m.t_cos, 1.928571, 1e-4);
  // Peak after the reversal: −0.5 rad/s at 1.2 s.
  EXPECT_NEAR(m.peak_yaw_rate, -0.5, 1e-9);
  EXPECT_NEAR(m.t_peak, 1.2, 1e-9);
  // ψ̇(COS + 1.00 = 2.928571) = −0.1 + 0.1·0.428571 = −0.0571429 → 11.43 %;
  // ψ̇(COS + 1.75 = 3.678571) = 0 → 0 %.
  const double r1 = -0.1 + 0.1 * (m.t_cos + 1.0 - 2.5);
  EXPECT_NEAR(m.ratio_1_00, 100.0 * r1 / -0.5, 1e-9);
  EXPECT_NEAR(m.ratio_1_00, 11.43, 0.01);
  EXPECT_NEAR(m.ratio_1_75, 0.0, 1e-12);
  // Constant 3 m/s² from BOS: ½·3·1.07² = 1.71735 m.
  EXPECT_NEAR(m.lateral_displacement, 1.71735, 1e-9);
  // Steered right first: the same numbers with every sign flipped.
  std::vector<double> s2 = steer, r2 = r, a2 = ay;
  for (auto* v : {&s2, &r2, &a2})
    for (double& x : *v) x = -x;
  const SineWithDwellMetrics n = ComputeSineWithDwell(
      t, s2, r2, a2, bos_threshold, swd.DwellStart() + swd.dwell, swd.Reversal(), -1.0);
  EXPECT_DOUBLE_EQ(n.ratio_1_00, m.ratio_1_00);
  EXPECT_DOUBLE_EQ(n.lateral_displacement, m.lateral_displacement);
  EXPECT_DOUBLE_EQ(n.t_cos, m.t_cos);
}

TEST(ManeuverMetrics, LineFitAndTheAngleA) {
  std::vector<double> ay, steer;
  for (int k = 0; k <= 100; ++k) {
    ay.push_back(0.05 * k);                      // 0 .. 5 m/s²
    steer.push_back(0.002 + 0.004 * ay.back());  // δ = 2 mrad + 4 mrad per m/s²
  }
  const LineFit f = FitLine(ay, steer, 0.1 * kStandardGravity, 0.375 * kStandardGravity);
  EXPECT_NEAR(f.slope, 0.004, 1e-12);
  EXPECT_NEAR(f.intercept, 0.002, 1e-12);
  EXPECT_EQ(f.samples, 54);  // 0.98 .. 3.68 m/s² holds 1.00, 1.05, .., 3.65
  EXPECT_NEAR(f.intercept + f.slope * 0.3 * kStandardGravity, 0.002 + 0.004 * 2.941995, 1e-9);
  EXPECT_EQ(FitLine(ay, steer, 10.0, 20.0).samples, 0);
}

TEST(ManeuverMetrics, StepResponseOfKnownSystems) {
  // Steering ramp 0 → 0.02 rad in 0.1 s: half reached at 0.05 s.
  const std::vector<double> t = Grid(-0.2, 6.0, 0.001);
  std::vector<double> steer, first, second;
  const double g = 5.0, tau = 0.1, zeta = 0.5, wn = 10.0, wd = wn * std::sqrt(1.0 - zeta * zeta);
  for (double ti : t) {
    steer.push_back(StepSteer(ti, 0.02, 0.1));
    const double u = ti - 0.05;
    first.push_back(u > 0.0 ? g * 0.02 * (1.0 - std::exp(-u / tau)) : 0.0);
    second.push_back(u > 0.0
                         ? g * 0.02 *
                               (1.0 - std::exp(-zeta * wn * u) *
                                          (std::cos(wd * u) +
                                           zeta / std::sqrt(1.0 - zeta * zeta) * std::sin(wd * u)))
                         : 0.0);
  }
  const StepResponse a = ComputeStepResponse(t, steer, first, 1.0);
  EXPECT_NEAR(a.steady_state, 0.1, 1e-9);
  EXPECT_NEAR(a.gain, 5.0, 1e-7);
  EXPECT_NEAR(a.response_time, tau * std::log(10.0), 1e-5);  // 0.2303 s
  EXPECT_NEAR(a.overshoot_pct, 0.0, 1e-7);
  const StepResponse b = ComputeStepResponse(t, steer, second, 1.0);
  EXPECT_NEAR(b.overshoot_pct, 100.0 * std::exp(-M_PI * zeta / std::sqrt(1 - zeta * zeta)), 1e-3);
  EXPECT_NEAR(b.peak_time, M_PI / wd, 1e-3);  // 0.3628 s
  EXPECT_NEAR(b.gain, 5.0, 1e-6);
  // Negative steering gives the same magnitudes.
  for (double& x : steer) x = -x;
  for (double& x : second) x = -x;
  const StepResponse c = ComputeStepResponse(t, steer, second, 1.0);
  EXPECT_NEAR(c.overshoot_pct, b.overshoot_pct, 1e-9);
  EXPECT_NEAR(c.gain, b.gain, 1e-9);
}

}  // namespace
}  // namespace scw::tuning
