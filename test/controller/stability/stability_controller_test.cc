// The composed stability controller (spec §1.3): transparent cruise, episodes that trigger each
// subsystem, release-compatible long_fx, robustness to NaN/inf/missing inputs, ablation over every
// enable combination and determinism.
#include "controller/stability/stability_controller.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "test/controller/stability/scenario_inputs.h"

namespace scw::controller {
namespace {

using testing::Cruise;
using testing::Lockup;
using testing::Oversteer;
using testing::RearSpin;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

static_assert(noexcept(std::declval<const StabilityController&>().Step(
    std::declval<const StabilityInput&>(), std::declval<StabilityController::State*>())));
static_assert(std::is_trivially_copyable_v<StabilityController::State>);

bool AnyActive(const PerWheel<SlipPhase>& phases) {
  for (auto ph : phases)
    if (IsActive(ph)) return true;
  return false;
}

void ExpectFinite(const StabilityOutput& o) {
  EXPECT_TRUE(std::isfinite(o.steering));
  EXPECT_TRUE(std::isfinite(o.throttle));
  EXPECT_TRUE(std::isfinite(o.yaw_moment));
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_TRUE(std::isfinite(o.brake_bar[i]));
    EXPECT_TRUE(std::isfinite(o.slip_pct[i]));
    EXPECT_TRUE(std::isfinite(o.slip_angle[i]));
  }
}

class StabilityControllerTest : public ::testing::Test {
 protected:
  params::StabilityParams p_;
};

TEST_F(StabilityControllerTest, InvalidParametersAreRefused) {
  params::StabilityParams p;
  p.tS = 0.0;
  p.ESC.beta_threshold_activate = {0.03};
  EXPECT_THROW(StabilityController c(p), ConfigError);
}

TEST_F(StabilityControllerTest, CruiseIsTransparent) {
  const StabilityController c(p_);
  StabilityController::State s;
  for (int k = 0; k < 300; ++k) {
    const auto in = Cruise(p_, 0.01 * k);
    const auto out = c.Step(in, &s);
    ASSERT_TRUE(out.valid);
    EXPECT_EQ(out.steering, in.steering_request);
    EXPECT_EQ(out.brake_bar, in.brake_request_bar);
    EXPECT_EQ(out.throttle, in.throttle_request);
    EXPECT_EQ(out.gear, in.gear_request);
    EXPECT_FALSE(out.esc_active || out.cs_active || out.slip_control_active);
    EXPECT_EQ(out.yaw_moment, 0.0);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(out.slip_pct[i], 0.0, 1e-9);
  }
}

TEST_F(StabilityControllerTest, OversteerTriggersEscAndCountersteer) {
  const StabilityController c(p_);
  StabilityController::State s;
  bool esc = false;
  bool cs = false;
  for (int k = 0; k < 100; ++k) {
    const auto in = Oversteer(p_, 0.01 * k);
    const auto out = c.Step(in, &s);
    if (out.esc_active) {
      esc = true;
      EXPECT_LT(out.yaw_moment, 0.0);  // left-hand oversteer → clockwise moment
      EXPECT_GT(out.brake_bar[kFR], in.brake_request_bar[kFR]);
    }
    if (out.cs_active) {
      cs = true;
      EXPECT_LT(out.steering, in.steering_request);  // steer right, into the slide
    }
  }
  EXPECT_TRUE(esc);
  EXPECT_TRUE(cs);
}

TEST_F(StabilityControllerTest, LockupTriggersAbs) {
  const StabilityController c(p_);
  StabilityController::State s;
  int t = 0;
  for (; t < 50; ++t) c.Step(Cruise(p_, 0.01 * t, 40.0), &s);
  bool abs = false;
  for (int k = 0; k < 40; ++k, ++t) {
    const auto in = Lockup(p_, 0.01 * t, k);
    const auto out = c.Step(in, &s);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_LE(out.brake_bar[i], in.brake_request_bar[i]);
    if (IsActive(out.abs_state[kFL])) {
      abs = true;
      EXPECT_TRUE(out.slip_control_active);
      EXPECT_LT(out.brake_bar[kFL], in.brake_request_bar[kFL]);
    }
  }
  EXPECT_TRUE(abs);
}

int TcSteps(const params::StabilityParams& p, const params::StabilityOptions& o) {
  const StabilityController c(p, o);
  StabilityController::State s;
  int t = 0;
  for (; t < 50; ++t) c.Step(Cruise(p, 0.01 * t, 20.0), &s);
  int n = 0;
  for (int k = 0; k < 50; ++k, ++t) {
    const auto out = c.Step(RearSpin(p, 0.01 * t), &s);
    if (AnyActive(out.tc_state)) {
      ++n;
      EXPECT_GT(out.brake_bar[kRL], 0.0);
    }
    EXPECT_EQ(out.throttle, 0.0);  // 30 % > 25 %: throttle cut in both modes
  }
  return n;
}

TEST_F(StabilityControllerTest, RearSpinTriggersTcUnlessReleaseCompat) {
  EXPECT_GT(TcSteps(p_, {}), 30);
  EXPECT_EQ(TcSteps(p_, {.release_compat = true}), 0);
}

TEST_F(StabilityControllerTest, ReleaseCompatKeepsEscTriggeredAbs) {
  const StabilityController c(p_, {.release_compat = true});
  StabilityController::State s;
  bool abs = false;
  for (int k = 0; k < 200; ++k) {
    auto in = Oversteer(p_, 0.01 * k);
    in.brake_request_bar = {30.0, 30.0, 10.0, 10.0};
    // The braked outer front starts to lock once ESC adds pressure.
    const auto w = testing::RollingWheelSpeeds(p_, in.v_x);
    in.wheel_speed = {w[0], w[1] * std::max(0.0, 1.0 - 0.01 * k), w[2], w[3]};
    const auto out = c.Step(in, &s);
    abs = abs || (out.esc_active && AnyActive(out.abs_state));
  }
  EXPECT_TRUE(abs);
}

struct Corruption {
  std::string name;
  std::function<void(StabilityInput&)> apply;
};

TEST_F(StabilityControllerTest, MissingEssentialInputPassesTheClampedRequestThrough) {
  const std::vector<Corruption> cases{
      {"t", [](StabilityInput& in) { in.t = kNan; }},
      {"v_x", [](StabilityInput& in) { in.v_x = kNan; }},
      {"v_y", [](StabilityInput& in) { in.v_y = kInf; }},
      {"yaw_rate", [](StabilityInput& in) { in.yaw_rate = kNan; }},
      {"steering_request", [](StabilityInput& in) { in.steering_request = kNan; }},
      {"brake_request", [](StabilityInput& in) { in.brake_request_bar[kRL] = kNan; }},
      {"throttle", [](StabilityInput& in) { in.throttle_request = -kInf; }},
      {"implausible_speed", [](StabilityInput& in) { in.v_x = 1e6; }},
  };
  const StabilityController c(p_);
  for (const auto& cs : cases) {
    StabilityController::State s;
    for (int k = 0; k < 20; ++k) c.Step(Oversteer(p_, 0.01 * k), &s);
    const StabilityController::State before = s;
    auto in = Oversteer(p_, 0.2);
    in.steering_request = 0.6;
    in.brake_request_bar = {100.0, 20.0, -3.0, 10.0};
    in.throttle_request = 1.4;
    cs.apply(in);
    const auto out = c.Step(in, &s);
    EXPECT_FALSE(out.valid) << cs.name;
    ExpectFinite(out);
    EXPECT_EQ(out.steering, std::isfinite(in.steering_request) ? 0.43 : 0.0) << cs.name;
    EXPECT_EQ(out.brake_bar[kFL], 80.0) << cs.name;
    EXPECT_EQ(out.brake_bar[kFR], 20.0) << cs.name;
    EXPECT_EQ(out.brake_bar[kRL], 0.0) << cs.name;
    EXPECT_EQ(out.throttle, std::isfinite(in.throttle_request) ? 1.0 : 0.0) << cs.name;
    EXPECT_FALSE(out.esc_active || out.cs_active || out.slip_control_active);
    EXPECT_EQ(0, std::memcmp(&before.esc, &s.esc, sizeof(s.esc))) << "state untouched";
  }
}

TEST_F(StabilityControllerTest, MissingOptionalInputsStayValidAndFinite) {
  const std::vector<Corruption> cases{
      {"accel", [](StabilityInput& in) { in.a_x = kNan; }},
      {"steer_meas", [](StabilityInput& in) { in.steering_measured = kInf; }},
      {"esc_targets", [](StabilityInput& in) { in.ay_request = kNan; }},
      {"engine", [](StabilityInput& in) { in.engine_speed = kNan; }},
      {"wheel", [](StabilityInput& in) { in.wheel_speed[kFR] = kNan; }},
      {"p_meas", [](StabilityInput& in) { in.brake_measured_bar[kFL] = kInf; }},
      {"temp", [](StabilityInput& in) { in.brake_temperature_degc[kRR] = kNan; }},
      {"long_fx", [](StabilityInput& in) { in.long_fx = kNan; }},
      {"fz",
       [](StabilityInput& in) {
         in.fz_external = {kNan, 1.0, 2.0, 3.0};
       }},
      {"huge_fz",
       [](StabilityInput& in) {
         in.fz_external = {1e300, 1e300, 1e300, 1e300};
       }},
  };
  const StabilityController c(p_);
  for (const auto& cs : cases) {
    StabilityController::State s;
    for (int k = 0; k < 100; ++k) {
      auto in = k < 50 ? Oversteer(p_, 0.01 * k) : Lockup(p_, 0.01 * k, k - 50);
      cs.apply(in);
      const auto out = c.Step(in, &s);
      ASSERT_TRUE(out.valid) << cs.name;
      ExpectFinite(out);
    }
  }
  StabilityController::State s;
  auto in = Cruise(p_, 0.0);
  in.wheel_speed[kFL] = kNan;
  EXPECT_FALSE(c.Step(in, &s).slip_valid);
}

TEST_F(StabilityControllerTest, EveryInputNonFiniteStaysFinite) {
  const StabilityController c(p_);
  StabilityController::State s;
  for (const double bad : {kNan, kInf, -kInf, 1e308, -1e308}) {
    StabilityInput in;
    in.t = in.v_x = in.v_y = in.yaw_rate = in.a_x = in.a_y = bad;
    in.steering_measured = in.steering_request = in.ay_request = in.yaw_rate_request = bad;
    in.beta_request = in.throttle_request = in.engine_speed = in.long_fx = bad;
    in.brake_request_bar = in.wheel_speed = in.brake_measured_bar = {bad, bad, bad, bad};
    in.brake_temperature_degc = in.fz_external = {bad, bad, bad, bad};
    const auto out = c.Step(in, &s);
    EXPECT_FALSE(out.valid);
    ExpectFinite(out);
    // Only the optionals bad: still valid.
    auto opt = Oversteer(p_, 1.0);
    opt.a_x = opt.a_y = opt.steering_measured = opt.ay_request = bad;
    opt.yaw_rate_request = opt.beta_request = opt.engine_speed = opt.long_fx = bad;
    opt.wheel_speed = opt.brake_measured_bar = {bad, bad, bad, bad};
    opt.brake_temperature_degc = opt.fz_external = {bad, bad, bad, bad};
    const auto out2 = c.Step(opt, &s);
    EXPECT_TRUE(out2.valid);
    ExpectFinite(out2);
  }
}

TEST_F(StabilityControllerTest, AblationEveryEnableCombination) {
  for (int mask = 0; mask < 16; ++mask) {
    params::StabilityParams p;
    p.ESC.enabled = mask & 1;
    p.countersteer_system.enabled = mask & 2;
    p.SlipControl.ABS.enabled = mask & 4;
    p.SlipControl.TC.enabled = mask & 8;
    const StabilityController c(p);
    StabilityController::State s;
    bool esc = false, cs = false, abs = false, tc = false;
    int t = 0;
    auto run = [&](const StabilityInput& in) {
      const auto out = c.Step(in, &s);
      ASSERT_TRUE(out.valid);
      ExpectFinite(out);
      for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_GE(out.brake_bar[i], 0.0);
        EXPECT_LE(out.brake_bar[i], p.ESC.max_brake_pressure);
      }
      EXPECT_GE(out.steering, p.vehicle.steering.min_angle);
      EXPECT_LE(out.steering, p.vehicle.steering.max_angle);
      esc = esc || out.esc_active;
      cs = cs || out.cs_active;
      abs = abs || AnyActive(out.abs_state);
      tc = tc || AnyActive(out.tc_state);
    };
    for (int k = 0; k < 30; ++k, ++t) run(Cruise(p, 0.01 * t));
    for (int k = 0; k < 80; ++k, ++t) run(Oversteer(p, 0.01 * t));
    for (int k = 0; k < 30; ++k, ++t) run(Cruise(p, 0.01 * t, 40.0));
    for (int k = 0; k < 40; ++k, ++t) run(Lockup(p, 0.01 * t, k));
    for (int k = 0; k < 30; ++k, ++t) run(Cruise(p, 0.01 * t, 20.0));
    for (int k = 0; k < 40; ++k, ++t) run(RearSpin(p, 0.01 * t));
    EXPECT_EQ(esc, p.ESC.enabled) << mask;
    EXPECT_EQ(cs, p.countersteer_system.enabled) << mask;
    EXPECT_EQ(abs, p.SlipControl.ABS.enabled) << mask;
    EXPECT_EQ(tc, p.SlipControl.TC.enabled) << mask;
  }
}

