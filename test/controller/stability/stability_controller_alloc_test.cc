// Allocation guard: the global operator new/delete of this test binary count calls, and a long
// run of StabilityController::Step — including NaN, inf and missing inputs — must allocate nothing.
#include <gtest/gtest.h>

#include <limits>
#include <new>

#include "controller/stability/stability_controller.h"
#include "test/common/alloc_counter.h"
#include "test/controller/stability/scenario_inputs.h"

namespace scw::controller {
namespace {

TEST(StabilityControllerAllocationTest, StepAllocatesNothing) {
  const params::StabilityParams p;
  const StabilityController c(p);
  StabilityController::State s;
  constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
  // Build all inputs before counting.
  std::vector<StabilityInput> inputs;
  for (int k = 0; k < 4000; ++k) {
    const double t = 0.01 * k;
    StabilityInput in;
    switch ((k / 100) % 5) {
      case 0:
        in = testing::Cruise(p, t);
        break;
      case 1:
        in = testing::Oversteer(p, t);
        break;
      case 2:
        in = testing::Lockup(p, t, k % 100);
        break;
      case 3:
        in = testing::RearSpin(p, t);
        break;
      default:
        in = testing::Oversteer(p, t);
        if (k % 3 == 0) in.v_x = kNan;
        if (k % 3 == 1) in.wheel_speed[kRL] = kNan;
        if (k % 3 == 2) in.a_y = std::numeric_limits<double>::infinity();
    }
    inputs.push_back(in);
  }
  const long before = AllocationCount();
  double sink = 0.0;
  for (const auto& in : inputs) sink += c.Step(in, &s).brake_bar[kFR];
  const long after = AllocationCount();
  EXPECT_EQ(after - before, 0) << "Step allocated";
  EXPECT_TRUE(std::isfinite(sink));
  // The guard itself works.
  const long probe = AllocationCount();
  void* volatile probe_block = ::operator new(16);
  ::operator delete(probe_block);
  EXPECT_EQ(AllocationCount() - probe, 1);
}

}  // namespace
}  // namespace scw::controller
