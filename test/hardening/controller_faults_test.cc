// Fault injection into the stability controller's measurements: NaN (= signal unavailable), ±inf,
// absurd magnitudes and dropouts of every input channel, alone and in bursts, over long
// deterministic sequences (no random numbers: the faults follow fixed periods, so a failure
// names a reproducible step).
//
// Contract checked at every step (stability_controller.h §1 and §7):
//  * every output number is finite, within its limits (steering limits, [0, p_max], [0, 1]);
//  * the gear request is passed through;
//  * a missing/implausible essential input → valid = false and exactly the pass-through of the
//    clamped request (non-finite request elements → 0);
//  * a step with clean inputs is valid, also right after a long fault burst (no state poisoned).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "controller/stability/stability_controller.h"
#include "test/controller/stability/scenario_inputs.h"

namespace scw::controller {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Bad values cycled through by the schedule.
constexpr double kBadValues[] = {kNaN, kInf, -kInf, 1e300, -1e300, 1e12, -1e12};
constexpr std::size_t kNumBad = sizeof(kBadValues) / sizeof(kBadValues[0]);

struct Channel {
  const char* name;
  bool essential;
  std::function<void(StabilityInput*, double)> set;
};

std::vector<Channel> Channels() {
  std::vector<Channel> c = {
      {"t", true, [](StabilityInput* in, double v) { in->t = v; }},
      {"v_x", true, [](StabilityInput* in, double v) { in->v_x = v; }},
      {"v_y", true, [](StabilityInput* in, double v) { in->v_y = v; }},
      {"yaw_rate", true, [](StabilityInput* in, double v) { in->yaw_rate = v; }},
      {"steering_request", true, [](StabilityInput* in, double v) { in->steering_request = v; }},
      {"throttle_request", true, [](StabilityInput* in, double v) { in->throttle_request = v; }},
      {"a_x", false, [](StabilityInput* in, double v) { in->a_x = v; }},
      {"a_y", false, [](StabilityInput* in, double v) { in->a_y = v; }},
      {"steering_measured", false, [](StabilityInput* in, double v) { in->steering_measured = v; }},
      {"ay_request", false, [](StabilityInput* in, double v) { in->ay_request = v; }},
      {"yaw_rate_request", false, [](StabilityInput* in, double v) { in->yaw_rate_request = v; }},
      {"beta_request", false, [](StabilityInput* in, double v) { in->beta_request = v; }},
      {"engine_speed", false, [](StabilityInput* in, double v) { in->engine_speed = v; }},
      {"long_fx", false, [](StabilityInput* in, double v) { in->long_fx = v; }},
  };
  for (std::size_t w = 0; w < 4; ++w) {
    c.push_back({"brake_request_bar", true,
                 [w](StabilityInput* in, double v) { in->brake_request_bar[w] = v; }});
    c.push_back(
        {"wheel_speed", false, [w](StabilityInput* in, double v) { in->wheel_speed[w] = v; }});
    c.push_back({"brake_measured_bar", false,
                 [w](StabilityInput* in, double v) { in->brake_measured_bar[w] = v; }});
    c.push_back({"brake_temperature_degc", false,
                 [w](StabilityInput* in, double v) { in->brake_temperature_degc[w] = v; }});
    c.push_back(
        {"fz_external", false, [w](StabilityInput* in, double v) { in->fz_external[w] = v; }});
  }
  return c;
}

// The clean driving sequence: cruise, oversteer, front lock-up and rear spin phases of 4 s each
// at a slowly varying speed, with all optional signals present.
StabilityInput Clean(const params::StabilityParams& p, int k) {
  const double t = k * p.tS;
  const double v = 25.0 + 20.0 * std::sin(k * 1e-3);
  switch ((k / 400) % 4) {
    case 0:
      return testing::Cruise(p, t, v);
    case 1:
      return testing::Oversteer(p, t, v);
    case 2:
      return testing::Lockup(p, t, k % 400, v);
    default:
      return testing::RearSpin(p, t, v);
  }
}

// First violated property of one step, or "".
std::string Check(const StabilityController& c, const StabilityInput& in,
                  const StabilityOutput& out, bool essential_ok, bool clean) {
  const auto& p = c.params();
  std::ostringstream err;
  auto finite = [&](const char* name, double x) {
    if (!std::isfinite(x)) err << name << " = " << x << "; ";
  };
  finite("steering", out.steering);
  finite("throttle", out.throttle);
  finite("yaw_moment", out.yaw_moment);
  finite("v_ref", out.v_ref);
  finite("alpha_front_filtered", out.alpha_front_filtered);
  finite("alpha_rear_filtered", out.alpha_rear_filtered);
  for (std::size_t i = 0; i < 4; ++i) {
    finite("brake_bar", out.brake_bar[i]);
    finite("slip_pct", out.slip_pct[i]);
    finite("slip_angle", out.slip_angle[i]);
    finite("fz", out.fz[i]);
    finite("mu", out.mu[i]);
    if (!(out.brake_bar[i] >= 0.0 && out.brake_bar[i] <= p.ESC.max_brake_pressure))
      err << "brake_bar[" << i << "] = " << out.brake_bar[i] << " outside [0, p_max]; ";
  }
  if (!(out.steering >= p.vehicle.steering.min_angle &&
        out.steering <= p.vehicle.steering.max_angle))
    err << "steering " << out.steering << " outside the limits; ";
  if (!(out.throttle >= 0.0 && out.throttle <= 1.0)) err << "throttle " << out.throttle << "; ";
  if (out.gear != in.gear_request) err << "gear not passed through; ";
  if (!essential_ok) {
    const StabilityOutput pass = c.PassThrough(in);
    if (out.valid) err << "valid with an essential input missing; ";
    if (out.steering != pass.steering || out.brake_bar != pass.brake_bar ||
        out.throttle != pass.throttle)
      err << "not the pass-through of the request; ";
  }
  if (clean && !out.valid) err << "clean inputs but valid = false; ";
  return err.str();
}

struct Counts {
  int steps = 0, invalid = 0, faulty = 0;
};

// Runs `steps` steps; fault(k, &in) corrupts the clean input and returns whether an essential
// channel was hit (and whether any channel was hit through *any).
Counts RunFaults(const params::StabilityParams& p, int steps,
                 const std::function<bool(int, StabilityInput*, bool*)>& fault) {
  const StabilityController c(p);
  StabilityController::State s;
  Counts n;
  int reported = 0;
  for (int k = 0; k < steps; ++k) {
    StabilityInput in = Clean(p, k);
    bool any = false;
    const bool essential_hit = fault(k, &in, &any);
    const StabilityOutput out = c.Step(in, &s);
    ++n.steps;
    n.invalid += !out.valid;
    n.faulty += any;
    const std::string e = Check(c, in, out, !essential_hit, !any);
    if (!e.empty() && reported++ < 5) ADD_FAILURE() << "step " << k << ": " << e;
  }
  return n;
}

TEST(ControllerFaultsTest, SingleChannelFaultsCycleThroughEveryChannelAndValue) {
  const params::StabilityParams p;
  const auto channels = Channels();
  // Every 10th step is faulty: channel (k/10) mod n, value (k/(10n)) mod kNumBad, so each
  // (channel, value) pair occurs, in every driving phase, over 60 000 steps (10 min at 100 Hz).
  const int n = static_cast<int>(channels.size());
  const Counts c = RunFaults(p, 60000, [&](int k, StabilityInput* in, bool* any) {
    if (k % 10 != 3) return false;
    const auto& ch = channels[static_cast<std::size_t>((k / 10) % n)];
    const double v = kBadValues[static_cast<std::size_t>((k / (10 * n)) % kNumBad)];
    ch.set(in, v);
    *any = true;
    // An absurd but finite optional value is "unavailable", an essential one beyond the
    // plausibility limits invalid; only t, the steering request and the throttle request need
    // nothing but finiteness (the requests are clamped), so those steps stay valid.
    const std::string name = ch.name;
    const bool finite_clamped = std::isfinite(v) && (name == "throttle_request" ||
                                                     name == "steering_request" || name == "t");
    return ch.essential && !finite_clamped;
  });
  EXPECT_GT(c.invalid, 1000);
  EXPECT_LT(c.invalid, c.faulty);
}

TEST(ControllerFaultsTest, DropoutBurstsAndRecovery) {
  const params::StabilityParams p;
  const auto channels = Channels();
  // Bursts of 1 s (100 steps) in which a whole group is unavailable (NaN), separated by 2 s of
  // clean input; the groups: odometry, one wheel speed, all wheel speeds, the brake requests,
  // every optional signal, every signal at once.
  const std::vector<std::vector<std::string>> groups = {
      {"v_x", "v_y", "yaw_rate"},
      {"wheel_speed"},
      {"brake_request_bar"},
      {"a_x", "a_y", "steering_measured", "ay_request", "yaw_rate_request", "beta_request",
       "engine_speed", "long_fx", "wheel_speed", "brake_measured_bar", "brake_temperature_degc",
       "fz_external"},
      {"t"},
      {},  // all
  };
  const Counts c = RunFaults(p, 36000, [&](int k, StabilityInput* in, bool* any) {
    const int period = 300, burst = 100;
    if (k % period >= burst || k > 34000) return false;  // the last 20 s are clean
    const auto& g = groups[static_cast<std::size_t>((k / period) % groups.size())];
    bool essential = false;
    for (const auto& ch : channels) {
      if (!g.empty() && std::find(g.begin(), g.end(), ch.name) == g.end()) continue;
      // "one wheel speed": only the rear-left one.
      if (g.size() == 1 && g[0] == "wheel_speed" && (k / period) % 2 == 1) {
        in->wheel_speed[2] = kNaN;
        *any = true;
        break;
      }
      ch.set(in, kNaN);
      *any = true;
      essential = essential || ch.essential;
    }
    return essential;
  });
  EXPECT_GT(c.invalid, 1000);
}

TEST(ControllerFaultsTest, OptionalDropoutsKeepTheControllerValid) {
  const params::StabilityParams p;
  const StabilityController c(p);
  StabilityController::State s;
  for (int k = 0; k < 2000; ++k) {
    StabilityInput in = Clean(p, k);
    in.wheel_speed[k % 4] = kNaN;
    in.a_x = k % 3 ? in.a_x : kInf;
    in.brake_temperature_degc = {kNaN, kNaN, kNaN, kNaN};
    const StabilityOutput out = c.Step(in, &s);
    ASSERT_TRUE(out.valid) << "step " << k;
    ASSERT_FALSE(out.slip_valid) << "step " << k;
    ASSERT_EQ(Check(c, in, out, true, false), "") << "step " << k;
  }
}

TEST(ControllerFaultsTest, AllSignalsNaNIsAZeroPassThrough) {
  const params::StabilityParams p;
  const StabilityController c(p);
  StabilityController::State s;
  StabilityInput in;
  in.t = in.v_x = in.v_y = in.yaw_rate = in.steering_request = in.throttle_request = kNaN;
  in.long_fx = kNaN;
  in.brake_request_bar = {kNaN, kNaN, kNaN, kNaN};
  in.gear_request = 3;
  const StabilityOutput out = c.Step(in, &s);
  EXPECT_FALSE(out.valid);
  EXPECT_EQ(out.steering, 0.0);
  EXPECT_EQ(out.throttle, 0.0);
  EXPECT_EQ(out.brake_bar, (PerWheel<double>{0.0, 0.0, 0.0, 0.0}));
  EXPECT_EQ(out.gear, 3);
}

TEST(ControllerFaultsTest, RequestIsPassedThroughClampedWhenOdometryIsMissing) {
  const params::StabilityParams p;
  const StabilityController c(p);
  StabilityController::State s;
  StabilityInput in = Clean(p, 0);
  in.v_x = kNaN;
  in.steering_request = 0.1;
  in.brake_request_bar = {12.0, -3.0, 1e3, 7.5};
  in.throttle_request = 1.7;
  const StabilityOutput out = c.Step(in, &s);
  EXPECT_FALSE(out.valid);
  EXPECT_EQ(out.steering, 0.1);
  EXPECT_EQ(out.brake_bar, (PerWheel<double>{12.0, 0.0, p.ESC.max_brake_pressure, 7.5}));
  EXPECT_EQ(out.throttle, 1.0);
}

}  // namespace
}  // namespace scw::controller
