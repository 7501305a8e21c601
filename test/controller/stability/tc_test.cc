// TC wheel controller (spec §3.5): one table row per edge of the transition table with the
// shipped rear thresholds (λ_hr 8, λ_rh 9, λ_hi 15, λ_ih 12, λ_safe 6 %, T_deact 0.5 s), the ε
// actions and the wheel-controller behaviour (simulation-time time-out, force compensation,
// pressure formula).
#include "controller/stability/tc.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "controller/stability/vehicle_model.h"

namespace scw::controller {
namespace {

using P = SlipPhase;
using A = TcAction;

struct TcRow {
  std::string name;
  P from;
  TcSignals sig;
  TcTransition expected;
};

TcSignals Sig(double slip, double rate, double since = 0.0, double fx = 3000.0, bool allowed = true,
              double r = 1.0) {
  return {.slip = slip,
          .slip_rate = rate,
          .scale = r,
          .long_fx = fx,
          .allowed = allowed,
          .time_since_exceed = since};
}

std::vector<TcRow> Rows() {
  return {
      // Inactive
      {"I_act_at_threshold", P::kInactive, Sig(8.0, 0.0), {P::kHold, A::kLatch}},
      {"I_act_scaled", P::kInactive, Sig(4.5, 0.0, 0.0, 3000.0, true, 0.52), {P::kHold, A::kLatch}},
      {"I_no_act_below", P::kInactive, Sig(7.99, 5.0), {P::kInactive, A::kNone}},
      {"I_no_act_no_drive", P::kInactive, Sig(20.0, 5.0, 0.0, 0.0), {P::kInactive, A::kNone}},
      {"I_no_act_not_allowed",
       P::kInactive,
       Sig(20.0, 5.0, 0.0, 3000.0, false),
       {P::kInactive, A::kNone}},
      // Hold
      {"H_deact_timeout", P::kHold, Sig(10.0, 0.0, 0.51), {P::kInactive, A::kNone}},
      {"H_no_deact_at_timeout", P::kHold, Sig(10.0, 0.0, 0.5), {P::kHold, A::kNone}},
      {"H_deact_not_allowed",
       P::kHold,
       Sig(10.0, 0.0, 0.0, 3000.0, false),
       {P::kInactive, A::kNone}},
      {"H_to_reduce", P::kHold, Sig(8.5, 1.0), {P::kReduce, A::kReduceStep}},
      {"H_to_increase", P::kHold, Sig(15.0, -1.0), {P::kIncrease, A::kIncreaseStep}},
      {"H_stay", P::kHold, Sig(10.0, 0.0), {P::kHold, A::kNone}},
      {"H_stay_high_falling", P::kHold, Sig(16.0, -1.0), {P::kHold, A::kNone}},
      // Reduce
      {"R_deact", P::kReduce, Sig(10.0, 1.0, 0.6), {P::kInactive, A::kNone}},
      {"R_to_increase", P::kReduce, Sig(10.0, -1.0), {P::kIncrease, A::kIncreaseStep}},
      {"R_to_hold_falling_high", P::kReduce, Sig(20.0, -1.0), {P::kHold, A::kNone}},
      {"R_to_hold_below_rh", P::kReduce, Sig(8.5, 0.0), {P::kHold, A::kNone}},
      {"R_stay", P::kReduce, Sig(10.0, 1.0), {P::kReduce, A::kReduceStep}},
      {"R_stay_at_rh", P::kReduce, Sig(9.0, 0.0), {P::kReduce, A::kReduceStep}},
      // Increase
      {"N_deact", P::kIncrease, Sig(10.0, 1.0, 0.6), {P::kInactive, A::kNone}},
      {"N_to_reduce", P::kIncrease, Sig(8.5, 1.0), {P::kReduce, A::kCapToInitial}},
      {"N_to_hold_high", P::kIncrease, Sig(13.0, -1.0), {P::kHold, A::kNone}},
      {"N_to_hold_rising_low", P::kIncrease, Sig(7.0, 1.0), {P::kHold, A::kNone}},
      {"N_stay", P::kIncrease, Sig(10.0, -1.0), {P::kIncrease, A::kIncreaseStep}},
      {"N_stay_below_safe", P::kIncrease, Sig(5.0, 1.0), {P::kIncrease, A::kIncreaseStep}},
  };
}

std::string RowName(const ::testing::TestParamInfo<TcRow>& row) { return row.param.name; }

class TcTransitionTest : public ::testing::TestWithParam<TcRow> {};

TEST_P(TcTransitionTest, Edge) {
  const params::TcParams tc;
  const TcRow& row = GetParam();
  EXPECT_EQ(NextTcPhase(row.from, row.sig, tc.rear, tc.deactivation_duration), row.expected);
}

INSTANTIATE_TEST_SUITE_P(ShippedRear, TcTransitionTest, ::testing::ValuesIn(Rows()), RowName);

TEST(TcActionTest, EpsilonUpdates) {
  const params::TcAxleParams a;  // ε_R0 0.82, Δ_R 0.04, Δ_I 0.018
  EXPECT_DOUBLE_EQ(ApplyTcAction(A::kLatch, 0.0, 1.0, a, false), 0.82);
  EXPECT_DOUBLE_EQ(ApplyTcAction(A::kReduceStep, 0.5, 0.5, a, false), 0.48);
  EXPECT_DOUBLE_EQ(ApplyTcAction(A::kReduceStep, 0.01, 1.0, a, false), 0.0);
  EXPECT_DOUBLE_EQ(ApplyTcAction(A::kIncreaseStep, 0.5, 0.5, a, false), 0.518);
  EXPECT_DOUBLE_EQ(ApplyTcAction(A::kIncreaseStep, 0.5, 0.5, a, true), 0.509);
  EXPECT_DOUBLE_EQ(ApplyTcAction(A::kIncreaseStep, 0.99, 1.0, a, false), 1.0);
  EXPECT_DOUBLE_EQ(ApplyTcAction(A::kCapToInitial, 0.9, 1.0, a, false), 0.82);
  EXPECT_DOUBLE_EQ(ApplyTcAction(A::kCapToInitial, 0.3, 1.0, a, false), 0.3);
}

class TcWheelTest : public ::testing::Test {
 protected:
  params::StabilityParams p_;
  double k_ = AxlePressurePerForce(p_.tires.rear_left.radius.radius_20mps, p_.vehicle.brake) /
              0.35 * (1.0 - 0.5);
  TcWheelController::Input In(double slip, double t, double fx = 4000.0) const {
    return {.allowed = true,
            .slip = slip,
            .slip_angle_abs = 0.0,
            .pressure_in = 0.0,
            .pressure_per_force = k_,
            .long_fx = fx,
            .t = t};
  }
};

TEST_F(TcWheelTest, FilteredSlipActivatesAndBrakesTheRetainedForceDifference) {
  const TcWheelController tc(p_, false);
  TcWheelController::State s;
  double t = 0.0;
  TcWheelController::Output out;
  int steps = 0;
  while (s.phase == P::kInactive && steps < 50) {
    out = tc.Step(In(20.0, t), &s);
    t += 0.01;
    ++steps;
  }
  ASSERT_EQ(s.phase, P::kHold);
  // LPF(0.8) of a 20 % step: 4, 7.2, 9.76 % → active in the third step (≥ 8 %).
  EXPECT_EQ(steps, 3);
  EXPECT_DOUBLE_EQ(s.epsilon, 0.82);
  EXPECT_NEAR(out.pressure, k_ * (4000.0 - 0.82 * 4000.0), 1e-12);
  EXPECT_NEAR(out.force_target, 0.82 * 4000.0, 1e-9);
}

TEST_F(TcWheelTest, DeactivatesByTimeoutInSimulationTime) {
  const TcWheelController tc(p_, false);
  TcWheelController::State s;
  double t = 100.0;  // absolute time does not matter, only differences
  for (int k = 0; k < 10; ++k, t += 0.01) tc.Step(In(20.0, t), &s);
  ASSERT_NE(s.phase, P::kInactive);
  const double last_exceed = s.t_exceed;
  // Slip drops to 0: the filtered slip falls below 8 % after a few steps; deactivation exactly
  // when more than 0.5 s have passed since the last exceedance.
  double t_off = 0.0;
  for (int k = 0; k < 200 && s.phase != P::kInactive; ++k, t += 0.01) {
    tc.Step(In(0.0, t), &s);
    t_off = t;
  }
  EXPECT_EQ(s.phase, P::kInactive);
  EXPECT_GT(t_off - s.t_exceed, 0.5);
  EXPECT_LE(t_off - 0.01 - s.t_exceed, 0.5 + 1e-9);
  EXPECT_GE(s.t_exceed, last_exceed);
}

TEST_F(TcWheelTest, DriveForceChangeKeepsTheAbsoluteReduction) {
  const TcWheelController tc(p_, false);
  TcWheelController::State s;
  s.phase = P::kHold;
  s.epsilon = 0.8;
  s.force_prev = 4000.0;
  s.t_exceed = 0.0;
  s.slip_filtered = 10.0;
  tc.Step(In(10.0, 0.01, 2000.0), &s);  // Hold, stays Hold (rate 0)
  ASSERT_EQ(s.phase, P::kHold);
  // (1 − ε)·F constant: 0.2·4000 = 800 = (1 − ε')·2000 → ε' = 0.6.
  EXPECT_NEAR(s.epsilon, 0.6, 1e-12);
}

TEST_F(TcWheelTest, BrakingRequestPassesThrough) {
  const TcWheelController tc(p_, false);
  TcWheelController::State s;
  s.phase = P::kHold;
  s.epsilon = 0.5;
  s.t_exceed = 0.0;
  auto in = In(10.0, 0.01, -3000.0);
  in.pressure_in = 12.0;
  const auto out = tc.Step(in, &s);
  EXPECT_EQ(out.pressure, 12.0);
  EXPECT_EQ(out.force_target, -3000.0);
}

}  // namespace
}  // namespace scw::controller
