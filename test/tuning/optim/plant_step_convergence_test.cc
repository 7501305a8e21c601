// Plant-step convergence on the critical situations (issue 18 part 4; docs/plant-step.md): the
// scenario key plant_step, and the closed loop of the car's shipped set at 0.5, 1 and 2 ms on the
// training scenarios where ABS and TC cycle, a wheel locks and the car spins. What the stability
// controller sees and does must not depend on the step beyond the closed loop's own sensitivity:
// the same outcome class, the same subsystems acting, their first activation, the spin onset and
// a lock-up abort within a few controller periods, ABS and TC active times before a spin within a
// quarter, lap times within 0.1 s.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "params/io/write.h"
#include "test/tuning/optim/default_training.h"
#include "tuning/optim/plant_step_check.h"
#include "tuning/sim/closed_loop.h"
#include "tuning/sim/scenario.h"
#include "tuning/sim/scenario_set.h"

namespace scw::tuning {
namespace {

ResolvedScenario AtStep(const std::string& name, double step) {
  ScenarioEntry e = DefaultTraining(name);
  if (step > 0.0) e = WithPlantStep({e}, step).front();
  return Resolve(LoadEntry(e, ""));
}

TEST(PlantStepKey, SetsTheVehicleStepAndSharesThePreparation) {
  const ResolvedScenario own = AtStep("power_on_c1", 0.0);
  const ResolvedScenario coarse = AtStep("power_on_c1", 0.002);
  EXPECT_EQ(own.vehicle.simulation.time_step, 0.001);
  EXPECT_EQ(coarse.vehicle.simulation.time_step, 0.002);
  // The racing line, the g-g-v table and the reference do not depend on the step.
  EXPECT_EQ(own.ideal_lap_time, coarse.ideal_lap_time);
  EXPECT_EQ(own.limit_lap_time, coarse.limit_lap_time);
  EXPECT_EQ(own.path->length(), coarse.path->length());
  // Everything but the step is the same scenario.
  params::VehicleParams v = coarse.vehicle;
  v.simulation.time_step = own.vehicle.simulation.time_step;
  EXPECT_TRUE(params::DifferingKeys(v, own.vehicle).empty());
}

TEST(PlantStepKey, AStepThatDoesNotDivideTheControllerPeriodIsRefusedByName) {
  ScenarioEntry e = DefaultTraining("power_on_c1");
  e.overrides.push_back("plant_step=0.003");
  try {
    Resolve(LoadEntry(e, ""));
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("plant_step"), std::string::npos) << what;
    EXPECT_NE(what.find("must divide the controller period"), std::string::npos) << what;
  }
  e.overrides.back() = "plant_step=0.006";  // beyond the schema's bound
  EXPECT_THROW(LoadEntry(e, ""), ConfigError);
}

/// What the stability controller saw and did in one run.
struct Signature {
  RunMetrics m;
  double first_esc = NAN, first_abs = NAN, first_tc = NAN;  ///< [s] first activation
  double spin_onset = NAN;                                  ///< [s] first |β| > 10°
  /// [s] ABS / TC active before the spin onset (the whole run without one): their cycling while
  /// the car is still under control. After the onset a spinning car's path is chaotic (which abort
  /// rule trips first, and when, differs between 0.5 and 1 ms already).
  double abs_active = 0.0, tc_active = 0.0;
};

Signature Observe(const ResolvedScenario& sc) {
  Signature s;
  double t = 0.0;
  RunOptions o;
  o.on_controller_input = [&](const controller::StabilityInput& in) {
    t = in.t;
    const double beta = std::atan2(in.v_y, std::max(std::abs(in.v_x), 1.0));
    if (std::isnan(s.spin_onset) && std::abs(beta) > 10.0 * M_PI / 180.0) s.spin_onset = t;
  };
  o.on_controller_output = [&](const controller::StabilityOutput& out) {
    const auto first = [&](double* at, bool active) {
      if (active && std::isnan(*at)) *at = t;
    };
    first(&s.first_esc, out.esc_active);
    bool abs = false, tc = false;
    for (std::size_t w = 0; w < 4; ++w) {
      abs = abs || controller::IsActive(out.abs_state[w]);
      tc = tc || controller::IsActive(out.tc_state[w]);
    }
    first(&s.first_abs, abs);
    first(&s.first_tc, tc);
    if (std::isnan(s.spin_onset)) {
      s.abs_active += abs ? sc.stability.tS : 0.0;
      s.tc_active += tc ? sc.stability.tS : 0.0;
    }
  };
  s.m = RunClosedLoop(sc, sc.stability, o);
  return s;
}

/// |a − b| for two times that both exist (or both do not).
double Gap(double a, double b) {
  if (std::isnan(a) && std::isnan(b)) return 0.0;
  return std::abs(a - b);  // NaN (one exists only) fails every bound
}

std::string Describe(const Signature& s) {
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "%-13s end %7.3f s, first ESC %6.2f ABS %6.2f TC %6.2f s, spin %6.2f s, "
                "active before it ABS %5.2f TC %5.2f s, ESC/CS/ABS/TC %d/%d/%d/%d",
                RunStatusName(s.m.status), s.m.time, s.first_esc, s.first_abs, s.first_tc,
                s.spin_onset, s.abs_active, s.tc_active, s.m.esc_count, s.m.cs_count, s.m.abs_count,
                s.m.tc_count);
  return buf;
}

