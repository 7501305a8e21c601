// The scenario's plant model (plant.model, tuning/sim/plant_choice.h): scw's plant by default,
// Open-Car-Dynamics where the build has it, and a clear error where it does not.
#include "tuning/sim/plant_choice.h"

#include <gtest/gtest.h>

#include <string>

#include "params/schema/vehicle_params.h"
#include "tuning/sim/scenario.h"

namespace scw::tuning {
namespace {

std::string ErrorOf(const params::ScenarioParams& spec) {
  try {
    (void)ResolveCar(spec);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(PlantChoiceTest, ScwIsTheDefaultAndItsTimeStepTheVehicles) {
  EXPECT_EQ(DefaultScenario().plant.model, "scw");
  const PlantChoice choice("scw", params::VehicleParams{});
  EXPECT_EQ(choice.time_step(), params::VehicleParams{}.simulation.time_step);
  EXPECT_TRUE(PlantNotes("scw", params::VehicleParams{}).empty());
}

TEST(PlantChoiceTest, AnUnknownModelIsAnErrorNamingTheKeyAndTheChoices) {
  std::string e;
  try {
    (void)DefaultScenario({"plant.model=carsim"});
  } catch (const ConfigError& x) {
    e = x.what();
  }
  EXPECT_NE(e.find("plant.model"), std::string::npos) << e;
  EXPECT_NE(e.find("'carsim' is not one of scw|ocd"), std::string::npos) << e;
  // The same from code that builds the plant directly.
  try {
    const PlantChoice choice("carsim", params::VehicleParams{});
    FAIL() << "no error";
  } catch (const ConfigError& x) {
    EXPECT_NE(std::string(x.what()).find("plant.model"), std::string::npos) << x.what();
    EXPECT_NE(std::string(x.what()).find("scw|ocd"), std::string::npos) << x.what();
  }
}

TEST(PlantChoiceTest, OcdWithoutTheBuildNamesTheOption) {
  if (kHaveOcdPlant) GTEST_SKIP() << "this build has Open-Car-Dynamics";
  const std::string e = ErrorOf(DefaultScenario({"plant.model=ocd"}));
  EXPECT_NE(e.find("plant.model"), std::string::npos) << e;
  EXPECT_NE(e.find("SCW_WITH_OCD"), std::string::npos) << e;
  EXPECT_THROW(PlantChoice("ocd", params::VehicleParams{}), ConfigError);
}

TEST(PlantChoiceTest, OcdRunsTheCarAndRefusesWhatItCannotRepresent) {
  if (!kHaveOcdPlant) GTEST_SKIP() << "this build has no Open-Car-Dynamics";
  const PlantChoice choice("ocd", params::VehicleParams{});
  EXPECT_EQ(choice.time_step(), params::VehicleParams{}.simulation.time_step);
  EXPECT_FALSE(PlantNotes("ocd", params::VehicleParams{}).empty());
  EXPECT_EQ(ErrorOf(DefaultScenario({"plant.model=ocd", "kind=maneuver"})), "");
  const std::string e =
      ErrorOf(DefaultScenario({"plant.model=ocd", "kind=maneuver", "plant.rear_tire_falloff=2"}));
  EXPECT_NE(e.find("tires.rear.falloff"), std::string::npos) << e;
}

}  // namespace
}  // namespace scw::tuning
