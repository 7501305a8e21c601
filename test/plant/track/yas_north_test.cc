// Built-in Yas North: the shipped yaml equals the C++ definition, and the definition follows the
// public centre line (length, corner radii, ideal lap time) when ../shared/data is present.
#include "plant/track/yas_north.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "controller/planning/velocity_profile.h"
#include "params/io/load.h"
#include "params/io/write.h"
#include "test/test_data.h"
#include "tuning/sim/track_csv.h"

namespace scw::plant {
namespace {

using tuning::LoadTrackCsv;

TEST(YasNorth, ShippedYamlEqualsTheBuiltInDefinition) {
  const auto file =
      params::LoadPlainFile<params::TrackParams>(test::SourcePath("params/tracks/yas_north.yaml"));
  EXPECT_EQ(params::ToPlainYaml(file), params::ToPlainYaml(YasNorthDefinition()));
}

TEST(YasNorth, DefinitionClosesByItselfAndIsAbout3Km) {
  const Track t = YasNorthTrack();
  EXPECT_LT(t.closure_gap(), 0.5);
  EXPECT_NEAR(t.total_turning(), 2 * 3.141592653589793, 1e-9);
  EXPECT_NEAR(t.length(), 3005.0, 30.0);
  const auto& d = YasNorthDefinition();
  EXPECT_GE(d.length.size(), 20u);
  EXPECT_LE(d.length.size(), 40u);
}

double MinRadius(const Track& t, double s0, double s1) {
  double k = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t.s()[i] >= s0 && t.s()[i] <= s1) k = std::max(k, std::abs(t.curvature()[i]));
  return 1.0 / k;
}

TEST(YasNorth, FollowsThePublicCentreLine) {
  const std::string path = test::SharedData(test::kYasSmoothed);
  if (path.empty()) GTEST_SKIP() << "../shared/data/" << test::kYasSmoothed << " not present";
  const Track pub = LoadTrackCsv(path);  // default 2 m smoothing removes the cm-level noise
  const Track def = YasNorthTrack();
  std::cout << "length: built-in " << def.length() << " m, public " << pub.length() << " m\n";
  EXPECT_NEAR(def.length() / pub.length(), 1.0, 0.01);

  // Corners of spec §5.2 (public s ranges); the same corner on the built-in line is found by
  // projecting the public range ends, both ranges widened by 15 m.
  struct Corner {
    const char* name;
    double s0, s1;
  };
  const Corner corners[] = {{"T1 left R31", 264, 324},
                            {"left R50", 508, 570},
                            {"right sweep R90-120", 650, 830},
                            {"hairpin left R27", 1291, 1397},
                            {"chicane left-left R11-15", 2536, 2626},
                            {"right R20", 2728, 2754}};
  for (const Corner& c : corners) {
    const TrackPose a = pub.PoseAt(c.s0), b = pub.PoseAt(c.s1);
    const double d0 = def.Project(a.x, a.y).s, d1 = def.Project(b.x, b.y).s;
    const double r_pub = MinRadius(pub, c.s0 - 15, c.s1 + 15);
    const double r_def = MinRadius(def, d0 - 15, d1 + 15);
    std::cout << c.name << ": min radius built-in " << r_def << " m, public " << r_pub << " m\n";
    EXPECT_NEAR(r_def / r_pub, 1.0, 0.15) << c.name;
  }

  const controller::planning::GgvTable ggv = controller::planning::RepresentativeGgv();
  const double t_pub = controller::planning::ComputeVelocityProfile(pub, ggv).lap_time;
  const double t_def = controller::planning::ComputeVelocityProfile(def, ggv).lap_time;
  std::cout << "centre-line lap time: built-in " << t_def << " s, public " << t_pub << " s\n";
  EXPECT_NEAR(t_def / t_pub, 1.0, 0.03);
}

}  // namespace
}  // namespace scw::plant