struct Case {
  const char* name;
  const char* what;  // the critical behaviour it stands for
};

class PlantStepConvergenceTest : public ::testing::TestWithParam<Case> {};

TEST_P(PlantStepConvergenceTest, TwoMillisecondsDecideAsTheVehiclesOwnStep) {
  const Case& c = GetParam();
  const Signature half = Observe(AtStep(c.name, 0.0005));
  const Signature own = Observe(AtStep(c.name, 0.0));
  const Signature coarse = Observe(AtStep(c.name, 0.002));
  std::printf("%s (%s)\n  0.5 ms: %s\n  1 ms:   %s\n  2 ms:   %s\n", c.name, c.what,
              Describe(half).c_str(), Describe(own).c_str(), Describe(coarse).c_str());
  // A few controller periods (the actuators alone take 30 ms and 150 ms to respond).
  constexpr double kTime = 0.05;
  for (const Signature* other : {&half, &coarse}) {
    const Signature& s = *other;
    SCOPED_TRACE(std::string(c.name) + (other == &half ? " at 0.5 ms" : " at 2 ms"));
    EXPECT_EQ(OutcomeClass(s.m.status), OutcomeClass(own.m.status));
    if (own.m.aborted() && std::isnan(own.spin_onset)) {
      EXPECT_LE(std::abs(s.m.time - own.m.time), kTime) << "abort time";
    } else if (own.m.aborted()) {  // a spin: its onset below decides, the abort follows it
      EXPECT_GT(s.m.time, s.spin_onset);
    } else {
      EXPECT_LE(std::abs(s.m.MeanLapTime() - own.m.MeanLapTime()), 0.1) << "lap time";
    }
    EXPECT_LE(Gap(s.first_esc, own.first_esc), kTime) << "first ESC activation";
    EXPECT_LE(Gap(s.first_abs, own.first_abs), kTime) << "first ABS activation";
    EXPECT_LE(Gap(s.first_tc, own.first_tc), kTime) << "first TC activation";
    EXPECT_LE(Gap(s.spin_onset, own.spin_onset), kTime) << "spin onset";
    // ABS and TC cycling: their active time while the car is under control.
    EXPECT_LE(std::abs(s.abs_active - own.abs_active), std::max(0.1, 0.25 * own.abs_active));
    EXPECT_LE(std::abs(s.tc_active - own.tc_active), std::max(0.1, 0.25 * own.tc_active));
    EXPECT_EQ(s.m.esc_count > 0, own.m.esc_count > 0);
    EXPECT_EQ(s.m.abs_count > 0, own.m.abs_count > 0);
    EXPECT_EQ(s.m.tc_count > 0, own.m.tc_count > 0);
  }
}

INSTANTIATE_TEST_SUITE_P(
    CriticalTrainingScenarios, PlantStepConvergenceTest,
    ::testing::Values(Case{"clean_gg1.2", "ABS and TC cycling over two laps at the limit"},
                      Case{"power_on_c1", "TC cycling, survived"},
                      Case{"late_braking_c8", "ABS on a late brake point, ESC"},
                      Case{"wet_braking_c1", "ABS on a wet braking zone"},
                      Case{"power_on_c7", "lock-up: ends by wheel_lock"},
                      Case{"power_on_c3_apex", "spin onset: ends by sideslip"},
                      Case{"rear_grip_loss_c3", "spin onset after rear grip loss"}),
    [](const ::testing::TestParamInfo<Case>& param) {
      std::string n = param.param.name;
      std::replace(n.begin(), n.end(), '.', '_');
      return n;
    });

}  // namespace
}  // namespace scw::tuning
