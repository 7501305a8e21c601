// Minimum-curvature racing line: within the bounds minus the margin, less curvature than the
// centre line, converged; and a given raceline file loads.
#include "tuning/sim/trajectory/racing_line.h"

#include <gtest/gtest.h>

#include <iostream>

#include "plant/track/yas_north.h"
#include "test/test_data.h"
#include "tuning/sim/track_csv.h"
#include "tuning/sim/trajectory/velocity_profile.h"

namespace scw::tuning {
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

TEST(RacingLine, GivenRacelineFileLoads) {
  const std::string ref = test::SharedData(test::kYasSmoothed);
  const std::string line =
      test::SharedData("tracks/yas_north/global_racing_lines/yasnorth_3d_dallaraAV21_gg_0.1.csv");
  if (ref.empty() || line.empty()) GTEST_SKIP() << "../shared/data/tracks/yas_north not present";
  const plant::Track t = tuning::LoadTrackCsv(ref);
  const RacingLine rl = LoadRacingLine(line, t);
  EXPECT_NEAR(rl.line.length(), 2990.0, 60.0);
  EXPECT_LT(SquaredCurvatureIntegral(rl.line), SquaredCurvatureIntegral(t));
}

}  // namespace
}  // namespace scw::tuning
