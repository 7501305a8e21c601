// Countersteer (spec §5): zero correction while the rear axle slides no more than the front,
// δ̄ = δ − k(ᾱ_r − ᾱ_f) otherwise, the steering clamp always.
#include "controller/stability/countersteer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace scw::controller {
namespace {

struct CsRow {
  std::string name;
  double delta;
  double alpha_f;
  double alpha_r;
  bool enabled;
  double expected;
  bool active;
};

TEST(CountersteerCommandTest, Table) {
  params::CountersteerParams cs;      // k = 1, α_en = 0.009
  const params::VehicleSteering lim;  // ±0.43
  const std::vector<CsRow> rows{
      {"rear_smaller", 0.1, 0.05, 0.04, true, 0.1, false},
      {"rear_equal", 0.1, 0.05, -0.05, true, 0.1, false},  // magnitudes compared
      {"rear_larger_left", 0.1, 0.02, 0.06, true, 0.1 - (0.06 - 0.02), true},
      {"rear_larger_right", -0.1, -0.02, -0.06, true, -0.1 - (-0.06 + 0.02), true},
      {"rear_larger_opposite_sign", 0.0, 0.01, -0.03, true, 0.0 - (-0.03 - 0.01), true},
      {"below_enable_sideslip", 0.1, 0.001, 0.009, true, 0.1, false},
      {"disabled", 0.1, 0.02, 0.06, false, 0.1, false},
      {"clamped_upper", 0.42, -0.05, -0.2, true, 0.43, true},
      {"clamped_lower", -0.42, 0.05, 0.2, true, -0.43, true},
      {"disabled_still_clamped", 0.6, 0.02, 0.06, false, 0.43, false},
  };
  for (const auto& r : rows) {
    cs.enabled = r.enabled;
    bool active = false;
    EXPECT_NEAR(CountersteerCommand(r.delta, r.alpha_f, r.alpha_r, cs, lim, &active), r.expected,
                1e-15)
        << r.name;
    EXPECT_EQ(active, r.active) << r.name;
  }
  cs.enabled = true;
  cs.steering_factor = 0.5;
  bool active = false;
  EXPECT_NEAR(CountersteerCommand(0.1, 0.02, 0.06, cs, lim, &active), 0.1 - 0.5 * 0.04, 1e-15);
}

Countersteer::Input Drift(double v_y, double yaw_rate, double delta) {
  Countersteer::Input in;
  in.v_x = 20.0;
  in.v_y = v_y;
  in.yaw_rate = yaw_rate;
  in.steering = delta;
  in.steering_request = delta;
  in.fz = {2000.0, 2000.0, 2000.0, 2000.0};
  return in;
}

TEST(CountersteerTest, FilterPoleFromTimeConstant) {
  EXPECT_NEAR(Countersteer(params::StabilityParams{}).filter_pole(), 0.9355, 5e-5);
}

TEST(CountersteerTest, OversteerDriftSteersIntoTheSlide) {
  const Countersteer cs(params::StabilityParams{});
  Countersteer::State s;
  Countersteer::Output out;
  // Left turn with the rear sliding out (v_y < 0 large): rear slip angle exceeds the front.
  for (int k = 0; k < 100; ++k) out = cs.Step(Drift(-3.0, 0.5, 0.05), &s);
  EXPECT_TRUE(out.active);
  EXPECT_GT(std::abs(out.alpha_rear_filtered), std::abs(out.alpha_front_filtered));
  EXPECT_NEAR(out.steering, 0.05 - (out.alpha_rear_filtered - out.alpha_front_filtered), 1e-15);
  EXPECT_LT(out.steering, 0.05);  // countersteer to the right
}

TEST(CountersteerTest, NeutralCorneringGivesNoCorrection) {
  const Countersteer cs(params::StabilityParams{});
  Countersteer::State s;
  Countersteer::Output out;
  // Understeer-balanced: front slip angle larger than rear.
  for (int k = 0; k < 100; ++k) out = cs.Step(Drift(0.3, 0.3, 0.08), &s);
  EXPECT_FALSE(out.active);
  EXPECT_EQ(out.steering, 0.08);
}

TEST(CountersteerTest, InvalidInputsPassTheClampedRequest) {
  const Countersteer cs(params::StabilityParams{});
  Countersteer::State s;
  auto in = Drift(-3.0, 0.5, 0.6);
  in.slip_angle_valid = false;
  auto out = cs.Step(in, &s);
  EXPECT_EQ(out.steering, 0.43);
  EXPECT_FALSE(out.active);
  EXPECT_EQ(s.alpha_rear_filtered, 0.0);  // not updated
  in = Drift(-3.0, 0.5, 0.1);
  in.fz = {0.0, 0.0, 2000.0, 2000.0};
  out = cs.Step(in, &s);
  EXPECT_EQ(out.steering, 0.1);
  EXPECT_EQ(s.alpha_front_filtered, 0.0);
}

}  // namespace
}  // namespace scw::controller
