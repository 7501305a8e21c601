#include "controller/motion/path.h"

#include <gtest/gtest.h>

#include <cmath>

namespace scw::controller::motion {
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
  EXPECT_THROW(Path(pts, 5.0), std::invalid_argument);
}

}  // namespace
}  // namespace scw::controller::motion
