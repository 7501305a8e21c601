// The vehicle model of the stability controller: the speed-dependent front brake bias (spec
// Appendix B).
#include "controller/stability/vehicle_model.h"

#include <gtest/gtest.h>

#include "params/schema/stability_params.h"

namespace scw::controller {
namespace {

TEST(VehicleModelTest, BrakeBiasOfAppendixB) {
  const params::StabilityParams p;
  auto b = [&](double v) {
    return FrontBrakeBias(v, p.P_VDC_brake_bias_front, p.brake_bias_shift);
  };
  EXPECT_NEAR(b(7.0), 0.433, 5e-4);
  EXPECT_NEAR(b(25.0), 0.497, 5e-4);
  EXPECT_NEAR(b(50.0), 0.561, 5e-4);
  EXPECT_NEAR(b(60.0), 0.58, 5e-4);
  EXPECT_NEAR(b(80.0), 0.618, 5e-4);
}

}  // namespace
}  // namespace scw::controller
