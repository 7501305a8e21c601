// The setup file of a controller log (tuning/replay/log_setup.h): what the recorded controller
// used besides its params file (vehicle constants, subsystem switches), so that a replay reproduces
// the simulation it was recorded from (issue 15).
#include "tuning/replay/log_setup.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "params/io/write.h"
#include "test/tuning/replay/log_stories.h"
#include "tuning/replay/controller_log.h"
#include "tuning/sim/scenario.h"

namespace scw::tuning::replay {
namespace {

using testing::ReadFile;
using testing::SameBits;
using testing::TempDir;

TEST(ControllerLogSetup, KeysTheParamsFileSetsWinTheOthersAreRecorded) {
  ControllerLogSetup setup;
  setup.vehicle.mass.total = 777.5;
  setup.vehicle.dimension.wheelbase = 3.1;
  setup.vehicle.drivetrain.gear_ratios = {3.0, 2.0, 1.5, 1.2, 1.0, 0.9};
  setup.tires.rear_left.radius.radius_20mps = 0.31;
  setup.subsystems.tc = false;

  params::StabilityParams file;
  file.vehicle.mass.total = 690.0;  // set by the params file
  file.ESC.kp_psi_dot = 1.25;       // not a vehicle constant: never touched
  const params::StabilityParams p = ApplySubsystemSwitches(
      WithRecordedVehicle(file, {"vehicle.mass.total"}, setup), setup.subsystems);
  EXPECT_EQ(p.vehicle.mass.total, 690.0);
  EXPECT_EQ(p.vehicle.dimension.wheelbase, 3.1);
  EXPECT_EQ(p.vehicle.drivetrain.gear_ratios, setup.vehicle.drivetrain.gear_ratios);
  EXPECT_EQ(p.tires.rear_left.radius.radius_20mps, 0.31);
  EXPECT_EQ(p.ESC.kp_psi_dot, 1.25);
  EXPECT_FALSE(p.SlipControl.TC.enabled);
  EXPECT_TRUE(p.SlipControl.ABS.enabled);
  EXPECT_TRUE(p.ESC.enabled);
}

TEST(ControllerLogSetup, ClosedLoopSetupIsWhatTheControllerRunsWith) {
  const ResolvedScenario sc = Resolve(DefaultScenario({"subsystems.cs=false", "laps=1"}));
  const ControllerLogSetup setup = ClosedLoopSetup(sc, sc.stability);
  const params::StabilityParams used = PrepareStability(sc, sc.stability);
  // The built-in run loads no params file: every key is the recorded one.
  const params::StabilityParams replayed = ApplySubsystemSwitches(
      WithRecordedVehicle(params::StabilityParams{}, {}, setup), setup.subsystems);
  EXPECT_TRUE(params::DifferingKeys(replayed, used).empty());
  EXPECT_FALSE(replayed.countersteer_system.enabled);
  // ... while the node's code defaults differ from the simulated car.
  EXPECT_FALSE(params::DifferingKeys(params::StabilityParams{}, used).empty());
}

TEST(ControllerLogSetup, FileRoundTripAndTheLogItBelongsTo) {
  const TempDir dir("scw_log_setup");
  const params::StabilityParams p;
  std::vector<controller::StabilityInput> rows;
  for (int k = 0; k < 20; ++k) rows.push_back(testing::SyntheticRow(p, k));
  ControllerLogSetup setup;
  setup.source = "test, with \"quotes\"";
  setup.vehicle.aero.lift_coeff = -1.0 / 3.0;
  setup.subsystems.release_compat = true;
  std::string setup_path;
  {
    ControllerLogWriter w(dir.File("log.csv"));
    for (const auto& r : rows) w.Write(r);
    setup_path = CommitWithSetup(w, setup);
  }
  EXPECT_EQ(setup_path, dir.File("log.csv.setup.yaml"));
  const ControllerLogSetup back = LoadSetup(setup_path);
  EXPECT_EQ(back.source, setup.source);
  EXPECT_EQ(back.log_rows, 20);
  EXPECT_EQ(back.log_bytes, static_cast<double>(ReadFile(dir.File("log.csv")).size()));
  EXPECT_TRUE(SameBits(back.vehicle.aero.lift_coeff, -1.0 / 3.0));
  EXPECT_TRUE(back.subsystems.release_compat);
  EXPECT_NO_THROW(CheckSetupMatchesLog(back, setup_path, dir.File("log.csv")));

  // The log written again without its setup (another tool): the setup is refused.
  testing::WriteLog(dir.File("log.csv"), {rows[0], rows[1]});
  try {
    CheckSetupMatchesLog(back, setup_path, dir.File("log.csv"));
    FAIL() << "a setup of another log was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--no-log-setup"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace scw::tuning::replay
