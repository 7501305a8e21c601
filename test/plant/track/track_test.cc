// Track geometry and the curvilinear projection on analytic tracks (no data needed).
#include "plant/track/track.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "plant/track/yas_north.h"

namespace scw::plant {
namespace {

constexpr double kPi = std::numbers::pi;

// Circle of radius r sampled at m points (anticlockwise, starting at (r, 0)).
Track Circle(double r, int m, double smoothing = 0.0) {
  std::vector<double> x, y, w(m, 5.0);
  for (int i = 0; i < m; ++i) {
    x.push_back(r * std::cos(2 * kPi * i / m));
    y.push_back(r * std::sin(2 * kPi * i / m));
  }
  TrackBuildOptions o;
  o.smoothing = smoothing;
  return Track::FromPoints(x, y, w, w, {}, o, "circle", "test");
}

TEST(Track, CircleFromPointsHasLengthCurvatureAndHeading) {
  const Track t = Circle(50.0, 200);
  EXPECT_NEAR(t.length(), 2 * kPi * 50.0, 1e-3);
  EXPECT_NEAR(t.total_turning(), 2 * kPi, 1e-9);
  for (std::size_t i = 0; i < t.size(); i += 37) {
    EXPECT_NEAR(t.curvature()[i], 1.0 / 50.0, 1e-5);
    EXPECT_NEAR(std::hypot(t.x()[i], t.y()[i]), 50.0, 1e-4);
  }
  EXPECT_NEAR(t.PoseAt(0.0).heading, kPi / 2, 1e-6);
}

TEST(Track, OvalDefinitionClosesWithExactCurvature) {
  const params::TrackParams def;  // 200 m straights, R 50 m semicircles
  const Track t = Track::FromDefinition(def);
  EXPECT_NEAR(t.length(), 400.0 + 2 * kPi * 50.0, 1e-9);
  EXPECT_LT(t.closure_gap(), 1e-6);
  EXPECT_NEAR(t.CurvatureAt(100.0), 0.0, 1e-12);
  EXPECT_NEAR(t.CurvatureAt(200.0 + 50.0), 0.02, 1e-9);
  const TrackPose top = t.PoseAt(200.0 + 50.0 * kPi);  // end of the first semicircle
  EXPECT_NEAR(top.x, 200.0, 1e-6);
  EXPECT_NEAR(top.y, 100.0, 1e-6);
  EXPECT_NEAR(top.heading, kPi, 1e-9);
}

TEST(Track, DefinitionThatDoesNotCloseIsRejected) {
  params::TrackParams def;
  def.length[0] = 230.0;  // straights of different length: 30 m gap
  try {
    Track::FromDefinition(def, "odd.yaml");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("do not close"), std::string::npos) << e.what();
  }
  def = params::TrackParams{};
  def.curvature_start[1] = def.curvature_end[1] = 0.03;  // turns 2.5π
  EXPECT_THROW(Track::FromDefinition(def), ConfigError);
}

TEST(Track, ProjectionOfCentreLinePointsGivesZeroOffsetAndTheirArcLength) {
  const Track t = Track::FromDefinition(params::TrackParams{});
  for (double s = 0.3; s < t.length(); s += 17.1) {
    const TrackPose p = t.PoseAt(s);
    const TrackProjection q = t.Project(p.x, p.y, p.heading);
    EXPECT_NEAR(q.s, s, 1e-6) << s;
    EXPECT_NEAR(q.n, 0.0, 1e-9) << s;
    EXPECT_NEAR(q.heading_error, 0.0, 1e-9) << s;
  }
}

TEST(Track, OffsetPointsGiveTheSignedOffsetLeftPositive) {
  const Track t = Circle(50.0, 400);
  // Anticlockwise circle: left = towards the centre. Positions are linear between nodes, so the
  // centre line sits up to ds²/(8R) inside the true circle (2.5 mm here).
  const TrackProjection in = t.Project(45.0, 0.0, kPi / 2 + 0.1);
  EXPECT_NEAR(in.n, 5.0, 5e-3);
  EXPECT_NEAR(in.s, 0.0, 1e-3);
  EXPECT_NEAR(in.heading_error, 0.1, 1e-3);
  const TrackProjection out = t.Project(0.0, 53.0);
  EXPECT_NEAR(out.n, -3.0, 5e-3);
  EXPECT_NEAR(out.s, t.length() / 4, 1e-2);
  // Round trip through ToCartesian on the piecewise oval, both sides, every 3.7 m.
  const Track oval = Track::FromDefinition(params::TrackParams{});
  for (double s = 0.0; s < oval.length(); s += 3.7)
    for (double n : {-4.5, -1.0, 2.0, 5.5}) {
      double x, y;
      oval.ToCartesian(s, n, &x, &y);
      const TrackProjection q = oval.Project(x, y, 0.0, s + 2.0);
      EXPECT_NEAR(q.s, s, 1e-6);
      EXPECT_NEAR(q.n, n, 1e-6);
    }
}

TEST(Track, ArcLengthWrapsAtTheStartLine) {
  const Track t = Track::FromDefinition(params::TrackParams{});
  EXPECT_NEAR(t.Wrap(t.length() + 3.0), 3.0, 1e-9);
  EXPECT_NEAR(t.Wrap(-2.0), t.length() - 2.0, 1e-9);
  // Just before and just after the line (start at the origin heading +x).
  const TrackProjection before = t.Project(-0.5, 1.0, 0.0, t.length() - 1.0);
  // (the last segment is the R 50 m semicircle ending at the line: s ≈ L − 0.51, n ≈ 1.0)
  EXPECT_NEAR(before.s, t.length() - 50.0 * std::atan(0.5 / 49.0), 1e-3);
  EXPECT_NEAR(before.n, 50.0 - std::hypot(0.5, 49.0), 5e-3);
  const TrackProjection after = t.Project(0.5, -1.0, 0.0, t.length() - 1.0);
  EXPECT_NEAR(after.s, 0.5, 1e-9);
  EXPECT_NEAR(after.n, -1.0, 1e-9);
  // Interpolation wraps too.
  EXPECT_NEAR(t.Interpolate(t.width_left(), t.length() + 1.0), t.WidthLeftAt(1.0), 1e-12);
}

TEST(Track, LocalSearchAgreesWithGlobalAndFallsBackFromAWrongHint) {
  const Track t = YasNorthTrack();
  for (double s = 1.0; s < t.length(); s += 41.3) {
    double x, y;
    t.ToCartesian(s, 3.0, &x, &y);
    const TrackProjection global = t.Project(x, y);
    const TrackProjection local = t.Project(x, y, 0.0, s - 4.0);
    const TrackProjection wrong = t.Project(x, y, 0.0, t.Wrap(s + 1500.0));
    EXPECT_NEAR(global.s, s, 1e-6);
    EXPECT_NEAR(local.s, s, 1e-6);
    EXPECT_NEAR(wrong.s, s, 1e-6);
    EXPECT_NEAR(local.n, 3.0, 1e-6);
  }
}

TEST(Track, FromPointsRejectsBadInput) {
  std::vector<double> x{0, 1, 2}, y{0, 1, 0}, w{1, 1, 1};
  EXPECT_THROW(Track::FromPoints(x, y, w, w, {}, {}, "t", "few"), ConfigError);
  // An open arc (a quarter circle) does not close.
  x.clear();
  y.clear();
  for (int i = 0; i < 20; ++i) {
    x.push_back(50 * std::cos(0.5 * kPi * i / 19));
    y.push_back(50 * std::sin(0.5 * kPi * i / 19));
  }
  w.assign(20, 3.0);
  EXPECT_THROW(Track::FromPoints(x, y, w, w, {}, {}, "t", "open"), ConfigError);
}

}  // namespace
}  // namespace scw::plant
