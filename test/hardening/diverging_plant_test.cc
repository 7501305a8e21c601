// A plant that diverges mid-run inside a batch: the broken runs end with a named status and a
// finite cost, and the batch carries on — the healthy scenario's result is the same as when it
// is evaluated alone. Broken in two ways without touching the closed loop's API:
//  * ice: grip 0.05 while the reference is planned with the nominal grip → the car slides off;
//  * an absurd but schema-valid vehicle file (featherweight car and wheels, stiff tyres, coarse
//    plant step) whose plant leaves the road within seconds (off track, or NaN → kNonFinite).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "params/io/atomic_file.h"
#include "params/io/load.h"
#include "params/io/write.h"
#include "params/schema/vehicle_params.h"
#include "tuning/optim/evaluator.h"

namespace scw::tuning {
namespace {

namespace fs = std::filesystem;

TEST(DivergingPlantTest, BrokenScenariosEndWithAStatusAndTheBatchContinues) {
  const fs::path dir =
      fs::temp_directory_path() / ("scw_diverging_plant_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  // Every value within its schema bounds, together absurd: a 100 kg car with a tenth of the
  // wheel inertia, five times the tyre stiffness, 1 cm relaxation lengths and a 5 ms plant step.
  params::VehicleParams v;
  v.chassis.mass = 100.0;
  v.chassis.yaw_inertia = 10.0;
  v.wheels.inertia_front = 0.05;
  v.wheels.inertia_rear = 0.05;
  for (auto* t : {&v.tires.front, &v.tires.rear}) t->lkx = t->lky = 5.0;
  v.tires.kinematics.relaxation_length_long = 0.01;
  v.tires.kinematics.relaxation_length_lat = 0.01;
  v.tires.kinematics.relaxation_speed_min = 50.0;
  v.simulation.time_step = 0.005;
  io::WriteFileAtomic((dir / "absurd.yaml").string(), params::ToPlainYaml(v));

  const std::vector<ScenarioEntry> entries = {
      {"healthy", 1.0, "", {"laps=1", "gg_scale=1.0"}},
      {"ice", 1.0, "", {"laps=1", "grip.mu=0.05", "plan_with_nominal_grip=true"}},
      {"absurd_vehicle",
       1.0,
       "",
       {"laps=1", "vehicle=" + (dir / "absurd.yaml").string(), "gg_scale=1.0"}},
  };
  const params::CostWeights w;
  const auto batch = BatchEvaluator::FromEntries(entries, "", w, 2);
  const params::StabilityParams p;
  const SetEvaluation r = batch.Evaluate(p);
  ASSERT_EQ(r.runs.size(), 3u);
  EXPECT_EQ(r.runs[0].status, RunStatus::kCompleted);
  for (std::size_t k = 1; k < 3; ++k) {
    SCOPED_TRACE(entries[k].name);
    EXPECT_TRUE(r.runs[k].aborted()) << RunStatusName(r.runs[k].status);
    EXPECT_TRUE(std::isfinite(r.costs[k].total));
    EXPECT_GT(r.costs[k].total, r.costs[0].total);
    EXPECT_LT(r.runs[k].Progress(), 1.0);
  }
  EXPECT_TRUE(std::isfinite(r.total));

  // The healthy run is unaffected by its broken neighbours.
  const auto alone = BatchEvaluator::FromEntries({entries[0]}, "", w, 1).Evaluate(p);
  EXPECT_EQ(alone.runs[0].lap_times, r.runs[0].lap_times);
  EXPECT_EQ(alone.costs[0].total, r.costs[0].total);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace scw::tuning
