// The observers of a closed-loop run on synthetic signals: no plant, no controller.
#include "tuning/sim/run_observers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include "test/tuning/sim/tick_signals.h"

namespace scw::tuning {
namespace {

using controller::SlipPhase;
using synthetic::TickSignals;

constexpr double kInf = std::numeric_limits<double>::infinity();

double Above(double x) { return std::nextafter(x, kInf); }
double Below(double x) { return std::nextafter(x, -kInf); }

// ---------------------------------------------------------------------------------------------
// LapCounter

TEST(LapCounterTest, CrossingTimeIsInterpolatedWithinTheTick) {
  // 40 m per 1 s tick on a 100 m track: the line lies halfway through the tick from s = 80 to
  // s = 20 (progress 80 → 120), i.e. at t = 2.5 s; lap 2 ends exactly on a tick (progress 200).
  LapCounter laps(100.0);
  const std::vector<double> s = {0.0, 40.0, 80.0, 20.0, 60.0, 0.0};
  std::vector<bool> completed;
  for (std::size_t k = 0; k < s.size(); ++k)
    completed.push_back(laps.Update(static_cast<double>(k), s[k]));
  EXPECT_EQ(completed, (std::vector<bool>{false, false, false, true, false, true}));
  EXPECT_EQ(laps.laps(), 2);
  EXPECT_EQ(laps.lap_times(), (std::vector<double>{2.5, 2.5}));
  EXPECT_EQ(laps.progress(), 200.0);
}

TEST(LapCounterTest, TheFirstTickOnlySetsThePosition) {
  LapCounter laps(100.0);
  EXPECT_FALSE(laps.Update(0.0, 70.0));
  EXPECT_EQ(laps.progress(), 0.0);
  EXPECT_EQ(laps.s(), 70.0);
  EXPECT_FALSE(laps.Update(1.0, 75.0));
  EXPECT_EQ(laps.progress(), 5.0);
}

TEST(LapCounterTest, AStartJustBeforeTheLineNeedsAFullLapOfProgress) {
  // Start at s = 95: crossing the line 5 m later is progress 10, not a lap. The lap ends when the
  // car is back at s = 95 (progress 100), at t = 4.5 within the tick from s = 80 to s = 10.
  LapCounter laps(100.0);
  const std::vector<double> s = {95.0, 5.0, 35.0, 65.0, 80.0, 10.0};
  // progress:                     0    10    40    70    85    115 (wrap: 10 − 80 + 100)
  laps.Update(0.0, s[0]);
  EXPECT_FALSE(laps.Update(1.0, s[1]));
  EXPECT_EQ(laps.progress(), 10.0);
  EXPECT_FALSE(laps.Update(2.0, s[2]));
  EXPECT_FALSE(laps.Update(3.0, s[3]));
  EXPECT_FALSE(laps.Update(4.0, s[4]));
  EXPECT_TRUE(laps.Update(5.0, s[5]));
  EXPECT_EQ(laps.progress(), 115.0);
  ASSERT_EQ(laps.lap_times().size(), 1u);
  EXPECT_EQ(laps.lap_times()[0], 4.5);
}

TEST(LapCounterTest, WrapsBothWaysAtTheStartLine) {
  LapCounter laps(100.0);
  laps.Update(0.0, 2.0);
  laps.Update(1.0, 98.0);  // backwards over the line: −4 m
  EXPECT_EQ(laps.progress(), -4.0);
  laps.Update(2.0, 3.0);  // forwards over it again: +5 m
  EXPECT_EQ(laps.progress(), 1.0);
  EXPECT_EQ(laps.laps(), 0);
}

TEST(LapCounterTest, WritesWhereTheRunEnded) {
  LapCounter laps(100.0);
  laps.Update(0.0, 1.0);
  laps.Update(0.5, 99.0);  // behind the start point: no negative distance
  RunMetrics m;
  m.max_speed = 7.0;  // not the counter's: left alone
  laps.WriteTo(&m);
  EXPECT_EQ(m.time, 0.5);
  EXPECT_EQ(m.end_s, 99.0);
  EXPECT_EQ(m.end_lap, 0);
  EXPECT_EQ(m.distance, 0.0);
  EXPECT_TRUE(m.lap_times.empty());
  EXPECT_EQ(m.max_speed, 7.0);

  // Progress −2, then 23, 48, 73, 98, 123: lap 1 ends on the last tick.
  double t = 0.5;
  for (double s : {24.0, 49.0, 74.0, 99.0, 24.0}) laps.Update(t += 1.0, s);
  laps.WriteTo(&m);
  EXPECT_EQ(m.time, 5.5);
  EXPECT_EQ(m.end_lap, 1);
  EXPECT_EQ(m.distance, 123.0);
  EXPECT_EQ(m.lap_times.size(), 1u);
}

// ---------------------------------------------------------------------------------------------
// InterventionCounter and MetricsAccumulator

TEST(InterventionCounterTest, CountsRisingEdgesAndActiveTime) {
  InterventionCounter c;
  int count = 0;
  double time = 0.0;
  for (bool on : {true, true, false, true, false, false, true, true, true})
    c.Update(on, 0.25, &count, &time);
  EXPECT_EQ(count, 3);
  EXPECT_EQ(time, 6 * 0.25);
}

TEST(InterventionCounterTest, AFirstTickThatIsOnIsAnActivation) {
  InterventionCounter c;
  int count = 0;
  double time = 0.0;
  c.Update(true, 0.5, &count, &time);
  EXPECT_EQ(count, 1);
  EXPECT_EQ(time, 0.5);
}

constexpr double kTs = 0.25;
constexpr PerWheel<double> kGain = {10.0, 10.0, 20.0, 20.0};

TEST(MetricsAccumulatorTest, KeepsTheExtremesOfMagnitudes) {
  MetricsAccumulator acc(kTs, 5.0, kGain);
  RunMetrics m;
  TickSignals x;
  x.beta = -0.2;
  x.motion.lateral_error = 1.5;
  x.motion.heading_error = -0.1;
  x.speed = 50.0;
  x.plant.kappa = {-0.3, 0.1, 0.05, 0.2};
  acc.Add(x.Record(), &m);
  x.beta = 0.1;
  x.motion.lateral_error = -2.0;
  x.motion.heading_error = 0.05;
  x.speed = 40.0;
  x.plant.kappa = {0.0, 0.0, -0.4, 0.0};
  acc.Add(x.Record(), &m);
  EXPECT_EQ(m.max_abs_sideslip, 0.2);
  EXPECT_EQ(m.max_abs_lateral_error, 2.0);
  EXPECT_EQ(m.max_abs_heading_error, 0.1);
  EXPECT_EQ(m.max_speed, 50.0);
  EXPECT_EQ(m.max_slip_front, 100.0 * 0.3);
  EXPECT_EQ(m.max_slip_rear, 100.0 * 0.4);
}

TEST(MetricsAccumulatorTest, IntegratesOnlyTheSideslipAboveTheAllowedAngle) {
  MetricsAccumulator acc(kTs, 5.0, kGain);
  RunMetrics m;
  TickSignals x;
  x.beta = 4.0 / kRadToDeg;  // below: nothing
  acc.Add(x.Record(), &m);
  EXPECT_EQ(m.sideslip_excess_integral, 0.0);
  x.beta = -8.0 / kRadToDeg;  // |β| counts: 3 deg excess over one tick
  acc.Add(x.Record(), &m);
  EXPECT_NEAR(m.sideslip_excess_integral, 3.0 * kTs, 1e-12);
}

TEST(MetricsAccumulatorTest, EscBrakeEnergyCountsAddedFrontPressureWhileEscActs) {
  MetricsAccumulator acc(kTs, 5.0, kGain);
  RunMetrics m;
  TickSignals x;
  x.input.brake_request_bar = {10.0, 10.0, 10.0, 10.0};
  x.output.brake_bar = {14.0, 6.0, 30.0, 30.0};  // FL +4 bar, FR released, rears ignored
  x.meas.wheel_speed = {-100.0, 100.0, 100.0, 100.0};
  acc.Add(x.Record(), &m);  // ESC not active
  EXPECT_EQ(m.esc_brake_energy, 0.0);
  x.output.esc_active = true;
  acc.Add(x.Record(), &m);
  EXPECT_EQ(m.esc_brake_energy, 4.0 * 10.0 * 100.0 * kTs);
}

TEST(MetricsAccumulatorTest, AbsReleaseAndTcCutCountOnlyWhereTheyAct) {
  MetricsAccumulator acc(kTs, 5.0, kGain);
  RunMetrics m;
  TickSignals x;
  x.input.brake_request_bar = {50.0, 50.0, 40.0, 40.0};
  x.output.brake_bar = {30.0, 20.0, 40.0, 10.0};
  x.input.throttle_request = 0.75;
  x.output.throttle = 0.25;
  acc.Add(x.Record(), &m);  // neither acts
  EXPECT_EQ(m.abs_pressure_released, 0.0);
  EXPECT_EQ(m.tc_throttle_cut, 0.0);
  x.output.abs_state = {SlipPhase::kReduce, SlipPhase::kInactive, SlipPhase::kHold,
                        SlipPhase::kInactive};
  x.output.tc_state = {SlipPhase::kInactive, SlipPhase::kInactive, SlipPhase::kInactive,
                       SlipPhase::kIncrease};
  acc.Add(x.Record(), &m);
  EXPECT_EQ(m.abs_pressure_released, 20.0 * kTs);  // FL released 20 bar, RL (held) none
  EXPECT_EQ(m.tc_throttle_cut, 0.5 * kTs);
}

// The steering request's RMS above ~1.6 Hz (a second-order high-pass): nothing from a constant
// or a steady steering rate, exact on the first ticks of a step, and it tells a 4 Hz limit cycle
// from a racing line's 0.2 Hz steering of the same amplitude.
TEST(MetricsAccumulatorTest, SteeringHighPassRmsSeparatesALimitCycleFromTheLine) {
  constexpr double ts = 0.01;
  constexpr double tau = MetricsAccumulator::kSteerHfTau;
  constexpr double a = ts / (tau + ts);
  {
    MetricsAccumulator acc(ts, 5.0, kGain);
    RunMetrics m;
    TickSignals x;
    x.input.steering_request = 0.3;  // the first tick starts the low-pass on the request
    acc.Add(x.Record(), &m);
    EXPECT_EQ(m.steer_hf_rms, 0.0);
    x.input.steering_request = 0.4;  // a step of 0.1 rad
    acc.Add(x.Record(), &m);
    const double h1 = 0.1 * (1 - a);  // y₁ = 0.3 + 0.1a
    const double h2 = h1 - a * h1;    // y₂ = a h₁
    EXPECT_NEAR(m.steer_hf_rms, std::sqrt(h2 * h2 / 2.0), 1e-15);
  }
  auto rms_of = [&](auto steer) {
    MetricsAccumulator acc(ts, 5.0, kGain);
    RunMetrics m;
    TickSignals x;
    for (int k = 0; k < 4000; ++k) {  // 40 s
      x.input.steering_request = steer(k * ts);
      acc.Add(x.Record(), &m);
    }
    return m.steer_hf_rms;
  };
  // a steady steering rate of 0.02 rad/s: only the start-up transient, which dies out
  EXPECT_LT(rms_of([](double t) { return 0.02 * t; }), 1e-4);
  auto sine = [](double hz) {
    return [hz](double t) { return 0.05 * std::sin(2 * std::numbers::pi * hz * t); };
  };
  // the sine's RMS 0.05/√2 through two of the discrete high-passes, each
  // H(z) = (1 − a)(1 − z⁻¹)/(1 − (1 − a) z⁻¹) at z = e^{jω tS}
  auto expected = [&](double hz) {
    const std::complex<double> zi = std::polar(1.0, -2 * std::numbers::pi * hz * ts);
    const double h = std::abs((1 - a) * (1.0 - zi) / (1.0 - (1 - a) * zi));
    return 0.05 / std::sqrt(2.0) * h * h;
  };
  EXPECT_NEAR(rms_of(sine(4.0)), expected(4.0), 0.02 * expected(4.0));
  EXPECT_NEAR(rms_of(sine(0.2)), expected(0.2), 0.05 * expected(0.2));
  EXPECT_GT(rms_of(sine(4.0)), 30.0 * rms_of(sine(0.2)));
}

TEST(MetricsAccumulatorTest, CountsActivationsOfEachIntervention) {
  MetricsAccumulator acc(kTs, 5.0, kGain);
  RunMetrics m;
  TickSignals x;
  const auto tick = [&](bool esc, bool cs, SlipPhase abs_fl, SlipPhase abs_rr) {
    x.output.esc_active = esc;
    x.output.cs_active = cs;
    x.output.abs_state = {abs_fl, SlipPhase::kInactive, SlipPhase::kInactive, abs_rr};
    acc.Add(x.Record(), &m);
  };
  constexpr auto kOff = SlipPhase::kInactive, kOn = SlipPhase::kHold;
  tick(true, false, kOn, kOff);
  tick(true, true, kOff, kOn);  // ABS moved to another wheel: still one activation
  tick(false, true, kOff, kOff);
  tick(true, false, kOn, kOn);
  EXPECT_EQ(m.esc_count, 2);
  EXPECT_EQ(m.esc_time, 3 * kTs);
  EXPECT_EQ(m.cs_count, 1);
  EXPECT_EQ(m.cs_time, 2 * kTs);
  EXPECT_EQ(m.abs_count, 2);
  EXPECT_EQ(m.abs_time, 3 * kTs);
  EXPECT_EQ(m.tc_count, 0);
  EXPECT_EQ(m.tc_time, 0.0);
}

// ---------------------------------------------------------------------------------------------
// AbortMonitor

// A circle of radius 100 m with 4 m to the left and 3 m to the right of the centre line.
plant::Track Circle() {
  constexpr int kPoints = 128;
  std::vector<double> x, y;
  for (int i = 0; i < kPoints; ++i) {
    x.push_back(100.0 * std::cos(2 * std::numbers::pi * i / kPoints));
    y.push_back(100.0 * std::sin(2 * std::numbers::pi * i / kPoints));
  }
  return plant::Track::FromPoints(x, y, std::vector<double>(kPoints, 4.0),
                                  std::vector<double>(kPoints, 3.0), {}, {}, "circle", "test");
}

params::AbortParams Limits() {
  params::AbortParams ab;
  ab.max_sideslip_deg = 20.0;
  ab.max_lateral_error = 3.0;
  ab.lock_slip_pct = 25.0;
  ab.spin_slip_pct = 50.0;
  ab.slip_time = 0.5;
  ab.off_track = true;
  return ab;
}

constexpr double kTimeout = 100.0;

class AbortMonitorTest : public ::testing::Test {
 protected:
  std::optional<RunStatus> Check(const TickSignals& x) { return monitor_.Check(x.Record()); }
  const plant::Track track_ = Circle();
  AbortMonitor monitor_{Limits(), kTimeout, kTs, track_};
};

TEST_F(AbortMonitorTest, ANominalTickGoesOn) {
  TickSignals x;
  x.s = 10.0;
  EXPECT_EQ(Check(x), std::nullopt);
}

TEST_F(AbortMonitorTest, SideslipFiresJustAboveItsThreshold) {
  // A limit equal to the tick's |β| in degrees: not above it.
  TickSignals x;
  x.beta = -0.3;
  params::AbortParams ab = Limits();
  ab.max_sideslip_deg = std::abs(x.beta) * kRadToDeg;
  AbortMonitor monitor(ab, kTimeout, kTs, track_);
  EXPECT_EQ(monitor.Check(x.Record()), std::nullopt);
  x.beta = -0.3 * (1.0 + 1e-12);
  EXPECT_EQ(monitor.Check(x.Record()), RunStatus::kSideslip);
}

TEST_F(AbortMonitorTest, LateralErrorFiresJustAboveItsThresholdOnEitherSide) {
  TickSignals x;
  for (double sign : {1.0, -1.0}) {
    x.motion.lateral_error = sign * 3.0;
    EXPECT_EQ(Check(x), std::nullopt);
    x.motion.lateral_error = sign * Above(3.0);
    EXPECT_EQ(Check(x), RunStatus::kLateralError);
  }
}

TEST_F(AbortMonitorTest, OffTrackFiresJustBeyondEitherEdge) {
  TickSignals x;
  x.s = 123.4;
  x.n = track_.WidthLeftAt(x.s);
  EXPECT_EQ(Check(x), std::nullopt);
  x.n = Above(x.n);
  EXPECT_EQ(Check(x), RunStatus::kOffTrack);
  x.n = -track_.WidthRightAt(x.s);
  EXPECT_EQ(Check(x), std::nullopt);
  x.n = Below(x.n);
  EXPECT_EQ(Check(x), RunStatus::kOffTrack);
}

TEST_F(AbortMonitorTest, OffTrackCanBeSwitchedOff) {
  params::AbortParams ab = Limits();
  ab.off_track = false;
  AbortMonitor monitor(ab, kTimeout, kTs, track_);
  TickSignals x;
  x.n = 50.0;
  EXPECT_EQ(monitor.Check(x.Record()), std::nullopt);
}

TEST_F(AbortMonitorTest, WheelLockFiresWhenHeldLongerThanTheSlipTime) {
  // tS = 0.25 s, slip_time = 0.5 s: held 0.25, 0.5 (not longer), 0.75 → abort on the third tick.
  TickSignals x;
  x.plant.kappa[kRL] = -0.25;  // −25 % is not below −25 %: never counts
  for (int k = 0; k < 5; ++k) EXPECT_EQ(Check(x), std::nullopt);
  EXPECT_EQ(monitor_.lock_time()[kRL], 0.0);
  x.plant.kappa[kRL] = -0.3;
  EXPECT_EQ(Check(x), std::nullopt);
  EXPECT_EQ(Check(x), std::nullopt);
  EXPECT_EQ(monitor_.lock_time()[kRL], 0.5);
  EXPECT_EQ(Check(x), RunStatus::kWheelLock);
}

TEST_F(AbortMonitorTest, AReleasedWheelStartsItsHoldTimeAgain) {
  TickSignals x;
  for (int k = 0; k < 3; ++k) {
    x.plant.kappa[kFR] = 0.6;  // spinning for two ticks ...
    EXPECT_EQ(Check(x), std::nullopt);
    EXPECT_EQ(Check(x), std::nullopt);
    x.plant.kappa[kFR] = 0.5;  // ... then exactly at the limit: not above, the time resets
    EXPECT_EQ(Check(x), std::nullopt);
    EXPECT_EQ(monitor_.spin_time()[kFR], 0.0);
  }
  x.plant.kappa[kFR] = 0.6;
  for (int k = 0; k < 2; ++k) EXPECT_EQ(Check(x), std::nullopt);
  EXPECT_EQ(Check(x), RunStatus::kWheelSpin);
}

TEST_F(AbortMonitorTest, LockWinsOverSpinOnTheSameTick) {
  TickSignals x;
  x.plant.kappa = {-0.3, 0.0, 0.0, 0.6};
  for (int k = 0; k < 2; ++k) EXPECT_EQ(Check(x), std::nullopt);
  EXPECT_EQ(Check(x), RunStatus::kWheelLock);
}

TEST_F(AbortMonitorTest, TimeoutFiresJustAfterTheLimit) {
  TickSignals x;
  x.t = kTimeout;
  EXPECT_EQ(Check(x), std::nullopt);
  x.t = Above(kTimeout);
  EXPECT_EQ(Check(x), RunStatus::kTimeout);
}

TEST_F(AbortMonitorTest, TheFirstRuleInOrderWins) {
  // Every rule holds; drop them one by one from the front: the next in order must answer.
  TickSignals x;
  x.beta = 1.0;                  // 57 deg
  x.motion.lateral_error = 4.0;  // > 3 m
  x.n = 10.0;                    // beyond the left edge
  x.plant.kappa = {-0.3, 0.0, 0.0, 0.6};
  x.t = 2 * kTimeout;
  EXPECT_EQ(Check(x), RunStatus::kSideslip);
  x.beta = 0.0;
  EXPECT_EQ(Check(x), RunStatus::kLateralError);
  x.motion.lateral_error = 0.0;
  EXPECT_EQ(Check(x), RunStatus::kOffTrack);
  x.n = 0.0;
  EXPECT_EQ(Check(x), RunStatus::kWheelLock);  // held 4 ticks by now
  x.plant.kappa = {};
  EXPECT_EQ(Check(x), RunStatus::kTimeout);
  x.t = 0.0;
  EXPECT_EQ(Check(x), std::nullopt);
}

}  // namespace
}  // namespace scw::tuning
