// Step (nominal and with an environment incl. wind), Measure (with noise) and the actuator/gearbox
// updates allocate nothing. This binary replaces the global operator new with a counting one, so it
// is built apart from the other tests.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "params/schema/vehicle_params.h"
#include "plant/vehicle/maneuver.h"
#include "plant/vehicle/vehicle.h"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

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
    const long before = g_allocations.load();
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
    EXPECT_EQ(g_allocations.load() - before, 0) << diff;
    EXPECT_EQ(s.status, kStatusOk);
  }
}

TEST(PlantAllocation, GuardCountsAllocations) {
  const long before = g_allocations.load();
  // A direct call (a new-expression may legally be elided by the optimiser).
  void* volatile p = ::operator new(64);
  ::operator delete(p);
  EXPECT_EQ(g_allocations.load() - before, 1);
}

}  // namespace
}  // namespace scw::plant
