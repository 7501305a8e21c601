// The controller log written by a closed-loop run (RunOptions::on_controller_input) replays the
// simulation's controller outputs exactly (tuning/replay/controller_log.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <vector>

#include "tuning/replay/controller_log.h"
#include "tuning/sim/closed_loop.h"

namespace scw::tuning::replay {
namespace {

TEST(ClosedLoopTest, ControllerLogReplaysTheSimulationExactly) {
  params::ScenarioParams spec =
      DefaultScenario({"laps=1", "grip.rear_mu_y=0.8", "plan_with_nominal_grip=true",
                       "gg_scale=1.1", "abort.lock_slip_pct=100"});
  const ResolvedScenario sc = Resolve(spec);
  const std::string path =
      (std::filesystem::temp_directory_path() / "scw_closed_loop_controller_log.csv").string();
  std::vector<controller::StabilityOutput> recorded;
  {
    ControllerLogWriter log(path);
    RunOptions ro;
    ro.on_controller_input = [&](const controller::StabilityInput& in) { log.Write(in); };
    ro.on_controller_output = [&](const controller::StabilityOutput& o) { recorded.push_back(o); };
    RunClosedLoop(sc, sc.stability, ro);
    log.Commit();
  }
  ASSERT_GT(recorded.size(), 500u);
  const controller::StabilityController ctl(PrepareStability(sc, sc.stability));
  controller::StabilityController::State state;
  ControllerLogReader reader(path);
  controller::StabilityInput in;
  std::size_t row = 0;
  bool any_intervention = false;
  while (reader.Next(&in)) {
    ASSERT_LT(row, recorded.size());
    const auto out = ctl.Step(in, &state);
    const auto& ref = recorded[row];
    ASSERT_EQ(out.steering, ref.steering) << "row " << row;
    ASSERT_EQ(out.brake_bar, ref.brake_bar) << "row " << row;
    ASSERT_EQ(out.throttle, ref.throttle) << "row " << row;
    ASSERT_EQ(out.yaw_moment, ref.yaw_moment) << "row " << row;
    ASSERT_EQ(out.esc_active, ref.esc_active) << "row " << row;
    any_intervention = any_intervention || out.esc_active || out.cs_active;
    ++row;
  }
  EXPECT_EQ(row, recorded.size());
  EXPECT_TRUE(any_intervention);
}

}  // namespace
}  // namespace scw::tuning::replay
