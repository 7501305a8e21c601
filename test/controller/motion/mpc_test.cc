// The MPC motion controllers (controller/motion/pmpc.h, nmpc.h): model derivatives against
// finite differences, constraint satisfaction of solved plans, full laps of the default track
// without stability control, solve-time statistics. Built on the resolved default scenario (track,
// reference, g-g-v limits) of scw::sim; the settings come from the scenario keys motion.pmpc.* and
// motion.nmpc.* (params/schema/mpc_params.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "controller/motion/nmpc.h"
#include "controller/motion/pmpc.h"
#include "tuning/sim/closed_loop.h"
#include "tuning/sim/motion_factory.h"

namespace scw::tuning {
namespace {

namespace cm = controller::motion;
using PM = cm::PointMassModel;
using ST = cm::SingleTrackModel;

const ResolvedScenario& Scenario(const std::string& controller) {
  static const ResolvedScenario pmpc = Resolve(DefaultScenario({"motion.controller=pmpc"}));
  static const ResolvedScenario nmpc = Resolve(DefaultScenario({"motion.controller=nmpc"}));
  return controller == "pmpc" ? pmpc : nmpc;
}

// A measured input on the reference at arc length s, displaced by n [m] to the left, with a
// heading error, speed factor and body slip.
cm::MotionInput OnPath(const cm::Path& path, double t, double s, double n = 0.0,
                       double heading_error = 0.0, double speed_factor = 1.0, double v_y = 0.0) {
  const cm::PathPoint p = path.Sample(s);
  cm::MotionInput in;
  in.t = t;
  in.x = p.x - n * std::sin(p.psi);
  in.y = p.y + n * std::cos(p.psi);
  in.psi = p.psi + heading_error;
  in.v_x = p.v * speed_factor;
  in.v_y = v_y;
  in.yaw_rate = p.kappa * in.v_x;
  return in;
}

// ---------------------------------------------------------------------------------------------
// Model derivatives against central differences.

TEST(PointMassModelTest, JacobiansMatchFiniteDifferences) {
  const double dt = 0.125;
  for (const double kappa : {0.0, 0.02, -0.05}) {
    for (const PM::StateVec& x : {PM::StateVec(0.0, 0.0, 50.0), PM::StateVec(1.2, -0.8, 30.0),
                                  PM::StateVec(-2.0, 1.5, 12.0)}) {
      const PM::InputVec u(-5.0, 8.0);
      Eigen::Matrix3d a;
      Eigen::Matrix<double, 3, 2> b;
      PM::Jacobians(x, u, kappa, dt, &a, &b);
      for (int j = 0; j < 3; ++j) {
        const double h = 1e-6 * std::max(1.0, std::abs(x[j]));
        PM::StateVec xp = x, xm = x;
        xp[j] += h;
        xm[j] -= h;
        const PM::StateVec fd = (PM::Step(xp, u, kappa, dt) - PM::Step(xm, u, kappa, dt)) / (2 * h);
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(a(i, j), fd[i], 1e-6) << i << "," << j;
      }
      for (int j = 0; j < 2; ++j) {
        PM::InputVec up = u, um = u;
        up[j] += 1e-6;
        um[j] -= 1e-6;
        const PM::StateVec fd = (PM::Step(x, up, kappa, dt) - PM::Step(x, um, kappa, dt)) / 2e-6;
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(b(i, j), fd[i], 1e-6) << i << "," << j;
      }
    }
  }
}

// States around the operating envelope: straight, cornering with slip, low speed, past the peak.
std::vector<std::pair<ST::StateVec, ST::InputVec>> SingleTrackPoints() {
  std::vector<std::pair<ST::StateVec, ST::InputVec>> pts;
  ST::StateVec x;
  x << 0.0, 0.0, 60.0, 0.0, 0.0;
  pts.push_back({x, ST::InputVec(0.0, 2.0)});
  x << 0.8, 0.05, 40.0, -0.6, 0.35;
  pts.push_back({x, ST::InputVec(0.04, -8.0)});
  x << -1.5, -0.2, 12.0, 0.9, -0.6;
  pts.push_back({x, ST::InputVec(-0.2, 3.0)});
  x << 0.3, 0.1, 25.0, -2.0, 0.8;  // large slip angles, beyond the tyre peak
  pts.push_back({x, ST::InputVec(0.25, -12.0)});
  return pts;
}

TEST(SingleTrackModelTest, ContinuousJacobianMatchesFiniteDifferences) {
  const auto p = cm::SingleTrackParamsFrom(Scenario("nmpc").vehicle);
  for (const double kappa : {0.0, 0.03, -0.1}) {
    for (const auto& [x, u] : SingleTrackPoints()) {
      ST::Jac jac;
      ST::Derivatives(p, x, u, kappa, &jac);
      for (int j = 0; j < ST::kNz; ++j) {
        const double h = 1e-6 * std::max(1.0, j < ST::kNx ? std::abs(x[j]) : std::abs(u[j - 5]));
        ST::StateVec xp = x, xm = x;
        ST::InputVec up = u, um = u;
        if (j < ST::kNx) {
          xp[j] += h;
          xm[j] -= h;
        } else {
          up[j - ST::kNx] += h;
          um[j - ST::kNx] -= h;
        }
        const ST::StateVec fd =
            (ST::Derivatives(p, xp, up, kappa) - ST::Derivatives(p, xm, um, kappa)) / (2 * h);
        for (int i = 0; i < ST::kNx; ++i)
          EXPECT_NEAR(jac(i, j), fd[i], 1e-5 * std::max(1.0, std::abs(fd[i])))
              << "row " << i << " col " << j << " kappa " << kappa;
      }
      // Lateral acceleration gradient.
      ST::Row grad;
      ST::LateralAcceleration(p, x, u, &grad);
      for (int j = 0; j < ST::kNz; ++j) {
        ST::StateVec xp = x, xm = x;
        ST::InputVec up = u, um = u;
        const double h = 1e-6;
        if (j < ST::kNx) {
          xp[j] += h;
          xm[j] -= h;
        } else {
          up[j - ST::kNx] += h;
          um[j - ST::kNx] -= h;
        }
        const double fd =
            (ST::LateralAcceleration(p, xp, up) - ST::LateralAcceleration(p, xm, um)) / (2 * h);
        EXPECT_NEAR(grad[j], fd, 1e-5 * std::max(1.0, std::abs(fd))) << "a_y col " << j;
      }
    }
  }
}

TEST(SingleTrackModelTest, DiscreteJacobianMatchesFiniteDifferences) {
  const auto p = cm::SingleTrackParamsFrom(Scenario("nmpc").vehicle);
  for (const auto& [x, u] : SingleTrackPoints()) {
    ST::Jac jac;
    ST::Discrete(p, x, u, 0.02, 0.1, 2, &jac);
    for (int j = 0; j < ST::kNz; ++j) {
      const double h = 1e-6 * std::max(1.0, j < ST::kNx ? std::abs(x[j]) : std::abs(u[j - 5]));
      ST::StateVec xp = x, xm = x;
      ST::InputVec up = u, um = u;
      if (j < ST::kNx) {
        xp[j] += h;
        xm[j] -= h;
      } else {
        up[j - ST::kNx] += h;
        um[j - ST::kNx] -= h;
      }
      const ST::StateVec fd =
          (ST::Discrete(p, xp, up, 0.02, 0.1, 2) - ST::Discrete(p, xm, um, 0.02, 0.1, 2)) / (2 * h);
      for (int i = 0; i < ST::kNx; ++i)
        EXPECT_NEAR(jac(i, j), fd[i], 1e-5 * std::max(1.0, std::abs(fd[i])))
            << "row " << i << " col " << j;
    }
  }
}

TEST(SingleTrackModelTest, TyreForcesAreOddAndBoundedByPeakFriction) {
  const auto p = cm::SingleTrackParamsFrom(Scenario("nmpc").vehicle);
  for (const double vy : {0.5, 2.0, 8.0}) {
    ST::StateVec x, xm;
    x << 0.0, 0.0, 30.0, vy, 0.0;
    xm << 0.0, 0.0, 30.0, -vy, 0.0;
    const double ay = ST::LateralAcceleration(p, x, ST::InputVec(0.0, 0.0));
    EXPECT_NEAR(ay, -ST::LateralAcceleration(p, xm, ST::InputVec(0.0, 0.0)), 1e-9);
    EXPECT_LT(ay, 0.0);  // sliding left pushes right
    const double fz = p.mass * p.gravity + (p.downforce_front + p.downforce_rear) * 900.0;
    EXPECT_LE(std::abs(ay) * p.mass, std::max(p.front.mu, p.rear.mu) * fz + 1e-6);
  }
  // The linear single track of the plant's tyres is near neutral (|K_us| small) [rad/(m/s²)].
  EXPECT_LT(std::abs(cm::UndersteerGradient(p, 50.0)), 5e-3);
}

// ---------------------------------------------------------------------------------------------
// Constraint satisfaction of solved plans.

struct Case {
  double s, n, heading_error, speed_factor;
};
const Case kCases[] = {{110.0, 0.0, 0.0, 1.0},     {160.0, 0.5, 0.02, 1.05},
                       {700.0, -0.8, -0.03, 0.95}, {1330.0, 0.3, 0.0, 1.0},
                       {2500.0, 0.0, 0.0, 1.1},    {1900.0, -0.3, 0.05, 1.0}};

TEST(PmpcTest, SolvedPlansSatisfyGgTrackAndDynamics) {
  const auto& sc = Scenario("pmpc");
  const auto ctl = MakeMotionController(sc);
  const auto& mpc = dynamic_cast<const cm::PointMassMpc&>(*ctl);
  const auto& o = mpc.options();
  for (const Case& c : kCases) {
    auto base = mpc.MakeState();
    auto* st = static_cast<cm::PointMassMpc::State*>(base.get());
    // Three solves along the path (cold start, then warm starts from the shifted plan).
    for (int i = 0; i < 3; ++i) {
      const double t = i * o.solve_period;
      const double v = sc.path->Sample(c.s).v * c.speed_factor;
      const auto out =
          mpc.Step(OnPath(*sc.path, t, c.s + v * t, c.n, c.heading_error, c.speed_factor), st);
      EXPECT_TRUE(std::isfinite(out.steering_request) && std::isfinite(out.ax_request));
    }
    ASSERT_EQ(st->diagnostics.failures, 0) << "s = " << c.s;
    const auto& p = st->plan;
    ASSERT_TRUE(p.valid);
    const double tol = 1e-4;
    for (int k = 0; k < o.horizon_steps; ++k) {
      const auto K = static_cast<std::size_t>(k);
      // g-g: inside the exact law (the inscribed polygon is inside it) at the node's speed; the
      // limits were frozen at the warm start's speed, so allow 3 %.
      const double v = p.v[K];
      const double ay = o.nominal_fraction * mpc.limits().AyMax(v);
      const double ax = p.at[K] >= 0.0 ? o.nominal_fraction * mpc.limits().AxDriveMax(v)
                                       : o.nominal_fraction * mpc.limits().AxBrakeMax(v);
      const double r = std::abs(p.an[K]) / ay;
      EXPECT_LE(r, 1.03) << "s = " << c.s << " k = " << k;
      const double comb = controller::planning::GgvTable::Combine(
          std::min(r, 1.0),
          p.at[K] >= 0.0 ? mpc.limits().DriveExponent(v) : mpc.limits().BrakeExponent(v));
      EXPECT_LE(std::abs(p.at[K]), 1.03 * ax * comb + 0.05) << "s = " << c.s << " k = " << k;
      // Track bounds (tightened by the tube) after the first node.
      const double up = mpc.CorridorLeft(p.s[K + 1]) - o.tube_lateral;
      const double lo = -(mpc.CorridorRight(p.s[K + 1]) - o.tube_lateral);
      EXPECT_LE(p.n[K + 1], up + 0.05) << "s = " << c.s << " k = " << k;
      EXPECT_GE(p.n[K + 1], lo - 0.05) << "s = " << c.s << " k = " << k;
      // The plan follows the nonlinear model (LTV linearisation error only).
      const PM::StateVec next = PM::Step(PM::StateVec(p.n[K], p.w[K], p.v[K]),
                                         PM::InputVec(p.at[K], p.an[K]), p.kappa[K], o.step);
      EXPECT_NEAR(next[0], p.n[K + 1], 0.05);
      EXPECT_NEAR(next[1], p.w[K + 1], 0.2);
      EXPECT_NEAR(next[2], p.v[K + 1], tol);
    }
  }
}

// The fast solver path (quasi-definite LDLᵀ, warm start from shifted multipliers) solves the same
// QP as Ipopt with MUMPS from a cold start: the plans agree to the solver tolerance over a
// sequence of warm-started solves with a lateral and heading disturbance.
TEST(PmpcTest, FastSolverGivesTheMumpsColdStartPlans) {
  const auto& sc = Scenario("pmpc");
  const auto ctl = MakeMotionController(sc);
  const auto& fast = dynamic_cast<const cm::PointMassMpc&>(*ctl);
  cm::Corridor corridor;
  for (const auto& pt : sc.path->points()) {
    corridor.left.push_back(fast.CorridorLeft(pt.s));
    corridor.right.push_back(fast.CorridorRight(pt.s));
  }
  cm::PmpcOptions o = fast.options();
  o.mumps = true;
  o.warm_start = false;
  const cm::PointMassMpc reference(o, fast.limits(), corridor, sc.path);
  auto fast_base = fast.MakeState(), ref_base = reference.MakeState();
  auto* a = static_cast<cm::PointMassMpc::State*>(fast_base.get());
  auto* b = static_cast<cm::PointMassMpc::State*>(ref_base.get());
  double s = 500.0, worst_n = 0.0, worst_v = 0.0, worst_a = 0.0;
  for (int i = 0; i < 40; ++i) {
    const double t = i * o.solve_period;
    const double v = sc.path->Sample(s).v;
    const auto in = OnPath(*sc.path, t, s, 0.3 * std::sin(0.3 * i), 0.02 * std::cos(0.2 * i));
    fast.Step(in, a);
    reference.Step(in, b);
    ASSERT_TRUE(a->plan.valid && b->plan.valid) << i;
    for (std::size_t k = 0; k < a->plan.at.size(); ++k) {
      worst_n = std::max(worst_n, std::abs(a->plan.n[k + 1] - b->plan.n[k + 1]));
      worst_v = std::max(worst_v, std::abs(a->plan.v[k + 1] - b->plan.v[k + 1]));
      worst_a = std::max({worst_a, std::abs(a->plan.at[k] - b->plan.at[k]),
                          std::abs(a->plan.an[k] - b->plan.an[k])});
    }
    s += v * o.solve_period;
  }
  EXPECT_EQ(a->diagnostics.failures, 0);
  EXPECT_EQ(b->diagnostics.failures, 0);
  EXPECT_LT(worst_n, 1e-3) << "lateral offset [m]";
  EXPECT_LT(worst_v, 1e-3) << "speed [m/s]";
  EXPECT_LT(worst_a, 1e-2) << "accelerations [m/s²]";
  // The warm start pays off: fewer Ipopt iterations than the cold start.
  EXPECT_LT(a->diagnostics.iterations, b->diagnostics.iterations);
  std::printf(
      "pmpc fast vs MUMPS cold: max |dn| %.2e m, |dv| %.2e m/s, |da| %.2e m/s2; "
      "iterations %lld vs %lld; median solve %.2f vs %.2f ms\n",
      worst_n, worst_v, worst_a, static_cast<long long>(a->diagnostics.iterations),
      static_cast<long long>(b->diagnostics.iterations), 1e3 * a->diagnostics.solve_time.Median(),
      1e3 * b->diagnostics.solve_time.Median());
}

TEST(NmpcTest, SolvedPlansSatisfyGgTrackSteeringAndDynamics) {
  const auto& sc = Scenario("nmpc");
  const auto ctl = MakeMotionController(sc);
  const auto& mpc = dynamic_cast<const cm::SingleTrackMpc&>(*ctl);
  const auto& o = mpc.options();
  for (const Case& c : kCases) {
    auto base = mpc.MakeState();
    auto* st = static_cast<cm::SingleTrackMpc::State*>(base.get());
    for (int i = 0; i < 3; ++i) {
      const double t = i * o.sample_time;
      const double v = sc.path->Sample(c.s).v * c.speed_factor;
      const auto out =
          mpc.Step(OnPath(*sc.path, t, c.s + v * t, c.n, c.heading_error, c.speed_factor), st);
      EXPECT_TRUE(std::isfinite(out.steering_request) && std::isfinite(out.ax_request));
      EXPECT_TRUE(std::isfinite(out.ay_request) && std::isfinite(out.yaw_rate_request));
    }
    ASSERT_EQ(st->diagnostics.failures, 0) << "s = " << c.s;
    const auto& p = st->plan;
    ASSERT_TRUE(p.valid);
    for (int k = 0; k < o.horizon_steps; ++k) {
      const auto K = static_cast<std::size_t>(k);
      const ST::StateVec x = Eigen::Map<const ST::StateVec>(&p.x[K * 5]);
      const ST::StateVec x1 = Eigen::Map<const ST::StateVec>(&p.x[(K + 1) * 5]);
      const ST::InputVec u = Eigen::Map<const ST::InputVec>(&p.u[K * 2]);
      // Dynamics (the exact discretisation the NLP uses).
      const ST::StateVec f = ST::Discrete(mpc.model(), x, u, p.kappa[K], o.step, o.substeps);
      EXPECT_LT((f - x1).cwiseAbs().maxCoeff(), 1e-3) << "s = " << c.s << " k = " << k;
      // Steering angle and rate.
      EXPECT_LE(std::abs(u[0]), o.max_steering + 1e-6);
      if (k > 0) {
        EXPECT_LE(std::abs(u[0] - p.u[(K - 1) * 2]), o.max_steering_rate * o.step + 1e-4);
      }
      // g-g ellipse at the node's speed (limits frozen at the warm start's: 3 %).
      const double v = std::max(x[ST::kVx], 1.0);
      const double ay = ST::LateralAcceleration(mpc.model(), x, u);
      const double e = std::pow(u[1] / (o.accel_fraction * mpc.limits().AxBrakeMax(v)), 2) +
                       std::pow(ay / (o.accel_fraction * mpc.limits().AyMax(v)), 2);
      EXPECT_LE(e, 1.06) << "s = " << c.s << " k = " << k;
      EXPECT_LE(u[1], 1.03 * o.accel_fraction * mpc.limits().AxDriveMax(v) + 1e-3);
      // Track bounds (tightened by the margin).
      EXPECT_LE(x1[ST::kN], mpc.CorridorLeft(p.s[K + 1]) - o.margin + 0.05);
      EXPECT_GE(x1[ST::kN], -(mpc.CorridorRight(p.s[K + 1]) - o.margin) - 0.05);
    }
  }
}

TEST(MpcTest, StepStaysFiniteOnBadInput) {
  for (const std::string name : {"pmpc", "nmpc"}) {
    const auto& sc = Scenario(name);
    const auto ctl = MakeMotionController(sc);
    auto st = ctl->MakeState();
    cm::MotionInput in = OnPath(*sc.path, 0.0, 500.0);
    in.v_x = std::nan("");
    in.yaw_rate = std::nan("");
    for (int i = 0; i < 3; ++i) {
      in.t = i * ctl->sample_time();
      const auto out = ctl->Step(in, st.get());
      EXPECT_TRUE(std::isfinite(out.steering_request)) << name;
      EXPECT_TRUE(std::isfinite(out.ax_request)) << name;
      EXPECT_TRUE(std::isfinite(out.ay_request)) << name;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Solve times over a drive along the reference (printed; the bound asserted is generous, the
// measurement proper is test/benchmarks/mpc_bench.cc).

template <class Mpc>
void SolveTimes(const std::string& name, double period) {
  const auto& sc = Scenario(name);
  const auto ctl = MakeMotionController(sc);
  auto base = ctl->MakeState();
  auto* st = static_cast<typename Mpc::State*>(base.get());
  double s = 100.0;
  for (int i = 0; i < 120; ++i) {
    const double t = i * period;
    ctl->Step(OnPath(*sc.path, t, s, 0.2 * std::sin(0.1 * i), 0.01 * std::cos(0.13 * i)),
              base.get());
    s += sc.path->Sample(s).v * period;
  }
  const auto& d = st->diagnostics;
  std::printf(
      "[ %s ] %ld solves, median %.2f ms, max %.2f ms, mean %.1f iterations, "
      "%ld failures (period %.0f ms)\n",
      name.c_str(), static_cast<long>(d.solve_time.count()), 1e3 * d.solve_time.Median(),
      1e3 * d.solve_time.max(), double(d.iterations) / std::max<double>(d.solves, 1),
      static_cast<long>(d.failures), 1e3 * period);
  EXPECT_EQ(d.failures, 0);
  EXPECT_LT(d.solve_time.Median(), 4.0 * period);  // generous: shared, loaded CI machines
}

TEST(MpcTest, SolveTimesArePrinted) {
  SolveTimes<cm::PointMassMpc>("pmpc", cm::PmpcOptions{}.solve_period);
  SolveTimes<cm::SingleTrackMpc>("nmpc", cm::NmpcOptions{}.sample_time);
}

// ---------------------------------------------------------------------------------------------
// One lap of the default track at GG 1.0 without stability control.

void Lap(const std::string& name, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> sets = {"motion.controller=" + name,
                                   "laps=1",
                                   "gg_scale=1.0",
                                   "subsystems.esc=false",
                                   "subsystems.cs=false",
                                   "subsystems.abs=false",
                                   "subsystems.tc=false"};
  sets.insert(sets.end(), extra.begin(), extra.end());
  const ResolvedScenario sc = Resolve(DefaultScenario(sets));
  const RunMetrics m = RunClosedLoop(sc, sc.stability);
  ASSERT_EQ(m.status, RunStatus::kCompleted)
      << name << ": " << RunStatusName(m.status) << " at s = " << m.end_s;
  ASSERT_EQ(m.lap_times.size(), 1u);
  std::printf(
      "[ %s ] lap %.3f s (reference %.3f s), max |lateral error| %.2f m, max |beta| "
      "%.2f deg\n",
      name.c_str(), m.lap_times[0], sc.ideal_lap_time, m.max_abs_lateral_error,
      m.max_abs_sideslip * 180.0 / M_PI);
  EXPECT_GT(m.lap_times[0], 0.97 * sc.ideal_lap_time);
  EXPECT_LT(m.lap_times[0], 1.05 * sc.ideal_lap_time);
}

TEST(MpcLapTest, PmpcLapsTheDefaultTrackWithoutStabilityControl) { Lap("pmpc"); }
TEST(MpcLapTest, NmpcLapsTheDefaultTrackWithoutStabilityControl) { Lap("nmpc"); }
// Within the provided limits (issue 48): the same lap on the profile planned at target_fraction.
TEST(MpcLapTest, PmpcWithinTheProvidedLimitsLapsTheDefaultTrack) {
  Lap("pmpc", {"motion.pmpc.limits=provided"});
}

// motion.pmpc.limits=provided: the reference is planned at target_fraction of the planner's
// limits (never faster than the scaled mode's, slower in total), the plan and the feedback use
// the limits themselves (1.0), and every request stays inside the g-g law: |a_n,cmd| ≤ ay_max and
// a_x inside the law at that a_n. The same states in the scaled mode (plan 1.15, feedback 1.3)
// ask for more, so the check can fail.
TEST(PmpcTest, WithinTheProvidedLimitsNoRequestLeavesTheLimits) {
  const std::vector<std::string> base = {"motion.controller=pmpc",
                                         "motion.pmpc.esc_target=commanded"};
  std::vector<std::string> with = base;
  with.push_back("motion.pmpc.limits=provided");
  const ResolvedScenario scaled = Resolve(DefaultScenario(base));
  const ResolvedScenario provided = Resolve(DefaultScenario(with));
  EXPECT_TRUE(PmpcWithinProvidedLimits(provided.spec));
  EXPECT_FALSE(PmpcWithinProvidedLimits(scaled.spec));
  EXPECT_GT(provided.ideal_lap_time, scaled.ideal_lap_time + 1.0);
  for (double s = 0.0; s < scaled.path->length(); s += 25.0)
    EXPECT_LE(provided.path->Sample(s).v, scaled.path->Sample(s).v + 1e-9) << "s = " << s;
  const auto a = MakeMotionController(scaled);
  const auto b = MakeMotionController(provided);
  const auto& pa = dynamic_cast<const cm::PointMassMpc&>(*a);
  const auto& pb = dynamic_cast<const cm::PointMassMpc&>(*b);
  EXPECT_EQ(pb.options().nominal_fraction, 1.0);
  EXPECT_EQ(pb.options().headroom, 1.0);
  const cm::GgTable& g = pb.limits();
  int scaled_over = 0, checked = 0;
  // The car 2 m off the line at 1.15 × the scaled reference speed, at stations all round the lap.
  for (double s = 0.0; s < provided.path->length(); s += 300.0)
    for (double off : {-2.0, 2.0}) {
      auto sa = pa.MakeState();
      auto sb = pb.MakeState();
      for (const cm::PointMassMpc* c : {&pa, &pb}) {
        const bool is_b = c == &pb;
        const cm::MotionInput in = OnPath(*scaled.path, 0.0, s, off, 0.0, 1.15);
        const double v = in.v_x;
        const cm::MotionOutput o = c->Step(in, is_b ? sb.get() : sa.get());
        const double an = std::abs(o.ay_request), ay_max = g.AyMax(v);
        const double drive = g.AxDriveMax(v) * g.DriveFactor(an, ay_max, v);
        const double brake = g.AxBrakeMax(v) * g.BrakeFactor(an, ay_max, v);
        const bool inside = an <= ay_max * (1 + 1e-9) && o.ax_request >= -brake * (1 + 1e-9) &&
                            o.ax_request <= std::max(drive, 0.5) * (1 + 1e-9);
        if (is_b) {
          ++checked;
          EXPECT_TRUE(inside) << "s = " << s << ", offset " << off << ": a_x " << o.ax_request
                              << ", |a_n| " << an << " (ay_max " << ay_max << ", brake " << brake
                              << ", drive " << drive << ")";
        } else if (!inside) {
          ++scaled_over;
        }
      }
    }
  EXPECT_GE(checked, 20);
  EXPECT_GT(scaled_over, 0) << "the scaled mode never left the limits: the check cannot fail";
}

// The ESC's yaw reference from the PMPC (motion.pmpc.esc_target): `plan` publishes the nominal
// plan's normal acceleration, `commanded` the one the steering follows (the plan plus the
// ancillary feedback). Right after a solve from the car's state both agree; one sample later,
// before the next solve, with the car 1 m left of where the plan has it on a straight, the
// commanded one steers back (to the right) while the plan's stays as it was, and the steering
// request is the kinematic steering of the commanded one in both. `steering` publishes none
// (NaN: the stability node then takes its curvature from the steering request) and steers
// exactly as `plan`.
TEST(PmpcTest, EscTargetIsThePlanOrTheCommandedLateralAccelerationOrNone) {
  const ResolvedScenario plan = Resolve(DefaultScenario({"motion.controller=pmpc"}));
  const ResolvedScenario cmd =
      Resolve(DefaultScenario({"motion.controller=pmpc", "motion.pmpc.esc_target=commanded"}));
  const auto a = MakeMotionController(plan);
  const auto b = MakeMotionController(cmd);
  const auto& pa = dynamic_cast<const cm::PointMassMpc&>(*a);
  const auto& pb = dynamic_cast<const cm::PointMassMpc&>(*b);
  EXPECT_EQ(pa.options().esc_target, "plan");
  EXPECT_EQ(pb.options().esc_target, "commanded");
  // s = 50 m lies on the start-finish straight of the default track (κ ≈ 0).
  const double s0 = 50.0, dt = pb.options().sample_time;
  ASSERT_LT(std::abs(plan.path->Sample(s0).kappa), 1e-3);
  ASSERT_LT(dt, pb.options().solve_period);
  auto sa = pa.MakeState();
  auto sb = pb.MakeState();
  const auto a0 = pa.Step(OnPath(*plan.path, 0.0, s0), sa.get());
  const auto b0 = pb.Step(OnPath(*cmd.path, 0.0, s0), sb.get());
  EXPECT_NEAR(a0.ay_request, b0.ay_request, 1e-9);
  EXPECT_EQ(a0.steering_request, b0.steering_request);
  const double v = plan.path->Sample(s0).v, s1 = s0 + v * dt;
  const auto a1 = pa.Step(OnPath(*plan.path, dt, s1, 1.0), sa.get());
  const auto b1 = pb.Step(OnPath(*cmd.path, dt, s1, 1.0), sb.get());
  EXPECT_EQ(a1.steering_request, b1.steering_request);  // the same law
  EXPECT_NEAR(a1.ay_request, a0.ay_request, 0.5) << "the plan has not changed";
  EXPECT_LT(b1.ay_request, a1.ay_request - 1.0) << "1 m left of the plan steers right";
  const double v1 = plan.path->Sample(s1).v;  // the measured speed there (OnPath)
  const double kinematic = std::atan(plan.vehicle.chassis.wheelbase * b1.ay_request / (v1 * v1)) +
                           pb.options().understeer_gradient * b1.ay_request;
  EXPECT_NEAR(b1.steering_request, kinematic, 1e-9);
  const ResolvedScenario st =
      Resolve(DefaultScenario({"motion.controller=pmpc", "motion.pmpc.esc_target=steering"}));
  const auto c = MakeMotionController(st);
  const auto& pc = dynamic_cast<const cm::PointMassMpc&>(*c);
  auto sc = pc.MakeState();
  const auto c0 = pc.Step(OnPath(*st.path, 0.0, s0), sc.get());
  const auto c1 = pc.Step(OnPath(*st.path, dt, s1, 1.0), sc.get());
  EXPECT_TRUE(std::isnan(c0.ay_request) && std::isnan(c1.ay_request));
  EXPECT_EQ(c0.steering_request, a0.steering_request);
  EXPECT_EQ(c1.steering_request, a1.steering_request);
  EXPECT_EQ(c1.ax_request, a1.ax_request);
  try {
    (void)DefaultScenario({"motion.controller=pmpc", "motion.pmpc.esc_target=total"});
    ADD_FAILURE() << "esc_target=total accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("motion.pmpc.esc_target"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("plan|commanded|steering"), std::string::npos) << e.what();
  }
}

// Two PMPCs on the default scenario that publish their commanded a_y: `a` as built in, `b` with
// one more override (a steering-law term under test).
struct PmpcPair {
  explicit PmpcPair(const std::string& extra)
      : base(Resolve(
            DefaultScenario({"motion.controller=pmpc", "motion.pmpc.esc_target=commanded"}))),
        with(Resolve(DefaultScenario(
            {"motion.controller=pmpc", "motion.pmpc.esc_target=commanded", extra}))),
        ca(MakeMotionController(base)),
        cb(MakeMotionController(with)) {}
  const cm::PointMassMpc& a() const { return dynamic_cast<const cm::PointMassMpc&>(*ca); }
  const cm::PointMassMpc& b() const { return dynamic_cast<const cm::PointMassMpc&>(*cb); }
  /// Steps both on `in` and returns b's steering request minus a's; the plan, its feedback and
  /// the speed law must be the same (`ay_request`: the a_y both publish).
  double SteeringChange(const cm::MotionInput& in, double* ay_request) {
    if (!sa) sa = a().MakeState();
    if (!sb) sb = b().MakeState();
    const auto oa = a().Step(in, sa.get());
    const auto ob = b().Step(in, sb.get());
    EXPECT_EQ(oa.ay_request, ob.ay_request) << "the plan and its feedback are the same";
    EXPECT_EQ(oa.ax_request, ob.ax_request);
    *ay_request = ob.ay_request;
    return ob.steering_request - oa.steering_request;
  }
  ResolvedScenario base, with;
  std::unique_ptr<cm::MotionController> ca, cb;
  std::unique_ptr<cm::MotionState> sa, sb;
};

// motion.pmpc.yaw_rate_gain: the steering request is reduced by k (r - a_n,cmd / v), so a car
// that yaws faster than its commanded path is steered out; 0 (the default) leaves the law as it
// was. With esc_target=commanded the published a_y request is a_n,cmd.
TEST(PmpcTest, YawRateFeedbackSteersOutWhenTheCarYawsFasterThanItsPath) {
  PmpcPair pair("motion.pmpc.yaw_rate_gain=0.3");
  EXPECT_EQ(pair.a().options().yaw_rate_gain, 0.0);
  EXPECT_EQ(pair.b().options().yaw_rate_gain, 0.3);
  for (const double s0 : {50.0, 700.0, 1400.0}) {
    for (const double dr : {0.0, 0.1, -0.05}) {
      cm::MotionInput in = OnPath(*pair.base.path, 0.0, s0, 0.2);
      in.yaw_rate += dr;
      double ay = 0.0;
      const double change = pair.SteeringChange(in, &ay);
      EXPECT_NEAR(change, -0.3 * (in.yaw_rate - ay / in.v_x), 1e-12)
          << "s " << s0 << ", yaw-rate offset " << dr;
    }
  }
  EXPECT_THROW((void)DefaultScenario({"motion.controller=pmpc", "motion.pmpc.yaw_rate_gain=-0.1"}),
               ConfigError);
}

// motion.pmpc.lat_accel_gain: the TUM tube MPC's lateral-acceleration feedback. The steering
// request is increased by k (a_n,cmd - a_y) / v², so a car that falls short of its commanded
// lateral acceleration is steered in and one that exceeds it is steered out; the plan, the
// speed law and the published a_y request are untouched, and 0 (the default) leaves the law as
// it was.
TEST(PmpcTest, LateralAccelerationFeedbackSteersInWhenTheCarFallsShortOfItsCommand) {
  PmpcPair pair("motion.pmpc.lat_accel_gain=3");
  EXPECT_EQ(pair.a().options().lat_accel_gain, 0.0);
  EXPECT_EQ(pair.b().options().lat_accel_gain, 3.0);
  int steered_in = 0, steered_out = 0;
  for (const double s0 : {50.0, 700.0, 1400.0}) {
    for (const double ay : {0.0, 12.0, -8.0}) {
      cm::MotionInput in = OnPath(*pair.base.path, 0.0, s0, 0.2);
      in.a_y = ay;
      double ay_request = 0.0;
      const double change = pair.SteeringChange(in, &ay_request);
      const double v = std::hypot(in.v_x, in.v_y);
      const double expected = 3.0 * (ay_request - ay) / (v * v);
      EXPECT_NEAR(change, expected, 1e-12) << "s " << s0 << ", a_y " << ay;
      steered_in += expected > 1e-4 ? 1 : 0;
      steered_out += expected < -1e-4 ? 1 : 0;
    }
  }
  EXPECT_GT(steered_in, 0);
  EXPECT_GT(steered_out, 0);
  EXPECT_THROW((void)DefaultScenario({"motion.controller=pmpc", "motion.pmpc.lat_accel_gain=-1"}),
               ConfigError);
}

TEST(MpcScenarioKeysTest, SettingsComeFromTheScenarioAndAreChecked) {
  const ResolvedScenario p = Resolve(DefaultScenario(
      {"motion.controller=pmpc", "motion.pmpc.horizon_steps=24", "motion.pmpc.q_v=3.5"}));
  const auto pm = MakeMotionController(p);
  const auto* pmpc = dynamic_cast<const cm::PointMassMpc*>(pm.get());
  ASSERT_NE(pmpc, nullptr);
  EXPECT_EQ(pmpc->options().horizon_steps, 24);
  EXPECT_EQ(pmpc->options().q_v, 3.5);
  EXPECT_EQ(pmpc->options().step, params::PmpcParams{}.step);  // not set: the default
  EXPECT_EQ(pmpc->options().sample_time, p.tracking.tS);       // fixed by the tracking loop

  const ResolvedScenario n =
      Resolve(DefaultScenario({"motion.controller=nmpc", "motion.nmpc.substeps=3"}));
  const auto nm = MakeMotionController(n);
  const auto* nmpc = dynamic_cast<const cm::SingleTrackMpc*>(nm.get());
  ASSERT_NE(nmpc, nullptr);
  EXPECT_EQ(nmpc->options().substeps, 3);
  EXPECT_EQ(nmpc->options().max_steering, n.vehicle.steering.max_angle);

  // Bounds and cross-checks of the schema, named by key path.
  auto message = [](const std::vector<std::string>& overrides) {
    try {
      (void)DefaultScenario(overrides);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message({"motion.pmpc.horizon_steps=1"}).find("motion.pmpc.horizon_steps"),
            std::string::npos);
  EXPECT_NE(message({"motion.pmpc.headroom=1.0"}).find("motion.pmpc.headroom"), std::string::npos);
  EXPECT_NE(message({"motion.nmpc.tol=0"}).find("motion.nmpc.tol"), std::string::npos);
  EXPECT_NE(message({"motion.pmpc.limits=hard"}).find("motion.pmpc.limits"), std::string::npos);
  EXPECT_NE(message({"motion.pmpc.limits=hard"}).find("scaled|provided"), std::string::npos);
  EXPECT_NE(message({"motion.pmpc.target_fraction=1.2"}).find("motion.pmpc.target_fraction"),
            std::string::npos);
}

}  // namespace
}  // namespace scw::tuning
