// The vehicle parameter files: eav24.yaml equals the in-class defaults, av21.yaml is valid, and
// the plain YAML round trip is exact.
#include <gtest/gtest.h>

#include <string>

#include "params/io/load.h"
#include "params/io/write.h"
#include "params/schema/vehicle_params.h"
#include "plant/vehicle/vehicle.h"

namespace scw::params {
namespace {

const std::string kDir = std::string(SCW_SOURCE_DIR) + "/params/vehicles/";

TEST(VehicleParamsFiles, Eav24FileEqualsTheInClassDefaults) {
  const VehicleParams file = LoadPlainFile<VehicleParams>(kDir + "eav24.yaml");
  const VehicleParams defaults;
  const auto differing = DifferingKeys(file, defaults);
  std::string list;
  for (const auto& k : differing) list += k + " ";
  EXPECT_TRUE(differing.empty())
      << "eav24.yaml differs from the defaults in: " << list
      << "\nregenerate with: scw vehicle init -o params/vehicles/eav24.yaml";
}

TEST(VehicleParamsFiles, Av21FileIsValidAndDiffersWhereExpected) {
  const VehicleParams p = LoadPlainFile<VehicleParams>(kDir + "av21.yaml");
  EXPECT_EQ(p.name, "av21");
  EXPECT_DOUBLE_EQ(p.chassis.mass, 750.0);
  EXPECT_DOUBLE_EQ(p.chassis.wheelbase, 2.971);
  EXPECT_DOUBLE_EQ(p.tires.front.pky1, -53.05);
  EXPECT_EQ(p.gearbox.ratios.size(), 6u);
  const plant::Vehicle v(p);  // validates
  EXPECT_GT(v.time_step(), 0.0);
}

TEST(VehicleParamsFiles, PlainYamlRoundTripIsExact) {
  VehicleParams p;
  p.grip.wheel_mu_x = {1.0, 0.5, 1.0, 0.5};
  p.tires.front.pdy1 = 1.234567890123;
  const VehicleParams q = LoadPlainText<VehicleParams>(ToPlainYaml(p), "round-trip");
  EXPECT_TRUE(DifferingKeys(p, q).empty());
}

}  // namespace
}  // namespace scw::params
