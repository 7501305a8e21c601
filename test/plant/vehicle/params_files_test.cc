// The vehicle parameter files: eav24.yaml equals the in-class defaults, av21.yaml is valid, and
// the plain YAML round trip is exact.
#include <gtest/gtest.h>

#include <fstream>
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

// The roll/pitch modes came later and are optional: a vehicle file written before them loads
// with the first-order load-transfer lag it was made for.
TEST(VehicleParamsFiles, AFileWithoutTheRollPitchModesKeepsTheFirstOrderLag) {
  std::ifstream in(kDir + "eav24.yaml");
  std::string text, line;
  int dropped = 0;
  while (std::getline(in, line)) {
    if (line.find("load_transfer_frequency") != std::string::npos ||
        line.find("load_transfer_damping_ratio") != std::string::npos) {
      ++dropped;
      continue;
    }
    text += line + "\n";
  }
  ASSERT_EQ(dropped, 2);
  const VehicleParams p = LoadPlainText<VehicleParams>(text, "eav24 without the modes");
  EXPECT_EQ(p.chassis.load_transfer_frequency, 0.0);
  EXPECT_TRUE(DifferingKeys(p, VehicleParams{}).empty());
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
