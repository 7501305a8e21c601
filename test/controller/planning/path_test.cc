#include "controller/planning/path.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "params/schema/field.h"

namespace scw::controller::planning {
namespace {

// Counter-clockwise circle of radius r around the origin, starting at (r, 0).
Path Circle(double r, int n, double v = 30.0) {
  std::vector<PathPoint> pts;
  const double len = 2 * M_PI * r;
  for (int i = 0; i < n; ++i) {
    const double s = len * i / n, th = s / r;
    pts.push_back({s, r * std::cos(th), r * std::sin(th), th + M_PI / 2, 1.0 / r, v, 0.0});
  }
  return Path(pts, len);
}

TEST(PathTest, ProjectionOfPointsOnAndBesideTheLine) {
  const Path p = Circle(100.0, 400);
  for (double th : {0.1, 1.0, 3.0, 6.0}) {
    const auto on = p.Project(100 * std::cos(th), 100 * std::sin(th), th + M_PI / 2);
    EXPECT_NEAR(on.s, 100 * th, 0.05);
    EXPECT_NEAR(on.lateral_error, 0.0, 0.02);
    EXPECT_NEAR(on.heading_error, 0.0, 1e-6);
    // Inside the CCW circle = left of the line.
    const auto in = p.Project(95 * std::cos(th), 95 * std::sin(th), th + M_PI / 2 + 0.1, 100 * th);
    EXPECT_NEAR(in.lateral_error, 5.0, 0.05);
    EXPECT_NEAR(in.heading_error, 0.1, 1e-3);
    const auto out = p.Project(104 * std::cos(th), 104 * std::sin(th), th, 100 * th);
    EXPECT_NEAR(out.lateral_error, -4.0, 0.05);
  }
}

TEST(PathTest, WrapsAtTheStartLine) {
  const Path p = Circle(50.0, 200);
  EXPECT_NEAR(p.Wrap(p.length() + 3.0), 3.0, 1e-9);
  EXPECT_NEAR(p.Wrap(-2.0), p.length() - 2.0, 1e-9);
  const auto pr = p.Project(50 * std::cos(-0.01), 50 * std::sin(-0.01), M_PI / 2, 1.0);
  EXPECT_NEAR(pr.s, p.length() - 0.5, 0.02);
  const PathPoint a = p.Sample(p.length() - 1e-6), b = p.Sample(0.0);
  EXPECT_NEAR(a.x, b.x, 1e-3);
  EXPECT_NEAR(WrapAngle(a.psi - b.psi), 0.0, 1e-3);
}

TEST(PathTest, RejectsBadStations) {
  std::vector<PathPoint> pts = {
      {0, 0, 0, 0, 0, 1, 0}, {1, 1, 0, 0, 0, 1, 0}, {1, 2, 0, 0, 0, 1, 0}};
  EXPECT_THROW(Path(pts, 5.0), ConfigError);
  // Every problem at once, each under its key.
  pts[0].s = 0.5;
  pts[2].v = std::numeric_limits<double>::quiet_NaN();
  try {
    Path(pts, 0.5);
    ADD_FAILURE() << "no ConfigError";
  } catch (const ConfigError& e) {
    std::vector<std::string> keys;
    for (const auto& p : e.problems()) keys.push_back(p.path);
    EXPECT_EQ(keys, (std::vector<std::string>{"stations[0].s", "stations[2].s", "length",
                                              "stations[2]"}));
    EXPECT_EQ(e.file(), "reference path");
  }
  EXPECT_THROW(Path({}, 1.0), ConfigError);
}

// ---------------------------------------------------------------------------------------------
// Bit-identity of the fast path matching against the straightforward algorithm it replaced: the
// reference below is the former Path::Project / Sample / Wrap / WrapAngle (a % per window index,
// the angle wraps redone at every improvement, remainder and fmod always called).

double RefWrapAngle(double a) {
  if (!std::isfinite(a)) return 0.0;
  a = std::remainder(a, 2.0 * M_PI);
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

double RefWrap(const Path& p, double s) {
  if (!std::isfinite(s)) return 0.0;
  double w = std::fmod(s, p.length());
  if (w < 0) w += p.length();
  return w >= p.length() ? 0.0 : w;
}

// The last station at or before s (what the estimate-and-walk search ends on).
std::size_t RefSegmentAt(const Path& p, double s) {
  const auto& pts = p.points();
  std::size_t i = 0;
  while (i + 1 < pts.size() && pts[i + 1].s <= s) ++i;
  return i;
}

PathPoint RefSample(const Path& path, double s_in) {
  const auto& pts = path.points();
  const double s = RefWrap(path, s_in);
  const std::size_t i = RefSegmentAt(path, s);
  const std::size_t j = (i + 1) % pts.size();
  const PathPoint& a = pts[i];
  const PathPoint& b = pts[j];
  const double s_b = j == 0 ? path.length() : b.s;
  const double t = (s - a.s) / (s_b - a.s);
  PathPoint p;
  p.s = s;
  p.x = a.x + t * (b.x - a.x);
  p.y = a.y + t * (b.y - a.y);
  p.psi = RefWrapAngle(a.psi + t * RefWrapAngle(b.psi - a.psi));
  p.kappa = a.kappa + t * (b.kappa - a.kappa);
  p.v = a.v + t * (b.v - a.v);
  p.a_x = a.a_x + t * (b.a_x - a.a_x);
  return p;
}

PathProjection RefProject(const Path& path, double x, double y, double psi, double s_hint,
                          double window) {
  const auto& pts = path.points();
  const std::size_t n = pts.size();
  const double length = path.length();
  const double mean_ds = length / static_cast<double>(n);
  std::size_t first = 0, count = n;
  if (std::isfinite(s_hint) && s_hint >= 0 && window > 0 && 2 * window < length) {
    const std::size_t half = static_cast<std::size_t>(window / mean_ds) + 2;
    const std::size_t center = RefSegmentAt(path, RefWrap(path, s_hint));
    first = (center + n - std::min(half, n)) % n;
    count = std::min(n, 2 * half + 1);
  }
  double best_d2 = std::numeric_limits<double>::infinity();
  PathProjection best;
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t i = (first + k) % n;
    const std::size_t j = (i + 1) % n;
    const PathPoint& a = pts[i];
    const PathPoint& b = pts[j];
    const double ex = b.x - a.x, ey = b.y - a.y;
    const double len2 = ex * ex + ey * ey;
    double t = len2 > 0 ? ((x - a.x) * ex + (y - a.y) * ey) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    const double px = a.x + t * ex, py = a.y + t * ey;
    const double d2 = (x - px) * (x - px) + (y - py) * (y - py);
    if (d2 < best_d2) {
      best_d2 = d2;
      const double s_b = j == 0 ? length : b.s;
      best.s = RefWrap(path, a.s + t * (s_b - a.s));
      best.segment = i;
      const double cross = ex * (y - a.y) - ey * (x - a.x);
      best.lateral_error = (cross >= 0 ? 1.0 : -1.0) * std::sqrt(d2);
      best.heading_error = RefWrapAngle(psi - (a.psi + t * RefWrapAngle(b.psi - a.psi)));
    }
  }
  return best;
}

// Equal bit for bit (tells −0 from +0, unlike ==).
bool Same(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

::testing::AssertionResult SameProjection(const PathProjection& got, const PathProjection& want) {
  if (Same(got.s, want.s) && Same(got.lateral_error, want.lateral_error) &&
      Same(got.heading_error, want.heading_error) && got.segment == want.segment)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << std::hexfloat << "got s " << got.s << " n " << got.lateral_error << " dpsi "
         << got.heading_error << " seg " << got.segment << ", want s " << want.s << " n "
         << want.lateral_error << " dpsi " << want.heading_error << " seg " << want.segment;
}

::testing::AssertionResult SamePoint(const PathPoint& got, const PathPoint& want) {
  if (Same(got.s, want.s) && Same(got.x, want.x) && Same(got.y, want.y) &&
      Same(got.psi, want.psi) && Same(got.kappa, want.kappa) && Same(got.v, want.v) &&
      Same(got.a_x, want.a_x))
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << std::hexfloat << "s " << got.s << " vs " << want.s
                                       << ", psi " << got.psi << " vs " << want.psi;
}

// A wobbly closed line with uneven station spacing and headings from atan2 (jumping at ±π), or
// continued without wrapping (growing by 2π per lap, so the closing segment turns by −2π).
Path Wobbly(int n, bool wrapped_heading, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::vector<double> th(n);
  for (int i = 0; i < n; ++i) th[i] = 2 * M_PI * (i + (i == 0 ? 0.0 : jitter(rng))) / n;
  const auto at = [](double a) {
    const double r = 150.0 * (1.0 + 0.25 * std::sin(3 * a));
    return std::pair{r * std::cos(a) + 40.0, r * std::sin(a) - 15.0};
  };
  std::vector<PathPoint> pts(n);
  double s = 0.0;
  for (int i = 0; i < n; ++i) {
    const auto [x, y] = at(th[i]);
    if (i > 0) s += std::hypot(x - pts[i - 1].x, y - pts[i - 1].y);
    const auto [xa, ya] = at(th[i] - 1e-4);
    const auto [xb, yb] = at(th[i] + 1e-4);
    double psi = std::atan2(yb - ya, xb - xa);
    if (!wrapped_heading) psi = th[i] + M_PI / 2 + RefWrapAngle(psi - th[i] - M_PI / 2);
    pts[i] = {s, x, y, psi, 0.01 * std::sin(5 * th[i]), 20.0 + 5.0 * std::cos(th[i]), 0.1 * i};
  }
  const double length = s + std::hypot(pts[0].x - pts[n - 1].x, pts[0].y - pts[n - 1].y);
  return Path(std::move(pts), length);
}

// A 40 m × 40 m square with a station every metre from the corner (0, 0): every coordinate is an
// integer, so many points are at exactly equal distance from several segments (exact ties).
Path Square() {
  std::vector<PathPoint> pts;
  for (int i = 0; i < 160; ++i) {
    const int side = i / 40, k = i % 40;
    const double x = side == 0 ? k : side == 1 ? 40 : side == 2 ? 40 - k : 0;
    const double y = side == 0 ? 0 : side == 1 ? k : side == 2 ? 40 : 40 - k;
    pts.push_back({double(i), x, y, side * M_PI / 2, 0.0, 10.0, 0.0});
  }
  return Path(std::move(pts), 160.0);
}

void CheckAgainstReference(const Path& path, int cases, std::uint64_t seed) {
  const double len = path.length();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto uni = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
  const double windows[] = {-1.0,           0.0,           0.5,     5.0, 20.0, 60.0, 200.0,
                            len / 2 - 1e-9, len / 2 - 3.0, len / 2, 1e9};
  int wrap_cases = 0;
  for (int c = 0; c < cases; ++c) {
    // Where along the line: anywhere, or within 3 m of the start line on either side.
    const int where = c % 4;
    const double s = where == 0 ? uni(len - 3.0, len) : where == 1 ? uni(0.0, 3.0) : uni(0.0, len);
    wrap_cases += where < 2;
    const PathPoint on = RefSample(path, s);
    const double off = c % 10 == 0 ? uni(-400.0, 400.0) : uni(-15.0, 15.0);
    const double x = on.x - off * std::sin(on.psi), y = on.y + off * std::cos(on.psi);
    const double psi = c % 3 == 0 ? uni(-20.0, 20.0) : on.psi + uni(-0.5, 0.5);
    // Hints: near the truth, anywhere, near the start line (also just past length), degenerate.
    double hint = 0.0;
    switch (c % 7) {
      case 0:
      case 1:
        hint = s + uni(-3.0, 3.0);
        break;
      case 2:
        hint = uni(0.0, len);
        break;
      case 3:
        hint = uni(len - 5.0, len + 5.0);
        break;
      case 4:
        hint = uni(0.0, 5.0);
        break;
      case 5:
        hint = (c / 7) % 2 ? 0.0 : std::nextafter(len, 0.0);
        break;
      default:
        hint = (c / 7) % 3 == 0 ? std::numeric_limits<double>::quiet_NaN() : -uni(0.0, 5.0);
    }
    const double window = windows[c % std::size(windows)];
    ASSERT_TRUE(SameProjection(path.Project(x, y, psi, hint, window),
                               RefProject(path, x, y, psi, hint, window)))
        << "case " << c << " x " << x << " y " << y << " psi " << psi << " hint " << hint
        << " window " << window;
    const double s_any = c % 5 == 0 ? s - len * std::floor(uni(-3.0, 3.0)) : s;
    ASSERT_TRUE(SamePoint(path.Sample(s_any), RefSample(path, s_any))) << "s " << s_any;
  }
  EXPECT_GT(wrap_cases, cases / 3);
}

TEST(PathTest, ProjectionIsBitIdenticalToTheReferenceOnAWobblyLine) {
  CheckAgainstReference(Wobbly(700, true, 1), 60000, 11);
  CheckAgainstReference(Wobbly(333, false, 2), 60000, 12);
}

TEST(PathTest, ProjectionIsBitIdenticalToTheReferenceOnExactTies) {
  const Path sq = Square();
  CheckAgainstReference(sq, 30000, 13);
  // Grid points (integers and halves) inside and around the square, every hint and window:
  // the centre is equally far from all four sides, a point off a corner from two segments,
  // one of them the closing segment when the corner is the start.
  int ties = 0;
  for (double x = -3.0; x <= 43.0; x += 0.5)
    for (double y = -3.0; y <= 43.0; y += 0.5)
      for (double hint : {0.0, 1.0, 159.5, 40.0, 100.0, -1.0})
        for (double window : {0.5, 3.0, 20.0, 79.0, 79.999, 80.0}) {
          const PathProjection got = sq.Project(x, y, 1.0, hint, window);
          ASSERT_TRUE(SameProjection(got, RefProject(sq, x, y, 1.0, hint, window)))
              << x << ", " << y << " hint " << hint << " window " << window;
          ties += (x == 20.0 && y == 20.0) || (x < 0 && y < 0);
        }
  EXPECT_GT(ties, 0);
  // Off the start corner, the closing segment (159 → 0) comes first in a window starting before
  // the start line and wins the tie with segment 0.
  EXPECT_EQ(sq.Project(-1.0, -1.0, 0.0, 0.0, 5.0).segment, 159u);
  EXPECT_EQ(sq.Project(-1.0, -1.0, 0.0, -1.0, 5.0).segment, 0u);  // full search from segment 0
}

TEST(PathTest, ProjectionOfNonFiniteOrFarPosesMatchesTheReference) {
  const Path p = Wobbly(200, true, 3);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double x : {nan, inf, -inf, 1e200, 0.0})
    for (double y : {nan, 1e200, 0.0})
      for (double psi : {nan, inf, 0.5})
        for (double hint : {-1.0, 10.0, nan})
          ASSERT_TRUE(SameProjection(p.Project(x, y, psi, hint, 20.0),
                                     RefProject(p, x, y, psi, hint, 20.0)))
              << x << ", " << y << ", " << psi << ", " << hint;
}

TEST(PathTest, WrapAngleIsBitIdenticalToTheRemainderForm) {
  std::vector<double> a = {0.0,    -0.0,    M_PI,  -M_PI,  2 * M_PI, -2 * M_PI, 3 * M_PI, -3 * M_PI,
                           1e-300, -1e-300, 1e300, -1e300, 7.0,      -7.0,      1e6,      -1e6};
  for (double b : {M_PI, 2 * M_PI, 3 * M_PI})
    for (double sign : {1.0, -1.0}) {
      double v = sign * b;
      for (int k = 0; k < 4; ++k) v = std::nextafter(v, 0.0);
      for (int k = 0; k < 8; ++k, v = std::nextafter(v, sign * 1e9)) a.push_back(v);
    }
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> u(-30.0, 30.0);
  for (int k = 0; k < 200000; ++k) a.push_back(u(rng));
  for (double v : a) ASSERT_TRUE(Same(WrapAngle(v), RefWrapAngle(v))) << std::hexfloat << v;
  EXPECT_EQ(WrapAngle(std::numeric_limits<double>::infinity()), 0.0);
  EXPECT_EQ(WrapAngle(std::numeric_limits<double>::quiet_NaN()), 0.0);
}

}  // namespace
}  // namespace scw::controller::planning
