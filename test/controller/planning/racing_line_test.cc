// Minimum-curvature racing line: within the bounds minus the margin, less curvature than the
// centre line, converged; and a line through given points (a raceline file's) is placed on the
// track.
#include "controller/planning/racing_line.h"

#include <gtest/gtest.h>

#include <iostream>

#include "controller/planning/velocity_profile.h"
#include "plant/track/yas_north.h"

namespace scw::controller::planning {
namespace {

TEST(RacingLine, YasNorthMinimumCurvatureLine) {
  const plant::Track t = plant::YasNorthTrack();
  RacingLineOptions o;
  const RacingLine rl = MinimumCurvatureLine(t, o);
  std::cout << "optimiser: " << rl.offset.size() << " offsets, " << rl.evaluations
            << " evaluations, " << rl.seconds << " s, " << rl.status << ", J "
            << rl.objective_initial << " -> " << rl.objective_final << "\n";
  EXPECT_TRUE(rl.status == "success" || rl.status == "ftol reached" || rl.status == "xtol reached")
      << rl.status;
  EXPECT_LT(rl.objective_final, 0.5 * rl.objective_initial);
  // Bounds minus margin at the optimisation nodes, and along the resampled line.
  for (std::size_t i = 0; i < rl.offset.size(); ++i) {
    EXPECT_LE(rl.offset[i], t.WidthLeftAt(rl.s_centre[i]) - o.margin + 1e-9);
    EXPECT_GE(rl.offset[i], -(t.WidthRightAt(rl.s_centre[i]) - o.margin) - 1e-9);
  }
  double hint = plant::Track::kNoHint;
  for (std::size_t i = 0; i < rl.line.size(); ++i) {
    const auto q = t.Project(rl.line.x()[i], rl.line.y()[i], 0.0, hint);
    hint = q.s;
    EXPECT_LE(q.n, t.WidthLeftAt(q.s) - o.margin + 0.05) << q.s;
    EXPECT_GE(q.n, -(t.WidthRightAt(q.s) - o.margin) - 0.05) << q.s;
  }
  const double k_line = SquaredCurvatureIntegral(rl.line), k_centre = SquaredCurvatureIntegral(t);
  std::cout << "integral of kappa^2: racing line " << k_line << ", centre line " << k_centre
            << " 1/m\n";
  EXPECT_LT(k_line, k_centre);
  const double lap_line = ComputeVelocityProfile(rl.line, RepresentativeGgv()).lap_time;
  const double lap_centre = ComputeVelocityProfile(t, RepresentativeGgv()).lap_time;
  std::cout << "ideal lap: racing line " << lap_line << " s, centre line " << lap_centre << " s\n";
  EXPECT_LT(lap_line, lap_centre);
}

TEST(RacingLine, MarginWiderThanTheTrackIsAConfigError) {
  RacingLineOptions o;
  o.margin = 8.0;
  EXPECT_THROW(MinimumCurvatureLine(plant::YasNorthTrack(), o), ConfigError);
}

TEST(RacingLine, ALineThroughGivenPointsFollowsThemAndNamesPointsOffTheTrack) {
  const plant::Track t = plant::YasNorthTrack();
  // Curvilinear points 1 m left of the centre line every 50 m: the line keeps that offset.
  RacelinePoints points;
  points.cartesian = false;
  for (double s = 0.0; s < t.length() - 25.0; s += 50.0) {
    points.a.push_back(s);
    points.b.push_back(1.0);
    points.rows.push_back(static_cast<int>(points.rows.size()) + 2);
  }
  const RacingLine rl = RacingLineThrough(t, points, "given.csv");
  EXPECT_EQ(rl.status, "loaded from given.csv");
  EXPECT_NEAR(rl.line.length(), t.length(), 0.01 * t.length());
  ASSERT_EQ(rl.offset.size(), points.a.size());
  EXPECT_EQ(rl.offset[3], 1.0);
  // One point far outside: the error names the source and the point's file line.
  points.b[4] = 40.0;
  try {
    RacingLineThrough(t, points, "given.csv");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("given.csv"), std::string::npos) << what;
    EXPECT_NE(what.find("line 6"), std::string::npos) << what;
    EXPECT_NE(what.find("off the track"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace scw::controller::planning
