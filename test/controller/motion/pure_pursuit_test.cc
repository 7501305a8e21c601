#include "controller/motion/pure_pursuit.h"

#include <gtest/gtest.h>

#include <cmath>

namespace scw::controller::motion {
namespace {

std::shared_ptr<const Path> Circle(double r, double v) {
  std::vector<PathPoint> pts;
  const int n = 800;
  const double len = 2 * M_PI * r;
  for (int i = 0; i < n; ++i) {
    const double s = len * i / n, th = s / r;
    pts.push_back({s, r * std::cos(th), r * std::sin(th), th + M_PI / 2, 1.0 / r, v, 0.0});
  }
  return std::make_shared<Path>(pts, len);
}

// Kinematic single-track model driven by the controller (speed held by the a_x request).
struct Kinematic {
  double x, y, psi, v;
  void Step(double delta, double ax, double l, double dt) {
    x += v * std::cos(psi) * dt;
    y += v * std::sin(psi) * dt;
    psi += v / l * std::tan(delta) * dt;
    v += ax * dt;
  }
};

TEST(PurePursuitTest, FollowsACircleAndConvergesFromAnOffset) {
  params::TrackingParams p;
  const double r = 120.0, v = 30.0;
  PurePursuit pp(p, Circle(r, v));
  auto st = pp.MakeState();
  Kinematic car{r + 2.0, 0.0, M_PI / 2, 27.0};  // 2 m outside, a bit slow
  MotionOutput out;
  for (int k = 0; k < 3000; ++k) {
    MotionInput in{k * 0.01, car.x, car.y, car.psi, car.v, 0, 0, 0, 0, 0};
    out = pp.Step(in, st.get());
    car.Step(out.steering_request, out.ax_request, p.vehicle.wheelbase_m, 0.01);
  }
  // With the shipped 50 % curvature feed-forward the feedback settles at about half the path
  // curvature, with a small steady offset to the inside (left) of the line.
  EXPECT_LT(std::abs(out.lateral_error), 0.5);
  EXPECT_NEAR(car.v, v, 0.3);
  EXPECT_NEAR(out.steering_request, std::atan(p.vehicle.wheelbase_m / r), 0.002);
  EXPECT_GT(out.ay_request, 0.4 * v * v / r);
  EXPECT_LT(out.ay_request, 1.05 * v * v / r);
  // Without feed-forward the pure-pursuit curvature alone carries the car: a_y,req ≈ v²/R.
  p.enable_lat_feedforward_perc = 0.0;
  PurePursuit fb_only(p, Circle(r, v));
  auto st2 = fb_only.MakeState();
  Kinematic car2{r, 0.0, M_PI / 2, v};
  for (int k = 0; k < 3000; ++k) {
    MotionInput in{k * 0.01, car2.x, car2.y, car2.psi, car2.v, 0, 0, 0, 0, 0};
    out = fb_only.Step(in, st2.get());
    car2.Step(out.steering_request, out.ax_request, p.vehicle.wheelbase_m, 0.01);
  }
  EXPECT_NEAR(out.ay_request, v * v / r, 0.05 * v * v / r);
  EXPECT_LT(std::abs(out.lateral_error), 0.2);
}

// The default (the car's node) publishes the feedback curvature only: about half of v²/R on a
// circle with the shipped 50 % feed-forward; the `total` option publishes the whole commanded
// curvature, ≈ v²/R.
TEST(PurePursuitTest, EscTargetFeedbackIsAboutHalfAndTotalIsTheWholeLateralAcceleration) {
  params::TrackingParams p;
  const double r = 120.0, v = 30.0;
  double ay[2] = {0.0, 0.0};
  for (int mode = 0; mode < 2; ++mode) {
    PurePursuitOptions o;
    o.esc_target = mode == 0 ? EscTarget::kFeedback : EscTarget::kTotal;
    PurePursuit pp(p, Circle(r, v), o);
    auto st = pp.MakeState();
    Kinematic car{r, 0.0, M_PI / 2, v};
    MotionOutput out;
    for (int k = 0; k < 3000; ++k) {
      MotionInput in{k * 0.01, car.x, car.y, car.psi, car.v, 0, 0, 0, 0, 0};
      out = pp.Step(in, st.get());
      car.Step(out.steering_request, out.ax_request, p.vehicle.wheelbase_m, 0.01);
    }
    ay[mode] = out.ay_request;
  }
  EXPECT_LT(ay[0], 0.7 * v * v / r);
  EXPECT_NEAR(ay[1], v * v / r, 0.03 * v * v / r);
}

TEST(PurePursuitTest, SteersTowardsThePathAndRespectsLimits) {
  params::TrackingParams p;
  PurePursuit pp(p, Circle(1000.0, 40.0));
  auto st = pp.MakeState();
  // Right of (outside) the path, heading along it: steer left.
  auto out = pp.Step({0, 1003.0, 0, M_PI / 2, 40, 0, 0, 0, 0, 0}, st.get());
  EXPECT_GT(out.steering_request, 0.0);
  EXPECT_LT(out.lateral_error, 0.0);
  // Far off with the wrong heading: clamped.
  auto st2 = pp.MakeState();
  out = pp.Step({0, 990.0, 0, -M_PI / 2, 5, 0, 0, 0, 0, 0}, st2.get());
  EXPECT_LE(std::abs(out.steering_request), p.vehicle.max_angle + 1e-12);
}

TEST(PurePursuitTest, CurvatureLookaheadIsCapped) {
  params::TrackingParams p;
  p.curvature_lookahead_gain = 4e-5;
  // A straight (zero curvature) line: without the cap the lookahead would be 4000 m.
  std::vector<PathPoint> pts;
  for (int i = 0; i < 1000; ++i) pts.push_back({i * 2.0, i * 2.0, 0, 0, 0, 50, 0});
  auto path = std::make_shared<Path>(pts, 2000.0);
  PurePursuit pp(p, path);
  auto st = pp.MakeState();
  const auto out = pp.Step({0, 100.0, -1.0, 0, 50, 0, 0, 0, 0, 0}, st.get());
  // Lookahead ≈ 0.1 + 0.45·50 + 20 = 42.6 m → κ = 2·1/42.6² filtered (pole 0.135).
  const double L = 0.1 + 0.45 * 50 + 20.0;
  const double kappa = (1 - std::exp(-0.01 / 0.005)) * 2.0 * 1.0 / (L * L);
  EXPECT_NEAR(out.steering_request, std::atan(p.vehicle.wheelbase_m * kappa), 1e-4);
}

TEST(PurePursuitTest, NonFiniteInputGivesFiniteOutput) {
  params::TrackingParams p;
  PurePursuit pp(p, Circle(100.0, 20.0));
  auto st = pp.MakeState();
  const double nan = std::nan("");
  const auto out = pp.Step({0, nan, nan, nan, nan, 0, 0, 0, 0, 0}, st.get());
  EXPECT_TRUE(std::isfinite(out.steering_request));
  EXPECT_TRUE(std::isfinite(out.ax_request));
  EXPECT_TRUE(std::isfinite(out.ay_request));
}

}  // namespace
}  // namespace scw::controller::motion