TEST_F(StabilityControllerTest, DeterministicAndStateIsolated) {
  const StabilityController c(p_);
  StabilityController::State a, b;
  for (int k = 0; k < 200; ++k) {
    const auto in = k < 100 ? Oversteer(p_, 0.01 * k) : Lockup(p_, 0.01 * k, k - 100);
    const auto oa = c.Step(in, &a);
    const auto ob = c.Step(in, &b);
    ASSERT_EQ(0, std::memcmp(&oa.brake_bar, &ob.brake_bar, sizeof(oa.brake_bar)));
    ASSERT_EQ(0, std::memcmp(&oa.steering, &ob.steering, sizeof(double)));
    ASSERT_EQ(0, std::memcmp(&oa.yaw_moment, &ob.yaw_moment, sizeof(double)));
  }
}

TEST_F(StabilityControllerTest, ExternalLoadsAndBrakeTemperatureMapAreUsed) {
  params::StabilityParams p;
  p.vehicle.brake.friction.temperature = {0.0, 1000.0};
  p.vehicle.brake.friction.coefficient = {0.3, 0.5};
  const StabilityController c(p);
  StabilityController::State s;
  auto in = Cruise(p, 0.0);
  in.brake_temperature_degc = {500.0, kNan, 0.0, 1000.0};
  in.fz_external = {1000.0, 1500.0, 2000.0, 2500.0};
  const auto out = c.Step(in, &s);
  EXPECT_DOUBLE_EQ(out.mu[kFL], 0.4);
  EXPECT_DOUBLE_EQ(out.mu[kFR], p.vehicle.brake.friction_coeff);  // unavailable → fallback
  EXPECT_DOUBLE_EQ(out.mu[kRR], 0.5);
  EXPECT_EQ(out.fz, in.fz_external);
}

}  // namespace
}  // namespace scw::controller
