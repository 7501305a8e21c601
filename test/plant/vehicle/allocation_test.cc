// Step (nominal and with an environment incl. wind), Measure (with noise) and the actuator/gearbox
// updates allocate nothing. This binary replaces the global operator new with a counting one, so it
// is built apart from the other tests.
#include <gtest/gtest.h>

#include <cmath>
#include <new>

#include "params/schema/vehicle_params.h"
#include "plant/vehicle/maneuver.h"
#include "plant/vehicle/vehicle.h"
#include "test/common/alloc_counter.h"

namespace scw::plant {
namespace {

TEST(PlantAllocation, StepAndMeasureAllocateNothing) {
  for (const char* diff : {"spool", "lsd"}) {
    params::VehicleParams p;
    p.differential.type = diff;
    p.sensors.noise = true;
    const Vehicle v(p);
    State s = v.MakeState();
    SensorNoiseState noise(3);
    const double radius = p.wheels.radius_rear;
    const long before = AllocationCount();
    Environment gusty;
    gusty.mu[kRL] = 0.7;
    for (int k = 0; k < 30000; ++k) {
      const Measurement m = v.Measure(s, &noise);
      const Actuators u = ReferenceManeuverInput(s.time, m, radius);
      if (k % 2 == 0) {
        v.Step(u, &s);
      } else {  // the environment path, with wind
        gusty.wind_x = 5.0 * std::sin(1e-3 * k);
        gusty.wind_y = -8.0;
        v.Step(u, gusty, &s);
      }
    }
    EXPECT_EQ(AllocationCount() - before, 0) << diff;
    EXPECT_EQ(s.status, kStatusOk);
  }
}

TEST(PlantAllocation, GuardCountsAllocations) {
  const long before = AllocationCount();
  // A direct call (a new-expression may legally be elided by the optimiser).
  void* volatile p = ::operator new(64);
  ::operator delete(p);
  EXPECT_EQ(AllocationCount() - before, 1);
}

}  // namespace
}  // namespace scw::plant
