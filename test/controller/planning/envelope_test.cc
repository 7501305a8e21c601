// The planner's g-g-v table from the plant's combined envelope: the fitted law lies inside the
// sampled envelope (the full-limit lap and the feasibility of the reference planned at 100 % of
// it are checked on a whole scenario: test/tuning/sim/scenario_test.cc).
#include "controller/planning/envelope.h"

#include <gtest/gtest.h>

namespace scw::controller::planning {
namespace {

TEST(PlantEnvelope, FittedLawLiesInsideTheSampledEnvelope) {
  const params::VehicleParams p;
  const auto rows = SampleEnvelope(p, 0.58, {20.0, 40.0, 60.0});
  const auto g = FitEnvelope(rows);
  for (const EnvelopeRow& r : rows)
    for (std::size_t j = 0; j < kEnvelopeLevels.size(); ++j) {
      const double ay = kEnvelopeLevels[j] * r.ay_max;
      EXPECT_LE(g.AxDriveMax(r.speed) * g.DriveFactor(ay, g.AyMax(r.speed), r.speed),
                r.drive[j] + 1e-9);
      EXPECT_LE(g.AxBrakeMax(r.speed) * g.BrakeFactor(ay, g.AyMax(r.speed), r.speed),
                r.brake[j] + 1e-9);
    }
  // Both capacities fall with lateral load.
  EXPECT_LT(rows[0].drive.back(), rows[0].drive.front());
  EXPECT_LT(rows[0].brake.back(), rows[0].brake.front());
}

}  // namespace
}  // namespace scw::controller::planning
