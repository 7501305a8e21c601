// Slip control (spec §3.1, §3.2, §3.6–§3.8): source selection, operation modes, output selection,
// gear-shift window and throttle cut.
#include "controller/stability/slip_control.h"

#include <gtest/gtest.h>

#include <cmath>

namespace scw::controller {
namespace {

using P = SlipPhase;

TEST(SlipSourceTest, TableOfSpec31) {
  const Wheels slip{-5.0, -15.0, -8.0, -2.0};
  const Wheels virt{-1.0, -2.0, -30.0, -40.0};
  const Wheels fz{1000.0, 3000.0, 2000.0, 2000.0};
  const Wheels rate{10.0, 20.0, 30.0, 40.0};
  const Wheels alpha{0.01, 0.02, 0.03, 0.04};
  // Raw.
  auto s = SelectSlipSource(SlipSelector::kMin, false, false, slip, virt, fz, rate, alpha);
  EXPECT_EQ(s.slip, slip);
  EXPECT_EQ(s.slip_rate, rate);
  EXPECT_EQ(s.slip_angle_abs, alpha);
  // Load weighted: front (1000·−5 + 3000·−15)/4000 = −12.5, rear −5; rates of the smaller slip.
  s = SelectSlipSource(SlipSelector::kMin, false, true, slip, virt, fz, rate, alpha);
  EXPECT_EQ(s.slip, (Wheels{-12.5, -12.5, -5.0, -5.0}));
  EXPECT_EQ(s.slip_rate, (Wheels{20.0, 20.0, 30.0, 30.0}));
  // TC picks the larger slip for the rates.
  s = SelectSlipSource(SlipSelector::kMax, false, true, slip, virt, fz, rate, alpha);
  EXPECT_EQ(s.slip_rate, (Wheels{10.0, 10.0, 40.0, 40.0}));
  // Virtual, not weighted: virtual slips; front rates individual, rear of the smaller raw slip.
  s = SelectSlipSource(SlipSelector::kMin, true, false, slip, virt, fz, rate, alpha);
  EXPECT_EQ(s.slip, virt);
  EXPECT_EQ(s.slip_rate, (Wheels{10.0, 20.0, 30.0, 30.0}));
  // Virtual and weighted: weighted fronts, virtual RL for both rears.
  s = SelectSlipSource(SlipSelector::kMin, true, true, slip, virt, fz, rate, alpha);
  EXPECT_EQ(s.slip, (Wheels{-12.5, -12.5, -30.0, -30.0}));
  EXPECT_EQ(s.slip_rate, (Wheels{20.0, 20.0, 30.0, 30.0}));
  // Zero axle load: raw slips of that axle.
  s = SelectSlipSource(SlipSelector::kMin, false, true, slip, virt, {0.0, 0.0, 1.0, 1.0}, rate,
                       alpha);
  EXPECT_EQ(s.slip[kFL], -5.0);
  EXPECT_EQ(s.slip[kFR], -15.0);
}

TEST(SlipDistributionTest, OperationModes) {
  const WheelSlipSignals src{{-5.0, -15.0, 3.0, 12.0}, {0.01, 0.02, 0.04, 0.03}, {1, 2, 3, 4}};
  EXPECT_EQ(DistributeSlips(SlipOperationMode::kIndividual, SlipSelector::kMin, src).slip,
            src.slip);
  // Axle split (ABS: min per axle; |α̃| max of axle; rate of the wheel with the larger |slip|).
  auto d = DistributeSlips(SlipOperationMode::kAxleSplit, SlipSelector::kMin, src);
  EXPECT_EQ(d.slip, (Wheels{-15.0, -15.0, 3.0, 3.0}));
  EXPECT_EQ(d.slip_angle_abs, (Wheels{0.02, 0.02, 0.04, 0.04}));
  EXPECT_EQ(d.slip_rate, (Wheels{2, 2, 4, 4}));
  d = DistributeSlips(SlipOperationMode::kAxleSplit, SlipSelector::kMax, src);
  EXPECT_EQ(d.slip, (Wheels{-5.0, -5.0, 12.0, 12.0}));
  // All together.
  d = DistributeSlips(SlipOperationMode::kAllTogether, SlipSelector::kMax, src);
  EXPECT_EQ(d.slip, (Wheels{12.0, 12.0, 12.0, 12.0}));
  EXPECT_EQ(d.slip_angle_abs, (Wheels{0.04, 0.04, 0.04, 0.04}));
  EXPECT_EQ(d.slip_rate, (Wheels{4, 4, 4, 4}));
  d = DistributeSlips(SlipOperationMode::kAllTogether, SlipSelector::kMin, src);
  EXPECT_EQ(d.slip_rate, (Wheels{2, 2, 2, 2}));
  // Rear only.
  d = DistributeSlips(SlipOperationMode::kRearOnly, SlipSelector::kMax, src);
  EXPECT_EQ(d.slip, (Wheels{0.0, 0.0, 12.0, 12.0}));
  EXPECT_EQ(d.slip_angle_abs, (Wheels{0.0, 0.0, 0.04, 0.04}));
  EXPECT_EQ(d.slip_rate, (Wheels{0, 0, 4, 4}));
  // Ties go to the right wheel for the rate.
  const WheelSlipSignals tie{{-5.0, -5.0, 0.0, 0.0}, {}, {1, 2, 3, 4}};
  EXPECT_EQ(DistributeSlips(SlipOperationMode::kAxleSplit, SlipSelector::kMin, tie).slip_rate[kFL],
            2);
}

TEST(SlipDistributionTest, OperationModeParameterValues) {
  using M = SlipOperationMode;
  for (const M m : {M::kIndividual, M::kAxleSplit, M::kAllTogether, M::kRearOnly})
    EXPECT_EQ(SlipOperationModeFromInt(ToInt(m), M::kAxleSplit), m);
  EXPECT_EQ(ToInt(M::kRearOnly), 3);
  EXPECT_EQ(SlipOperationModeFromInt(-1, M::kAxleSplit), M::kAxleSplit);
  EXPECT_EQ(SlipOperationModeFromInt(4, M::kRearOnly), M::kRearOnly);
  params::StabilityParams p;
  p.SlipControl.ABS.operation_mode = 2;  // TC keeps rear only: its front thresholds stay unused
  const SlipControl sc(p);
  EXPECT_EQ(sc.abs_mode(), M::kAllTogether);
  EXPECT_EQ(sc.tc_mode(), M::kRearOnly);
}

class SlipControlTest : public ::testing::Test {
 protected:
  params::StabilityParams p_;
  SlipControl::Input Base(double t) const {
    SlipControl::Input in;
    in.slip_valid = true;
    in.fz = {2000.0, 2000.0, 2000.0, 2000.0};
    in.pressure_in = {30.0, 30.0, 20.0, 20.0};
    in.v_x = 30.0;
    in.t = t;
    in.gear = 3;
    in.gear_request = 3;
    in.throttle = 0.6;
    in.long_fx = -8000.0;
    return in;
  }
};

TEST_F(SlipControlTest, AbsLockupSelectsAbsOutputsAndReportsActive) {
  const SlipControl sc(p_);
  SlipControl::State s;
  SlipControl::Output out;
  double t = 1.0;
  for (int k = 0; k < 5; ++k, t += 0.01) out = sc.Step(Base(t), &s);
  EXPECT_FALSE(out.active);
  auto in = Base(t);
  in.slip_pct = {-15.0, -2.0, -1.0, -1.0};  // FL locks (slip falls: negative rate)
  out = sc.Step(in, &s);
  EXPECT_EQ(out.abs_phase[kFL], P::kHold);
  EXPECT_EQ(out.abs_phase[kFR], P::kInactive);  // mode 0: wheel individual
  EXPECT_TRUE(out.abs_latched);
  EXPECT_TRUE(out.active);
  EXPECT_LT(out.pressure[kFL], 30.0);
  EXPECT_EQ(out.pressure[kFR], 30.0);
}

TEST_F(SlipControlTest, TcRearSpinBrakesBothRearsInRearOnlyMode) {
  const SlipControl sc(p_);
  SlipControl::State s;
  double t = 1.0;
  SlipControl::Output out;
  // 30 steps: the first engaged-gear value blocks rear TC for 0.1 s (reference start-up quirk).
  for (int k = 0; k < 30; ++k, t += 0.01) {
    auto in = Base(t);
    in.long_fx = 3000.0;
    in.pressure_in = {0.0, 0.0, 0.0, 0.0};
    in.slip_pct = {0.0, 0.0, 20.0, 14.0};
    out = sc.Step(in, &s);
  }
  EXPECT_TRUE(out.tc_latched);
  EXPECT_EQ(out.tc_phase[kFL], P::kInactive);
  EXPECT_NE(out.tc_phase[kRL], P::kInactive);
  EXPECT_GT(out.pressure[kRL], 0.0);
  EXPECT_DOUBLE_EQ(out.pressure[kRL], out.pressure[kRR]);  // axle-weighted slip, one unit
  EXPECT_EQ(out.pressure[kFL], 0.0);
}

TEST_F(SlipControlTest, ZeroLongFxNeverActivatesTcAndOnlyEscTriggersAbs) {
  const SlipControl sc(p_);
  SlipControl::State s;
  double t = 1.0;
  SlipControl::Output out;
  for (int k = 0; k < 20; ++k, t += 0.01) {
    auto in = Base(t);
    in.long_fx = 0.0;  // the released node
    in.slip_pct = {-30.0 - k, -30.0 - k, 30.0, 30.0};
    out = sc.Step(in, &s);
    EXPECT_FALSE(out.active);
  }
  auto in = Base(t);
  in.long_fx = 0.0;
  in.esc_active = true;
  in.slip_pct = {-60.0, -60.0, 30.0, 30.0};
  out = sc.Step(in, &s);
  EXPECT_TRUE(out.abs_latched);
  EXPECT_FALSE(out.tc_latched);
}

TEST_F(SlipControlTest, ThrottleCutAboveMaxSlip) {
  const SlipControl sc(p_);
  SlipControl::State s;
  auto in = Base(1.0);
  in.slip_pct = {0.0, 0.0, 25.0, 25.0};
  EXPECT_EQ(sc.Step(in, &s).throttle, 0.6);  // ≤ 25 % keeps the throttle
  in.slip_pct = {0.0, 0.0, 27.0, 25.0};      // rear axle (load weighted) 26 %
  in.t += 0.01;
  const auto cut = sc.Step(in, &s);
  EXPECT_EQ(cut.throttle, 0.0);
  EXPECT_TRUE(cut.throttle_cut);
  in.slip_valid = false;
  in.t += 0.01;
  EXPECT_EQ(sc.Step(in, &s).throttle, 0.6);
  // Independent of TC.enabled.
  params::StabilityParams p = p_;
  p.SlipControl.TC.enabled = false;
  const SlipControl off(p);
  SlipControl::State s2;
  in.slip_valid = true;
  EXPECT_EQ(off.Step(in, &s2).throttle, 0.0);
}

TEST_F(SlipControlTest, GearShiftWindowReducesRearPressures) {
  const SlipControl sc(p_);
  SlipControl::State s;
  // Steady in gear 3 from t = 0 (the first step counts as a change: reference start-up quirk).
  int reduced_steps = 0;
  double first = -1.0;
  double last = -1.0;
  for (int k = 0; k < 100; ++k) {
    auto in = Base(0.01 * k);
    if (k >= 50) in.gear_request = 4;  // request changes at t = 0.50 s
    const auto out = sc.Step(in, &s);
    if (out.shift_reduction) {
      EXPECT_DOUBLE_EQ(out.pressure[kRL], 20.0 * 0.85);
      EXPECT_EQ(out.pressure[kFL], 30.0);
      if (k >= 50) {
        ++reduced_steps;
        if (first < 0) first = in.t;
        last = in.t;
      }
    }
  }
  // 150 ms < t − t_req < 200 ms: 0.66 … 0.69 s.
  EXPECT_EQ(reduced_steps, 4);
  EXPECT_NEAR(first, 0.66, 1e-9);
  EXPECT_NEAR(last, 0.69, 1e-9);
}

TEST_F(SlipControlTest, InitialGearQuirkAndOption) {
  auto count = [&](const params::StabilityOptions& o) {
    const SlipControl sc(p_, o);
    SlipControl::State s;
    int n = 0;
    for (int k = 0; k < 40; ++k) n += sc.Step(Base(0.01 * k), &s).shift_reduction ? 1 : 0;
    return n;
  };
  EXPECT_EQ(count({}), 4);  // reference: first gear value counts as a request change
  EXPECT_EQ(count({.ignore_initial_gear_change = true}), 0);
}

TEST_F(SlipControlTest, RearAbsBlockedAfterEngagedGearChange) {
  const SlipControl sc(p_, {.ignore_initial_gear_change = true});
  SlipControl::State s;
  for (int k = 0; k < 5; ++k) sc.Step(Base(1.0 + 0.01 * k), &s);
  auto in = Base(1.05);
  in.gear = 4;  // engaged gear changes now
  sc.Step(in, &s);
  in.t = 1.06;
  in.slip_pct = {-1.0, -1.0, -20.0, -20.0};
  auto out = sc.Step(in, &s);
  EXPECT_EQ(out.abs_phase[kRL], P::kInactive);  // 0.01 s < 0.1 s cooldown
  in.t = 1.20;
  in.slip_pct = {-1.0, -1.0, -30.0, -30.0};
  out = sc.Step(in, &s);
  EXPECT_NE(out.abs_phase[kRL], P::kInactive);
}

TEST(SlipControlConfigTest, WindowAboveCapacityIsRefused) {
  params::StabilityParams p;
  p.SlipControl.ABS.moving_average_fx_window_length = static_cast<int>(kMaxFxWindowLength) + 1;
  try {
    SlipControl sc(p);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("SlipControl.ABS.moving_average_fx_window_length"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace scw::controller
