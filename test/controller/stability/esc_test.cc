// ESC (spec §4): oversteer-only activation, speed gate, moment sign, the worked allocation
// example of §4.6, realised moment = demand unless clipped, and the global pressure clamp.
#include "controller/stability/esc.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "controller/stability/vehicle_model.h"

namespace scw::controller {
namespace {

constexpr double kMu = 0.35;

Wheels Mu() { return {kMu, kMu, kMu, kMu}; }

/// A steady slide: CoG speed v, sideslip β, yaw rate; ESC targets given directly.
Esc::Input Slide(double v, double beta, double yaw_rate, double yaw_rate_ref, double beta_ref) {
  Esc::Input in;
  in.v_x = v * std::cos(beta);
  in.v_y = v * std::sin(beta);
  in.yaw_rate = yaw_rate;
  in.yaw_rate_request = yaw_rate_ref;
  in.beta_request = beta_ref;
  in.pressure_in = {10.0, 10.0, 5.0, 5.0};
  in.mu = Mu();
  return in;
}

/// Runs n steps and returns the largest |M| and the last output.
double MaxMoment(const Esc& esc, const Esc::Input& in, int n, Esc::Output* last = nullptr) {
  Esc::State s;
  double m = 0.0;
  Esc::Output out;
  for (int k = 0; k < n; ++k) {
    out = esc.Step(in, &s);
    m = std::max(m, std::abs(out.yaw_moment));
  }
  if (last) *last = out;
  return m;
}

TEST(EscTest, WorkedAllocationExampleOfSpec46) {
  const params::StabilityParams p;
  const double k = WheelPressurePerForce(p.tires.front_left.radius.radius_20mps, p.vehicle.brake);
  EXPECT_NEAR(k, 0.0043790, 5e-7);
  const Wheels both = AllocateYawMoment(-800.0, {20.0, 20.0, 0.0, 0.0}, Mu(), k, 1.606, 80.0);
  EXPECT_NEAR(both[kFL], 13.77, 0.01);
  EXPECT_NEAR(both[kFR], 26.23, 0.01);
  EXPECT_EQ(both[kRL], 0.0);
  EXPECT_EQ(both[kRR], 0.0);
  const Wheels none = AllocateYawMoment(-800.0, {0.0, 0.0, 0.0, 0.0}, Mu(), k, 1.606, 80.0);
  EXPECT_NEAR(none[kFR], 12.46, 0.01);
  EXPECT_EQ(none[kFL], 0.0);
  // Mirror for a positive moment.
  const Wheels mirror = AllocateYawMoment(800.0, {20.0, 20.0, 0.0, 0.0}, Mu(), k, 1.606, 80.0);
  EXPECT_NEAR(mirror[kFL], 26.23, 0.01);
  EXPECT_NEAR(mirror[kFR], 13.77, 0.01);
}

/// Yaw moment produced by the pressure change on the front axle: braking the left wheel turns the
/// car left (M > 0).
double RealisedMoment(const Wheels& before, const Wheels& after, const Wheels& mu, double k,
                      double tw) {
  const double df_left = (after[kFL] - before[kFL]) * mu[kFL] / k;
  const double df_right = (after[kFR] - before[kFR]) * mu[kFR] / k;
  return 0.5 * tw * (df_left - df_right);
}

TEST(EscTest, RealisedMomentEqualsDemandUnlessClipped) {
  const params::StabilityParams p;
  const double k = WheelPressurePerForce(p.tires.front_left.radius.radius_20mps, p.vehicle.brake);
  const double tw = p.vehicle.dimension.trackwidth;
  const std::vector<Wheels> requests{
      {0, 0, 0, 0}, {20, 20, 8, 8}, {3, 40, 0, 0}, {40, 3, 0, 0}, {60, 60, 20, 20}};
  const std::vector<Wheels> mus{Mu(), {0.3, 0.45, 0.35, 0.35}, {0.5, 0.25, 0.4, 0.4}};
  for (const double m : {-2500.0, -800.0, -50.0, 50.0, 800.0, 2500.0}) {
    for (const auto& req : requests) {
      for (const auto& mu : mus) {
        const Wheels out = AllocateYawMoment(m, req, mu, k, tw, 80.0);
        EXPECT_EQ(out[kRL], req[kRL]);
        EXPECT_EQ(out[kRR], req[kRR]);
        const double realised = RealisedMoment(req, out, mu, k, tw);
        const bool clipped = out[kFL] >= 80.0 - 1e-9 || out[kFR] >= 80.0 - 1e-9;
        if (clipped) {
          EXPECT_LE(std::abs(realised), std::abs(m) + 1e-6);
          EXPECT_GT(realised * m, 0.0);
        } else {
          EXPECT_NEAR(realised, m, 1e-6 * std::max(1.0, std::abs(m)))
              << "M " << m << " req " << req[0] << "," << req[1];
        }
        EXPECT_GE(out[kFL], 0.0);
        EXPECT_GE(out[kFR], 0.0);
      }
    }
  }
}

TEST(EscTest, NoYawMomentInUndersteer) {
  const Esc esc(params::StabilityParams{});
  // Left turn, the car turns less than asked (ψ̇ < ψ̇_ref) and slides less than the reference:
  // large errors, but of the understeer sign.
  for (const double v : {10.0, 25.0, 50.0, 75.0}) {
    EXPECT_EQ(MaxMoment(esc, Slide(v, -0.01, 0.2, 0.6, -0.2), 300), 0.0) << v;
    EXPECT_EQ(MaxMoment(esc, Slide(v, 0.01, -0.2, -0.6, 0.2), 300), 0.0) << v;  // right turn
  }
}

TEST(EscTest, NoYawMomentBelowMinimumSpeed) {
  const Esc esc(params::StabilityParams{});
  EXPECT_EQ(MaxMoment(esc, Slide(6.9, -0.3, 1.0, 0.3, 0.0), 300), 0.0);
  EXPECT_GT(MaxMoment(esc, Slide(8.0, -0.3, 1.0, 0.3, 0.0), 300), 0.0);
}

TEST(EscTest, MomentSignForLeftAndRightOversteer) {
  const Esc esc(params::StabilityParams{});
  Esc::Output out;
  // Left-hand oversteer: ψ̇ > ψ̇_ref > 0, β < β_ref → M < 0, outer (right) front braked.
  ASSERT_GT(MaxMoment(esc, Slide(25.0, -0.12, 0.8, 0.4, 0.0), 60, &out), 0.0);
  EXPECT_TRUE(out.active);
  EXPECT_LT(out.yaw_moment, 0.0);
  EXPECT_GT(out.pressure[kFR], 10.0);
  EXPECT_LT(out.pressure[kFL], 10.0);
  // Right-hand oversteer: mirror.
  ASSERT_GT(MaxMoment(esc, Slide(25.0, 0.12, -0.8, -0.4, 0.0), 60, &out), 0.0);
  EXPECT_GT(out.yaw_moment, 0.0);
  EXPECT_GT(out.pressure[kFL], 10.0);
  EXPECT_LT(out.pressure[kFR], 10.0);
  EXPECT_EQ(out.pressure[kRL], 5.0);
}

TEST(EscTest, DisabledOrInvalidNeverActivates) {
  params::StabilityParams p;
  p.ESC.enabled = false;
  EXPECT_EQ(MaxMoment(Esc(p), Slide(25.0, -0.12, 0.8, 0.4, 0.0), 100), 0.0);
  auto in = Slide(25.0, -0.12, 0.8, 0.4, 0.0);
  in.slip_angle_valid = false;
  EXPECT_EQ(MaxMoment(Esc(params::StabilityParams{}), in, 100), 0.0);
}

TEST(EscTest, GlobalClampAppliesActiveOrNot) {
  for (const bool enabled : {true, false}) {
    params::StabilityParams p;
    p.ESC.enabled = enabled;
    const Esc esc(p);
    Esc::State s;
    Esc::Input in;
    in.v_x = 20.0;
    in.pressure_in = {100.0, -5.0, 90.0, 10.0};
    const auto out = esc.Step(in, &s);
    EXPECT_FALSE(out.active);
    EXPECT_EQ(out.pressure, (Wheels{80.0, 0.0, 80.0, 10.0}));
  }
}

TEST(EscTest, DeactivatesWhenAllThreeErrorsAreSmall) {
  const Esc esc(params::StabilityParams{});
  Esc::State s;
  for (int k = 0; k < 60; ++k) esc.Step(Slide(25.0, -0.12, 0.8, 0.4, 0.0), &s);
  ASSERT_EQ(s.phase, EscPhase::kActive);
  int steps = 0;
  while (s.phase == EscPhase::kActive && steps < 500) {
    esc.Step(Slide(25.0, -0.01, 0.4, 0.4, 0.0), &s);
    ++steps;
  }
  EXPECT_EQ(s.phase, EscPhase::kInactive);
  EXPECT_GT(steps, 1);                   // the filtered errors need time to decay
  EXPECT_EQ(s.pid_psi.integrator, 0.0);  // integrator reset while inactive
  EXPECT_EQ(esc.Step(Slide(25.0, -0.01, 0.4, 0.4, 0.0), &s).yaw_moment, 0.0);
}

// One row per edge of the activation state machine (step 4), each condition at its boundary and
// each oversteer sign condition failing alone.
struct EscRow {
  std::string name;
  EscPhase from;
  EscSignals sig;
  EscPhase expected;
};

EscSignals Sig(double beta, double yaw_rate, double e_psi, double e_beta, double speed = 20.0,
               bool enabled = true) {
  return {.enabled = enabled,
          .speed = speed,
          .beta = beta,
          .yaw_rate = yaw_rate,
          .e_psi = e_psi,
          .e_beta = e_beta};
}

std::vector<EscRow> Rows() {
  using P = EscPhase;
  // Left-hand oversteer slide: every activation condition met by a margin.
  const EscSignals over = Sig(-0.1, 0.5, -0.1, 0.1);
  // Every deactivation magnitude strictly below its threshold.
  const EscSignals small = Sig(-0.03, 0.5, -0.02, 0.01);
  return {
      // Inactive
      {"I_act_oversteer_left", P::kInactive, over, P::kActive},
      {"I_act_oversteer_right", P::kInactive, Sig(0.1, -0.5, 0.1, -0.1), P::kActive},
      {"I_no_act_disabled", P::kInactive, Sig(-0.1, 0.5, -0.1, 0.1, 20.0, false), P::kInactive},
      {"I_no_act_at_min_speed", P::kInactive, Sig(-0.1, 0.5, -0.1, 0.1, 7.0), P::kInactive},
      {"I_no_act_beta_at_threshold", P::kInactive, Sig(-0.03, 0.5, -0.1, 0.1), P::kInactive},
      {"I_no_act_beta_error_at_threshold", P::kInactive, Sig(-0.1, 0.5, -0.1, 0.06), P::kInactive},
      {"I_no_act_yaw_error_at_threshold", P::kInactive, Sig(-0.1, 0.5, -0.04, 0.1), P::kInactive},
      {"I_no_act_understeer_yaw_error", P::kInactive, Sig(-0.1, 0.5, 0.1, 0.1), P::kInactive},
      {"I_no_act_yaw_rate_sign", P::kInactive, Sig(-0.1, -0.5, -0.1, 0.1), P::kInactive},
      {"I_no_act_zero_yaw_rate", P::kInactive, Sig(-0.1, 0.0, -0.1, 0.1), P::kInactive},
      {"I_no_act_beta_sign", P::kInactive, Sig(0.1, 0.5, -0.1, 0.1), P::kInactive},
      {"I_no_act_error_signs_agree", P::kInactive, Sig(0.1, 0.5, -0.1, -0.1), P::kInactive},
      // Active
      {"A_deact_disabled", P::kActive, Sig(-0.1, 0.5, -0.1, 0.1, 20.0, false), P::kInactive},
      {"A_deact_below_min_speed", P::kActive, Sig(-0.1, 0.5, -0.1, 0.1, 6.9), P::kInactive},
      {"A_stay_at_min_speed", P::kActive, Sig(-0.1, 0.5, -0.1, 0.1, 7.0), P::kActive},
      {"A_deact_all_small", P::kActive, small, P::kInactive},
      {"A_deact_all_small_any_sign", P::kActive, Sig(0.03, 0.5, 0.02, 0.01), P::kInactive},
      {"A_stay_beta_at_threshold", P::kActive, Sig(-0.035, 0.5, -0.02, 0.01), P::kActive},
      {"A_stay_beta_error_large", P::kActive, Sig(-0.03, 0.5, -0.02, 0.02), P::kActive},
      {"A_stay_yaw_error_at_threshold", P::kActive, Sig(-0.03, 0.5, -0.026, 0.01), P::kActive},
      {"A_stay_oversteer", P::kActive, over, P::kActive},
  };
}

std::string RowName(const ::testing::TestParamInfo<EscRow>& row) { return row.param.name; }

class EscTransitionTest : public ::testing::TestWithParam<EscRow> {};

// The thresholds the boundary rows are written against.
EscThresholds RowThresholds() {
  return {.beta_activate = 0.03,
          .psi_dot_error_activate = 0.04,
          .beta_error_activate = 0.06,
          .beta_deactivate = 0.035,
          .psi_dot_error_deactivate = 0.026,
          .beta_error_deactivate = 0.018,
          .min_velocity = 7.0};
}

TEST_P(EscTransitionTest, Edge) {
  const EscThresholds th = RowThresholds();
  const EscRow& row = GetParam();
  EXPECT_EQ(NextEscPhase(row.from, row.sig, th), row.expected);
}

INSTANTIATE_TEST_SUITE_P(Boundaries, EscTransitionTest, ::testing::ValuesIn(Rows()), RowName);

// The activation margin (a diagnostic) agrees with the activation condition of an inactive ESC on
// every boundary row with E set: > 1 exactly where it activates (the margin ignores E, the
// transition needs it). Its value is the smallest ratio of a magnitude to its threshold, 0 without
// the oversteer signs or at the speed gate, and a non-positive threshold counts as met.
TEST(EscTest, ActivationMarginIsTheSmallestRatioAndAgreesWithActivation) {
  const EscThresholds th = RowThresholds();
  for (const EscRow& row : Rows()) {
    if (row.from != EscPhase::kInactive || !row.sig.enabled) continue;
    const double m = EscActivationMargin(row.sig, th);
    EXPECT_EQ(m > 1.0, row.expected == EscPhase::kActive) << row.name << " margin " << m;
  }
  // |β|/B_a = 0.5, |e_β|/Eβ_a = 2/3, |e_ψ|/Eψ_a = 0.75: the β term decides.
  EXPECT_DOUBLE_EQ(EscActivationMargin(Sig(-0.015, 0.5, -0.03, 0.04), th), 0.5);
  EXPECT_EQ(EscActivationMargin(Sig(-0.015, 0.5, 0.03, 0.04), th), 0.0);        // understeer
  EXPECT_EQ(EscActivationMargin(Sig(-0.015, 0.5, -0.03, 0.04, 7.0), th), 0.0);  // speed gate
  EXPECT_EQ(EscActivationMargin(Sig(-0.1, 0.5, -0.1, 0.1, 20.0, false), th),
            EscActivationMargin(Sig(-0.1, 0.5, -0.1, 0.1), th));  // E ignored
  EscThresholds extrapolated = th;
  extrapolated.beta_activate = -0.004;  // above 74.7 m/s with the shipped arrays
  EXPECT_DOUBLE_EQ(EscActivationMargin(Sig(-0.001, 0.5, -0.03, 0.04), extrapolated), 0.04 / 0.06);
  extrapolated.psi_dot_error_activate = 0.0;
  extrapolated.beta_error_activate = -1.0;
  EXPECT_EQ(EscActivationMargin(Sig(-0.001, 0.5, -0.03, 0.04), extrapolated), kMaxEscMargin);
}

// The margin's three terms one by one: each magnitude over its own threshold, all 0 without the
// oversteer signs or at the speed gate, capped, a non-positive threshold counting as met; the
// margin is their smallest.
TEST(EscTest, ActivationRatiosAreTheTermsOfTheMargin) {
  const EscThresholds th = RowThresholds();
  const EscActivationTerms t = EscActivationRatios(Sig(-0.015, 0.5, -0.03, 0.04), th);
  EXPECT_DOUBLE_EQ(t.beta, 0.5);
  EXPECT_DOUBLE_EQ(t.beta_error, 0.04 / 0.06);
  EXPECT_DOUBLE_EQ(t.yaw_rate_error, 0.75);
  for (const EscRow& row : Rows()) {
    const EscActivationTerms r = EscActivationRatios(row.sig, th);
    EXPECT_EQ(EscActivationMargin(row.sig, th), std::min({r.beta, r.beta_error, r.yaw_rate_error}))
        << row.name;
  }
  const EscActivationTerms under = EscActivationRatios(Sig(-0.015, 0.5, 0.03, 0.04), th);
  EXPECT_EQ(under.beta + under.beta_error + under.yaw_rate_error, 0.0);  // understeer
  const EscActivationTerms slow = EscActivationRatios(Sig(-0.015, 0.5, -0.03, 0.04, 7.0), th);
  EXPECT_EQ(slow.beta + slow.beta_error + slow.yaw_rate_error, 0.0);  // speed gate
  EXPECT_EQ(EscActivationRatios(Sig(-3.0, 50.0, -3.0, 0.04), th).beta, kMaxEscMargin);  // capped
  EscThresholds extrapolated = th;
  extrapolated.beta_activate = -0.004;
  EXPECT_EQ(EscActivationRatios(Sig(-0.001, 0.5, -0.03, 0.04), extrapolated).beta, kMaxEscMargin);
}

TEST(EscTest, ReferencesFromAyRequestOrSingleTrack) {
  const EscReferenceModel m;
  const double nan = std::nan("");
  const EscReference ay = EscReferences(20.0, 0.1, 4.0, nan, nan, m);
  EXPECT_DOUBLE_EQ(ay.curvature, 4.0 / 400.0);
  EXPECT_DOUBLE_EQ(ay.yaw_rate, 0.01 * 20.0);
  EXPECT_DOUBLE_EQ(
      ay.beta, 0.01 * (m.l_rear - m.l_front * m.mass * 400.0 / (m.stiffness_rear * m.wheelbase)));
  EXPECT_DOUBLE_EQ(EscReferences(1.0, 0.1, 4.0, nan, nan, m).curvature, 4.0 / 9.0);  // max(v, 3)
  const EscReference st = EscReferences(20.0, 0.05, nan, nan, nan, m);
  const double under = m.mass * 400.0 *
                       (m.l_rear * m.stiffness_rear - m.l_front * m.stiffness_front) /
                       (m.stiffness_front * m.stiffness_rear * m.wheelbase);
  EXPECT_DOUBLE_EQ(st.curvature, 0.05 / (m.wheelbase + under));
  const EscReference given = EscReferences(20.0, 0.05, 4.0, 0.3, -0.02, m);
  EXPECT_EQ(given.yaw_rate, 0.3);
  EXPECT_EQ(given.beta, -0.02);
}

}  // namespace
}  // namespace scw::controller
