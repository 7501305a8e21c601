// Forward-backward g-g-v velocity profile: limits respected at every node, periodic, monotone in
// the acceleration scaling GG.
#include "controller/planning/velocity_profile.h"

#include <gtest/gtest.h>

#include <cmath>

#include "plant/track/yas_north.h"

namespace scw::controller::planning {
namespace {

// Every segment's mean a_x within the combined limit at both of its ends; a_y at every node.
void ExpectWithinLimits(const ReferenceTrajectory& r, const plant::Track& path, const GgvTable& g,
                        double gg) {
  auto ay_lim = [&](std::size_t i) { return gg * path.friction()[i] * g.AyMax(r.v[i]); };
  auto comb = [&](std::size_t i) { return g.DriveFactor(std::abs(r.a_y[i]), ay_lim(i), r.v[i]); };
  int violations = 0;
  for (std::size_t i = 0; i + 1 < r.size(); ++i) {
    const double tol = 1e-6;
    if (std::abs(r.a_y[i]) > ay_lim(i) + tol) ++violations;
    const double ax = r.a_x[i];
    if (ax > 0) {
      const double lim = std::min(gg * g.AxDriveMax(r.v[i]) * comb(i),
                                  gg * g.AxDriveMax(r.v[i + 1]) * comb(i + 1));
      if (ax > lim + tol) ++violations;
    } else {
      const double lim =
          std::min(gg * path.friction()[i] * g.AxBrakeMax(r.v[i]) * comb(i),
                   gg * path.friction()[i + 1] * g.AxBrakeMax(r.v[i + 1]) * comb(i + 1));
      if (-ax > lim + tol) ++violations;
    }
  }
  EXPECT_EQ(violations, 0);
}

TEST(VelocityProfile, ConstantRadiusCircleRunsAtTheLateralLimit) {
  params::TrackParams def;
  def.length = {100.0 * M_PI, 100.0 * M_PI};
  def.curvature_start = def.curvature_end = {0.01, 0.01};
  def.width_left = def.width_right = {5.0, 5.0};
  const plant::Track circle = plant::Track::FromDefinition(def);
  const auto g = GgvTable::Constant(16.0, 6.0, 12.0, 2.0);
  const ReferenceTrajectory r = ComputeVelocityProfile(circle, g);
  for (std::size_t i = 0; i < r.size(); ++i) {
    EXPECT_NEAR(r.v[i], 40.0, 1e-6);
    EXPECT_NEAR(r.a_x[i], 0.0, 1e-6);
  }
  EXPECT_NEAR(r.lap_time, 2 * M_PI * 100.0 / 40.0, 1e-6);
}

TEST(VelocityProfile, YasNorthRespectsLimitsAndIsPeriodic) {
  const plant::Track t = plant::YasNorthTrack();
  const GgvTable g = RepresentativeGgv();
  for (double gg : {0.8, 1.0, 1.3}) {
    VelocityProfileOptions o;
    o.gg_scale = gg;
    const ReferenceTrajectory r = ComputeVelocityProfile(t, g, o);
    ExpectWithinLimits(r, t, g, gg);
    EXPECT_DOUBLE_EQ(r.v.front(), r.v.back());
    EXPECT_LE(*std::max_element(r.v.begin(), r.v.end()), o.v_max);
    EXPECT_NEAR(r.t.back(), r.lap_time, 1e-12);
  }
}

TEST(VelocityProfile, ScalesUpMonotonicallyWithGg) {
  const plant::Track t = plant::YasNorthTrack();
  const GgvTable g = RepresentativeGgv();
  ReferenceTrajectory prev;
  for (double gg : {0.6, 0.8, 1.0, 1.2, 1.4}) {
    VelocityProfileOptions o;
    o.gg_scale = gg;
    const ReferenceTrajectory r = ComputeVelocityProfile(t, g, o);
    if (!prev.v.empty()) {
      EXPECT_LT(r.lap_time, prev.lap_time) << gg;
      for (std::size_t i = 0; i < r.size(); ++i) EXPECT_GE(r.v[i], prev.v[i] - 1e-9) << i;
    }
    prev = r;
  }
}

TEST(VelocityProfile, InterpolationWrapsAndMatchesNodes) {
  const plant::Track t = plant::YasNorthTrack();
  const ReferenceTrajectory r = ComputeVelocityProfile(t, RepresentativeGgv());
  EXPECT_NEAR(r.At(r.s[100]).v, r.v[100], 1e-12);
  EXPECT_NEAR(r.At(r.length + r.s[100]).v, r.v[100], 1e-9);
  EXPECT_NEAR(r.At(-1.0).v, r.At(r.length - 1.0).v, 1e-12);
}

TEST(VelocityProfile, InvalidLimitsAreConfigErrors) {
  GgvTable g = RepresentativeGgv();
  g.ay_max.pop_back();
  EXPECT_THROW(ComputeVelocityProfile(plant::YasNorthTrack(), g), ConfigError);
}

}  // namespace
}  // namespace scw::controller::planning
