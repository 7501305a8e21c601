// ABS wheel controller (spec §3.3, §3.4): one table row per edge of the transition table with the
// shipped front thresholds (λ_hr −10, λ_rh −12, λ_hi −25, λ_ih −15, λ_safe −7 %, F_min −2500 N),
// the ε actions, and the wheel-controller invariants (pressure never above the request, latch
// drop, target increase, safety limiter).
#include "controller/stability/abs.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "controller/stability/vehicle_model.h"

namespace scw::controller {
namespace {

using P = SlipPhase;
using A = AbsAction;

struct AbsRow {
  std::string name;
  P from;
  AbsSignals sig;
  AbsTransition expected;
};

AbsSignals Sig(double slip, double rate, double fx, bool esp_trigger = false, double epsilon = 0.7,
               bool esc = false, bool allowed = true, double r = 1.0) {
  return {.slip = slip,
          .slip_rate = rate,
          .scale = r,
          .long_fx = fx,
          .esc_active = esc,
          .esp_trigger = esp_trigger,
          .allowed = allowed,
          .epsilon = epsilon};
}

constexpr double kBrake = -5000.0;  // F < F_min − 100

std::vector<AbsRow> Rows() {
  return {
      // Inactive
      {"I_act_at_threshold", P::kInactive, Sig(-10.0, -1.0, kBrake), {P::kHold, A::kLatch}},
      {"I_act_via_esc",
       P::kInactive,
       Sig(-11.0, -1.0, 0.0, false, 0.0, true),
       {P::kHold, A::kLatch}},
      {"I_act_scaled_threshold",
       P::kInactive,
       Sig(-7.5, -1.0, kBrake, false, 0.0, false, true, 0.7),
       {P::kHold, A::kLatch}},
      {"I_no_act_slip_above", P::kInactive, Sig(-9.99, -1.0, kBrake), {P::kInactive, A::kNone}},
      {"I_no_act_rate_zero", P::kInactive, Sig(-20.0, 0.0, kBrake), {P::kInactive, A::kNone}},
      {"I_no_act_force_hysteresis",
       P::kInactive,
       Sig(-20.0, -1.0, -2550.0),
       {P::kInactive, A::kNone}},
      {"I_no_act_not_allowed",
       P::kInactive,
       Sig(-20.0, -1.0, kBrake, false, 0.0, false, false),
       {P::kInactive, A::kNone}},
      // Hold
      {"H_deact_force", P::kHold, Sig(-20.0, -1.0, -2400.0), {P::kInactive, A::kNone}},
      {"H_deact_esp_slip_recovered",
       P::kHold,
       Sig(-9.0, -1.0, kBrake, true),
       {P::kInactive, A::kNone}},
      {"H_deact_not_allowed",
       P::kHold,
       Sig(-20.0, -1.0, kBrake, false, 0.7, false, false),
       {P::kInactive, A::kNone}},
      {"H_no_deact_esp_ignores_force", P::kHold, Sig(-11.0, 0.0, 0.0, true), {P::kHold, A::kNone}},
      {"H_to_reduce", P::kHold, Sig(-11.0, -1.0, kBrake), {P::kReduce, A::kReduceStep}},
      {"H_to_increase", P::kHold, Sig(-20.0, 1.0, kBrake), {P::kIncrease, A::kEnterIncrease}},
      {"H_stay_rate_zero", P::kHold, Sig(-11.0, 0.0, kBrake), {P::kHold, A::kNone}},
      {"H_stay_at_hr_falling", P::kHold, Sig(-10.0, -1.0, kBrake), {P::kHold, A::kNone}},
      {"H_stay_deep_rising", P::kHold, Sig(-25.0, 1.0, kBrake), {P::kHold, A::kNone}},
      // Reduce
      {"R_deact", P::kReduce, Sig(-20.0, -1.0, -2400.0), {P::kInactive, A::kNone}},
      {"R_to_increase", P::kReduce, Sig(-20.0, 1.0, kBrake), {P::kIncrease, A::kEnterIncrease}},
      {"R_to_hold_rising_deep", P::kReduce, Sig(-30.0, 1.0, kBrake), {P::kHold, A::kNone}},
      {"R_to_hold_above_rh", P::kReduce, Sig(-11.0, -1.0, kBrake), {P::kHold, A::kNone}},
      {"R_stay", P::kReduce, Sig(-13.0, -1.0, kBrake), {P::kReduce, A::kReduceStep}},
      {"R_stay_at_rh", P::kReduce, Sig(-12.0, 0.0, kBrake), {P::kReduce, A::kReduceStep}},
      // Increase
      {"N_deact", P::kIncrease, Sig(-20.0, -1.0, -2400.0), {P::kInactive, A::kNone}},
      {"N_to_reduce_caps_epsilon",
       P::kIncrease,
       Sig(-11.0, -1.0, kBrake, false, 1.2),
       {P::kReduce, A::kCapToInitial}},
      {"N_to_hold_falling", P::kIncrease, Sig(-8.0, -1.0, kBrake), {P::kHold, A::kNone}},
      {"N_to_hold_below_ih", P::kIncrease, Sig(-16.0, 1.0, kBrake), {P::kHold, A::kNone}},
      {"N_target_increase_safe",
       P::kIncrease,
       Sig(-5.0, 0.0, kBrake, false, 1.0),
       {P::kIncrease, A::kTargetIncrease}},
      {"N_target_increase_rising",
       P::kIncrease,
       Sig(-8.0, 1.0, kBrake, false, 1.0),
       {P::kIncrease, A::kTargetIncrease}},
      {"N_hold_epsilon_saturated",
       P::kIncrease,
       Sig(-13.0, 0.0, kBrake, false, 1.0),
       {P::kIncrease, A::kNone}},
      {"N_increase_step",
       P::kIncrease,
       Sig(-5.0, 0.0, kBrake, false, 0.8),
       {P::kIncrease, A::kIncreaseStep}},
      {"N_increase_step_at_0999",
       P::kIncrease,
       Sig(-5.0, 0.0, kBrake, false, 0.999),
       {P::kIncrease, A::kIncreaseStep}},
  };
}

std::string RowName(const ::testing::TestParamInfo<AbsRow>& row) { return row.param.name; }

class AbsTransitionTest : public ::testing::TestWithParam<AbsRow> {};

TEST_P(AbsTransitionTest, Edge) {
  const params::AbsParams abs;
  const AbsRow& row = GetParam();
  EXPECT_EQ(NextAbsPhase(row.from, row.sig, abs.front, abs.min_long_force), row.expected);
}

INSTANTIATE_TEST_SUITE_P(ShippedFront, AbsTransitionTest, ::testing::ValuesIn(Rows()), RowName);

TEST(AbsActionTest, EpsilonUpdates) {
  const params::AbsAxleParams a;  // ε_R0 0.7, ε_I0 0.45, Δ_R 0.038, Δ_I 0.023, Δ_T 0.015
  EXPECT_DOUBLE_EQ(ApplyAbsAction(A::kLatch, 0.1, 1.0, a, false), 0.7);
  EXPECT_DOUBLE_EQ(ApplyAbsAction(A::kReduceStep, 0.5, 0.5, a, false), 0.5 - 0.5 * 0.038);
  EXPECT_DOUBLE_EQ(ApplyAbsAction(A::kReduceStep, 0.01, 1.0, a, false), 0.0);
  EXPECT_DOUBLE_EQ(ApplyAbsAction(A::kIncreaseStep, 0.5, 0.5, a, false), 0.523);
  EXPECT_DOUBLE_EQ(ApplyAbsAction(A::kIncreaseStep, 0.5, 0.5, a, true), 0.5 + 0.5 * 0.023);
  EXPECT_DOUBLE_EQ(ApplyAbsAction(A::kIncreaseStep, 0.99, 1.0, a, false), 1.0);
  EXPECT_DOUBLE_EQ(ApplyAbsAction(A::kEnterIncrease, 0.2, 1.0, a, false), 0.45);
  EXPECT_DOUBLE_EQ(ApplyAbsAction(A::kEnterIncrease, 0.6, 1.0, a, false), 0.623);
  EXPECT_DOUBLE_EQ(ApplyAbsAction(A::kEnterIncrease, 1.3, 1.0, a, false), 1.0);
  EXPECT_DOUBLE_EQ(ApplyAbsAction(A::kCapToInitial, 1.2, 1.0, a, false), 0.7);
  EXPECT_DOUBLE_EQ(ApplyAbsAction(A::kCapToInitial, 0.3, 1.0, a, false), 0.3);
  // Target increase has no upper clamp: ε may exceed 1.
  EXPECT_DOUBLE_EQ(ApplyAbsAction(A::kTargetIncrease, 1.0, 1.0, a, false), 1.015);
  EXPECT_DOUBLE_EQ(ApplyAbsAction(A::kTargetIncrease, 1.2, 0.5, a, true), 1.2 + 0.5 * 0.015);
  EXPECT_DOUBLE_EQ(ApplyAbsAction(A::kNone, 0.42, 1.0, a, false), 0.42);
}

TEST(AbsActionTest, ScaleAndError) {
  EXPECT_DOUBLE_EQ(ThresholdScale(0.0, 0.07, 0.3), 1.0);
  EXPECT_DOUBLE_EQ(ThresholdScale(0.035, 0.07, 0.3), 0.85);
  EXPECT_DOUBLE_EQ(ThresholdScale(0.2, 0.07, 0.3), 0.7);    // saturates (Appendix B: 0.7…1)
  EXPECT_DOUBLE_EQ(ThresholdScale(0.2, 0.07, 0.48), 0.52);  // TC: 0.52…1
  EXPECT_DOUBLE_EQ(NormalisedSlipError(-15.0, -10.0), 0.5);
  EXPECT_DOUBLE_EQ(NormalisedSlipError(-10.5, -10.0), 0.1);  // floor
  EXPECT_DOUBLE_EQ(NormalisedSlipError(-40.0, -10.0), 1.0);  // ceiling
}

// ---- Wheel controller ----

class AbsWheelTest : public ::testing::Test {
 protected:
  params::StabilityParams p_;
  AbsWheelController::Input In(double slip, double rate, double p_in = 40.0,
                               double fx = -6000.0) const {
    const double k =
        AxlePressurePerForce(p_.tires.front_left.radius.radius_20mps, p_.vehicle.brake) / 0.35 *
        0.5;
    return {.allowed = true,
            .slip = slip,
            .slip_angle_abs = 0.0,
            .slip_rate = rate,
            .pressure_in = p_in,
            .mu = 0.35,
            .pressure_per_force = k,
            .long_fx = fx,
            .esc_active = false,
            .v_x = 30.0};
  }
};

TEST_F(AbsWheelTest, InactivePassesRequestThrough) {
  const AbsWheelController abs(p_, true);
  AbsWheelController::State s;
  const auto out = abs.Step(In(-2.0, -1.0), &s);
  EXPECT_EQ(s.phase, P::kInactive);
  EXPECT_EQ(out.pressure, 40.0);
  EXPECT_EQ(out.force_target, -6000.0);
}

TEST_F(AbsWheelTest, LatchDropsPressureToRfTimesInitialRatio) {
  const AbsWheelController abs(p_, true);
  AbsWheelController::State s;
  // Request force and pressure consistent: p_lat = k_w·|F_lat| → force form = ratio form.
  auto in = In(-12.0, -100.0);
  in.pressure_in = in.pressure_per_force * 6000.0;
  s.mu_prev = 0.35;
  const auto out = abs.Step(in, &s);
  EXPECT_EQ(s.phase, P::kHold);
  EXPECT_DOUBLE_EQ(s.epsilon, 0.7);
  EXPECT_FALSE(s.esp_trigger);
  EXPECT_DOUBLE_EQ(s.f_latched, -6000.0);
  EXPECT_NEAR(out.pressure, 0.9 * 0.7 * in.pressure_in, 1e-9);
  EXPECT_NEAR(out.force_target, 0.9 * 0.7 * -6000.0, 1e-9);
}

TEST_F(AbsWheelTest, OutputNeverExceedsRequestAndTargetIncreaseFollowsRisingRequest) {
  const AbsWheelController abs(p_, true);
  AbsWheelController::State s;
  s.mu_prev = 0.35;
  abs.Step(In(-12.0, -100.0), &s);  // latch at 40 bar
  ASSERT_EQ(s.phase, P::kHold);
  // Slip recovers while rising: Hold → Increase, then ε climbs to 1 and beyond (target increase).
  double last = 0.0;
  for (int k = 0; k < 200; ++k) {
    const double p_in = 40.0 + 0.2 * k;  // request keeps rising
    const auto out = abs.Step(In(-5.0, 10.0, p_in, -6000.0 - 30.0 * k), &s);
    EXPECT_LE(out.pressure, p_in);
    last = out.pressure;
  }
  EXPECT_EQ(s.phase, P::kIncrease);
  EXPECT_GT(s.epsilon, 1.0);  // target-increase path taken
  EXPECT_GT(last, 40.0);      // the output follows the request above the latched level
}

TEST_F(AbsWheelTest, SafetyLimiterKeepsTheMinimumBrakingFraction) {
  params::StabilityParams p = p_;
  p.SlipControl.ABS.moving_average_fx_window_length = 5;
  const AbsWheelController abs(p, true);
  AbsWheelController::State s;
  s.mu_prev = 0.35;
  const double fx = -6000.0;
  abs.Step(In(-12.0, -100.0, 40.0, fx), &s);
  bool safety_seen = false;
  for (int k = 0; k < 200; ++k) {
    // Slip stays deep and falling: Reduce keeps lowering ε towards 0.
    const auto out = abs.Step(In(-30.0, -1.0, 40.0, fx), &s);
    if (out.safety_active) {
      safety_seen = true;
      EXPECT_DOUBLE_EQ(out.force_target,
                       std::min(0.4 * fx, s.epsilon * out.target_reduction * s.f_latched));
    }
  }
  EXPECT_TRUE(safety_seen);
  EXPECT_EQ(s.phase, P::kReduce);
  EXPECT_DOUBLE_EQ(s.epsilon, 0.0);
}

TEST_F(AbsWheelTest, TargetReductionFollowsDownforceLoss) {
  const AbsWheelController abs(p_, true);
  AbsWheelController::State s;
  s.mu_prev = 0.35;
  auto in = In(-12.0, -100.0);
  in.v_x = 60.0;
  abs.Step(in, &s);  // latched at 60 m/s
  in = In(-11.0, 0.0);
  in.v_x = 30.0;
  const auto out = abs.Step(in, &s);
  const double c = -0.5 * 1.22 * 1.0 * -1.65;
  const double fz_lat = 800.0 * 9.81 + c * 3600.0;
  EXPECT_NEAR(out.target_reduction, 0.9 * (1.0 - c * (3600.0 - 900.0) / fz_lat), 1e-12);
  EXPECT_LT(out.target_reduction, 0.9);
}

TEST_F(AbsWheelTest, EscTriggeredUsesRatioFormAndEndsWhenSlipRecovers) {
  const AbsWheelController abs(p_, true);
  AbsWheelController::State s;
  s.mu_prev = 0.35;
  auto in = In(-11.0, -1.0, 30.0, 0.0);
  in.esc_active = true;
  auto out = abs.Step(in, &s);
  ASSERT_EQ(s.phase, P::kHold);
  EXPECT_TRUE(s.esp_trigger);
  EXPECT_NEAR(out.pressure, 0.9 * 0.7 * 30.0, 1e-9);
  in.slip = -9.0;
  out = abs.Step(in, &s);
  EXPECT_EQ(s.phase, P::kInactive);
  EXPECT_EQ(out.pressure, 30.0);
}

TEST_F(AbsWheelTest, FrictionChangeRescalesLatchedPressure) {
  const AbsWheelController abs(p_, true);
  AbsWheelController::State s;
  s.mu_prev = 0.35;
  abs.Step(In(-12.0, -100.0), &s);
  const double p_lat = s.p_latched;
  auto in = In(-11.0, 0.0);
  in.mu = 0.7;
  abs.Step(in, &s);
  EXPECT_DOUBLE_EQ(s.p_latched, 0.5 * p_lat);
}

}  // namespace
}  // namespace scw::controller
