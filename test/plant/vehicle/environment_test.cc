// The road reaches the plant: the friction under each wheel (plant::Environment) scales that
// wheel's tyre forces, a friction patch of a track or scenario covers exactly its (s, n) area,
// and a uniform road leaves every step bit for bit as it was without an environment.
#include "plant/vehicle/environment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "params/schema/track_params.h"
#include "params/schema/vehicle_params.h"
#include "plant/track/road_surface.h"
#include "plant/track/track.h"
#include "plant/vehicle/vehicle.h"

namespace scw::plant {
namespace {

// Hard braking at 40 m/s, straight, for 0.6 s (past the brake delay): the state after it.
State BrakeOn(const Vehicle& v, const Environment& env, int steps = 600) {
  State s = v.MakeState({0.0, 0.0, 0.0, 40.0});
  Actuators u;
  u.brake_pressure_req = {60.0, 60.0, 60.0, 60.0};
  for (int k = 0; k < steps; ++k) v.Step(u, env, &s);
  return s;
}

TEST(Environment, NominalRoadIsBitIdenticalToTheStepWithoutEnvironment) {
  const Vehicle v{params::VehicleParams{}};
  State a = v.MakeState({0.0, 0.0, 0.0, 30.0}), b = a;
  Actuators u;
  u.throttle = 0.8;
  u.steer_req = 0.05;
  for (int k = 0; k < 2000; ++k) {
    v.Step(u, &a);
    v.Step(u, Environment{}, &b);
  }
  for (int i = 0; i < kNumStates; ++i) EXPECT_EQ(a.x[i], b.x[i]) << kStateNames[i];
}

TEST(Environment, ALowFrictionWheelLosesForceAndLocksFirst) {
  const Vehicle v{params::VehicleParams{}};
  Environment oily;
  oily.mu[kFL] = 0.3;  // the left front on an oily patch
  const State nominal = BrakeOn(v, Environment{}, 250);
  const State patch = BrakeOn(v, oily, 250);
  // The wheel on the patch transmits far less braking force and slips far more.
  EXPECT_LT(std::abs(patch.out.fx[kFL]), 0.5 * std::abs(nominal.out.fx[kFL]));
  EXPECT_LT(patch.out.kappa[kFL], nominal.out.kappa[kFL] - 0.05);
  // The others are barely touched; the car slows less.
  EXPECT_NEAR(patch.out.fx[kFR], nominal.out.fx[kFR], 0.1 * std::abs(nominal.out.fx[kFR]));
  EXPECT_GT(patch.x[kVx], nominal.x[kVx]);
  // Braking harder on one side yaws the car towards the grippy side (right: negative yaw rate).
  EXPECT_LT(patch.x[kYawRate], nominal.x[kYawRate]);
}

TEST(Environment, NonFiniteOrNonPositiveFactorsCountAsTheNominalRoad) {
  const Vehicle v{params::VehicleParams{}};
  Environment bad;
  bad.mu = {std::numeric_limits<double>::quiet_NaN(), -1.0, 0.0,
            std::numeric_limits<double>::infinity()};
  const State a = BrakeOn(v, Environment{}, 300), b = BrakeOn(v, bad, 300);
  for (int i = 0; i < kNumStates; ++i) EXPECT_EQ(a.x[i], b.x[i]) << kStateNames[i];
}

// A straight-sided oval: 200 m straights from s = 0, 6 m to each side.
Track Oval(const params::FrictionPatches& patches = {}) {
  params::TrackParams def;
  def.friction_patches = patches;
  return Track::FromDefinition(def, "oval");
}

TEST(RoadSurface, PatchCoversItsArcLengthAndLateralRangeOnly) {
  params::FrictionPatches p;
  p.start = {50.0};
  p.end = {80.0};
  p.n_min = {0.0};  // the left half only (μ-split)
  p.n_max = {6.0};
  p.factor = {0.5};
  const Track track = Oval(p);
  const RoadSurface road(track);
  EXPECT_FALSE(road.uniform());
  EXPECT_EQ(road.FrictionAt(60.0, 2.0), 0.5);
  EXPECT_EQ(road.FrictionAt(60.0, -2.0), 1.0);                  // right half
  EXPECT_EQ(road.FrictionAt(49.9, 2.0), 1.0);                   // before
  EXPECT_EQ(road.FrictionAt(80.0, 2.0), 1.0);                   // end is exclusive
  EXPECT_EQ(road.FrictionAt(60.0 + track.length(), 2.0), 0.5);  // wraps
}

TEST(RoadSurface, ScenarioPatchesAddToTheTracksAndOverlapsMultiply) {
  params::FrictionPatches own, extra;
  own = {{10.0}, {30.0}, {-100.0}, {100.0}, {0.8}};
  const Track track = Oval(own);
  const double last = track.length() - 5.0;
  extra = {{20.0, last}, {40.0, 5.0}, {-100.0, -100.0}, {100.0, 100.0}, {0.5, 0.6}};
  const RoadSurface road(track, extra);
  EXPECT_EQ(road.FrictionAt(15.0, 0.0), 0.8);
  EXPECT_EQ(road.FrictionAt(25.0, 0.0), 0.8 * 0.5);
  EXPECT_EQ(road.FrictionAt(35.0, 0.0), 0.5);
  EXPECT_EQ(road.FrictionAt(2.0, 0.0), 0.6);         // spans the start line
  EXPECT_EQ(road.FrictionAt(last + 1.0, 0.0), 0.6);  // spans the start line
  EXPECT_EQ(road.FrictionAt(100.0, 0.0), 1.0);
}

TEST(RoadSurface, WheelsOfACarStraddlingAMuSplitSeeTheirOwnSide) {
  params::FrictionPatches p = {{50.0}, {150.0}, {0.0}, {100.0}, {0.4}};
  const Track track = Oval(p);
  const RoadSurface road(track);
  const Vehicle v{params::VehicleParams{}};
  // On the centre line at s = 100, heading along the track.
  TrackProjection at;
  at.s = 100.0;
  at.n = 0.0;
  const Environment env = road.UnderWheels(at, v.contact_x(), v.contact_y());
  EXPECT_EQ(env.mu[kFL], 0.4);
  EXPECT_EQ(env.mu[kRL], 0.4);
  EXPECT_EQ(env.mu[kFR], 1.0);
  EXPECT_EQ(env.mu[kRR], 1.0);
  // Only the front axle has reached a patch that starts 1 m ahead of the CoG.
  at.s = 49.0;
  at.n = -3.0;  // right of the centre line: every wheel right of n = 0, off the patch
  const Environment before = road.UnderWheels(at, v.contact_x(), v.contact_y());
  for (double mu : before.mu) EXPECT_EQ(mu, 1.0);
  at.n = 3.0;
  const Environment front_in = road.UnderWheels(at, v.contact_x(), v.contact_y());
  EXPECT_EQ(front_in.mu[kFL], 0.4);
  EXPECT_EQ(front_in.mu[kFR], 0.4);
  EXPECT_EQ(front_in.mu[kRL], 1.0);
  EXPECT_EQ(front_in.mu[kRR], 1.0);
}

TEST(RoadSurface, UniformTrackGivesTheDefaultEnvironment) {
  const Track track = Oval();
  const RoadSurface road(track);
  EXPECT_TRUE(road.uniform());
  const Environment env = road.UnderWheels({}, {1.0, 1.0, -1.0, -1.0}, {1.0, -1.0, 1.0, -1.0});
  for (double mu : env.mu) EXPECT_EQ(mu, 1.0);
  params::TrackParams wet;
  wet.friction_scale = {0.7};
  const Track wet_track = Track::FromDefinition(wet, "wet");
  const RoadSurface wet_road(wet_track);
  EXPECT_FALSE(wet_road.uniform());
  EXPECT_DOUBLE_EQ(wet_road.FrictionAt(10.0, 0.0), 0.7);
}

}  // namespace
}  // namespace scw::plant
