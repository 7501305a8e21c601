// Event places (a corner's apex plus an offset) and the late-braking reference: the brake point
// moves later, the slowest speed stays, the shift is capped.
#include "controller/planning/late_braking.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "plant/track/corners.h"
#include "plant/track/yas_north.h"

namespace scw::controller::planning {
namespace {

const plant::Track& Yas() {
  static const plant::Track t = plant::YasNorthTrack();
  return t;
}

TEST(LateBraking, APlaceIsAnArcLengthOrAnOffsetFromACornersApex) {
  const auto corners = plant::FindCorners(Yas());
  ASSERT_GE(corners.size(), 9u);
  EXPECT_EQ(corners[0].number, 1);
  EXPECT_EQ(EventPlace(Yas(), 0.0, 700.0, "events.throttle", 0), 700.0);
  EXPECT_NEAR(EventPlace(Yas(), 0.0, -10.0, "events.throttle", 0), Yas().length() - 10.0, 1e-9);
  EXPECT_EQ(EventPlace(Yas(), 3.0, 25.0, "events.throttle", 0), corners[2].s_apex + 25.0);
  try {
    EventPlace(Yas(), 42.0, 0.0, "events.throttle", 1);
    FAIL() << "a corner the track does not have must be refused";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("events.throttle.corner"), std::string::npos) << what;
    EXPECT_NE(what.find("element [1] = 42"), std::string::npos) << what;
    EXPECT_NE(what.find("9 corners"), std::string::npos) << what;
  }
}

Path SyntheticPath() {
  // A 1000 m circle: 60 m/s, braking from s = 400 to s = 500 (60 → 20 m/s at 16 m/s²), then
  // accelerating back at 8 m/s².
  std::vector<PathPoint> pts;
  for (int i = 0; i < 1000; ++i) {
    PathPoint p;
    p.s = i;
    const double a = 2.0 * M_PI * i / 1000.0;
    p.x = 1000.0 / (2.0 * M_PI) * std::cos(a);
    p.y = 1000.0 / (2.0 * M_PI) * std::sin(a);
    p.psi = a + M_PI / 2.0;
    const double s = i;
    if (s < 400.0)
      p.v = 60.0;
    else if (s <= 500.0)
      p.v = std::sqrt(60.0 * 60.0 - 2.0 * 16.0 * (s - 400.0));
    else
      p.v = std::min(60.0, std::sqrt(20.0 * 20.0 + 2.0 * 8.0 * (s - 500.0)));
    pts.push_back(p);
  }
  return Path(std::move(pts), 1000.0);
}

TEST(LateBraking, LateBrakingMovesTheBrakePointAndKeepsTheSlowestSpeed) {
  const auto path = SyntheticPath();
  // A track on the same circle: its arc length is the path's (up to the resampling).
  std::vector<double> x, y;
  for (const auto& p : path.points()) {
    x.push_back(p.x);
    y.push_back(p.y);
  }
  const std::vector<double> width(x.size(), 5.0);
  const plant::Track loop =
      plant::Track::FromPoints(x, y, width, width, {}, plant::TrackBuildOptions{}, "loop", "test");
  params::LateBraking late{{0.0}, {480.0}, {30.0}};
  const auto moved = LateBrakingPath(path, late, loop);
  EXPECT_EQ(moved.Sample(420.0).v, 60.0);  // still at full speed 20 m after the old brake point
  EXPECT_LT(path.Sample(420.0).v, 60.0);
  EXPECT_EQ(moved.Sample(500.0).v, path.Sample(500.0).v);  // same slowest speed
  double min_ax_new = 0.0;
  for (const auto& p : moved.points()) min_ax_new = std::min(min_ax_new, p.a_x);
  EXPECT_LT(min_ax_new, -16.0 * 100.0 / 70.0 * 0.98);  // the speed drop over 70 m instead of 100
  // Outside the zone nothing changes.
  EXPECT_EQ(moved.Sample(200.0).v, path.Sample(200.0).v);
  EXPECT_EQ(moved.Sample(700.0).v, path.Sample(700.0).v);
  // The shift is capped at 80 % of the zone.
  params::LateBraking huge{{0.0}, {480.0}, {400.0}};
  const auto capped = LateBrakingPath(path, huge, loop);
  EXPECT_EQ(capped.Sample(479.0).v, 60.0);
  EXPECT_LT(capped.Sample(490.0).v, 60.0);
}

}  // namespace
}  // namespace scw::controller::planning
