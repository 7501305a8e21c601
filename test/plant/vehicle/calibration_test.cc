// Issue 14, prerequisites P1, P3, P4 of ../shared/spec/closed-loop-fidelity.md §9: the built-in
// EAV24 set against public data. These pin the calibration; change a number here only together
// with the vehicle set and a stated public source.
#include <gtest/gtest.h>

#include <cmath>

#include "params/schema/vehicle_params.h"
#include "plant/actuator/actuators.h"
#include "plant/tire/magic_formula.h"
#include "plant/vehicle/ggv.h"
#include "plant/vehicle/quasi_steady.h"

namespace scw::plant {
namespace {

// Public EAV g-g-v fit (plant-and-track spec §4.4), ±10 %.
void ExpectWithin10Percent(double value, double reference, const char* what) {
  EXPECT_GE(value, 0.9 * reference) << what;
  EXPECT_LE(value, 1.1 * reference) << what;
}

TEST(Eav24Calibration, FrictionRatioAtNominalLoadIsThatOfRealSlicks) {
  const params::VehicleParams p;
  for (const params::Mf52Params* t : {&p.tires.front, &p.tires.rear}) {
    const TirePeakFriction mu = PeakFriction(t->fnomin, 1.0, 1.0, *t);
    EXPECT_GE(mu.mu_x / mu.mu_y, 1.0);
    EXPECT_LE(mu.mu_x / mu.mu_y, 1.25);
  }
}

TEST(Eav24Calibration, SteadyStateLimitsFollowThePublicEavFit) {
  const params::VehicleParams p;
  ExpectWithin10Percent(ComputeGgvPoint(p, 40.0).lateral_max, 22.5, "lateral at 40 m/s");
  ExpectWithin10Percent(ComputeGgvPoint(p, 58.0).lateral_max, 26.4, "lateral at 58 m/s");
  ExpectWithin10Percent(ComputeGgvPoint(p, 10.0).braking_max, 15.0, "braking at low speed");
  ExpectWithin10Percent(ComputeGgvPoint(p, 60.0).braking_max, 34.2, "braking at 60 m/s");
  // Known deviation at 13 m/s (stated in docs/plant-calibration.md): the public fit's 17.3 m/s^2
  // needs R = 9.8 m, beyond the car's 0.324 rad steering lock with any understeer, and mu_y
  // ~ 1.76 at low speed, which together with its ~15 m/s^2 braking contradicts mu_x >= mu_y.
  // With mu_x >= mu_y kept, the tyres alone reach ~80 % of it; pinned so it cannot drift.
  QuasiSteadyOptions no_lock;
  no_lock.respect_steering_lock = false;
  const double ay13 = QuasiSteadyModel(p, no_lock).MaxLateral(13.0);
  EXPECT_GE(ay13, 0.75 * 17.3);
  EXPECT_LE(ay13, 1.1 * 17.3);
}

TEST(Eav24Calibration, PaperMaximaLieInsideTheEnvelope) {
  const params::VehicleParams p;
  // Pitschi et al.: 29.5 m/s^2 lateral and 29.2 m/s^2 longitudinal reached in testing.
  const GgvPoint g70 = ComputeGgvPoint(p, 70.0);
  EXPECT_GE(g70.lateral_max, 29.5);
  EXPECT_GE(g70.braking_max, 29.2);
}

TEST(Eav24Calibration, UndersteersLinearlyAtEverySpeed) {
  const QuasiSteadyModel qs{params::VehicleParams{}};
  for (double v : {10.0, 40.0, 70.0}) {
    const double k = 1e3 * qs.UndersteerGradient(v);  // mrad/(m/s^2)
    EXPECT_GT(k, 0.3) << v;
    EXPECT_LT(k, 1.0) << v;
  }
}

TEST(Eav24Calibration, BrakeResponseIsAbout150Ms) {
  const params::VehicleParams p;
  const double t = BrakeStepResponseTime(p.brakes, p.simulation.time_step);
  EXPECT_GE(t, 0.130);
  EXPECT_LE(t, 0.170);
  // The documented 40 ms sensitivity: delay 0.006 s, lag and rate limit unchanged.
  params::BrakeParams fast = p.brakes;
  fast.delay = 0.006;
  EXPECT_NEAR(BrakeStepResponseTime(fast, p.simulation.time_step), 0.040, 0.003);
}

TEST(QuasiSteady, AgreesWithTheSimulatedLateralLimit) {
  const params::VehicleParams p;
  const QuasiSteadyModel qs(p);
  for (double v : {20.0, 40.0, 60.0}) {
    // The simulation holds speed without drag; the quasi-steady model carries drag on the rear
    // tyres, so it may be slightly lower at speed.
    EXPECT_NEAR(qs.MaxLateral(v), ComputeGgvPoint(p, v).lateral_max,
                0.05 * ComputeGgvPoint(p, v).lateral_max)
        << v;
  }
}

TEST(QuasiSteady, StateBalancesForcesAndIsMirrorSymmetric) {
  const params::VehicleParams p;
  const QuasiSteadyModel qs(p);
  const QuasiSteadyState l = qs.Solve(40.0, 2.0, 12.0);
  const QuasiSteadyState r = qs.Solve(40.0, 2.0, -12.0);
  ASSERT_TRUE(l.feasible);
  ASSERT_TRUE(r.feasible);
  EXPECT_NEAR(l.steer, -r.steer, 1e-9);
  EXPECT_NEAR(l.fy[kFL], -r.fy[kFR], 1e-6);
  double fy = 0.0;
  for (std::size_t i = 0; i < 4; ++i) {
    const double c = IsFront(i) ? std::cos(l.steer) : 1.0, s = IsFront(i) ? std::sin(l.steer) : 0;
    fy += s * l.fx[i] + c * l.fy[i];
  }
  EXPECT_NEAR(fy / p.chassis.mass, 12.0, 1e-3);
  // Drive beyond the envelope is infeasible; more lateral load leaves less drive.
  EXPECT_FALSE(qs.Solve(40.0, 30.0, 12.0).feasible);
  EXPECT_GT(qs.MaxDrive(30.0, 5.0), qs.MaxDrive(30.0, 15.0));
  EXPECT_GT(qs.MaxBrake(30.0, 5.0), qs.MaxBrake(30.0, 15.0));
}

}  // namespace
}  // namespace scw::plant
