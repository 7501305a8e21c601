// The scenario's plant section on the command line (issue 25), end to end with the built `scw`
// program: `scw vehicle balance --brake-dead-time` prints the lag that keeps the total brake
// response and refuses an infeasible dead time before printing anything; a bad plant key given
// with --set is bad input (exit 2) naming the key and the rule.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "test/common/cli_run.h"

namespace scw {
namespace {

namespace fs = std::filesystem;

using Output = test::CliResult;

Output Scw(const std::string& args) {
  const fs::path dir = fs::temp_directory_path() / ("scw_plant_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Output r = test::RunCli(SCW_BIN, args, dir);
  fs::remove_all(dir);
  return r;
}

TEST(PlantSectionCliTest, BalancePrintsTheLagThatKeepsTheBrakeResponse) {
  const Output r = Scw("vehicle balance --speeds 40 --brake-dead-time 0.03");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("brake actuator: 63 % of an 80 bar step after 150 ms (dead time 116 ms"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("  with dead time 30.0 ms: lag 119.5 ms keeps 63 % at 150 ms (feasible "
                       "dead times 0-121 ms)"),
            std::string::npos)
      << r.out;
  const Output bad = Scw("vehicle balance --speeds 40 --brake-dead-time 0.13");
  EXPECT_EQ(bad.code, 2);
  EXPECT_EQ(bad.out, "");  // refused before anything is printed
  EXPECT_NE(bad.err.find("scw vehicle balance: --brake-dead-time: 0.13 s is outside the feasible "
                         "range 0-0.121 s"),
            std::string::npos)
      << bad.err;
}

TEST(PlantSectionCliTest, BadPlantKeysAreBadInput) {
  const Output r = Scw("simulate --set plant.actuators=ideal --progress never");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("plant.actuators: 'ideal' is not one of vehicle|paper_sim"),
            std::string::npos)
      << r.err;
  const Output dead =
      Scw("simulate --set plant.actuators=paper_sim --set plant.brake_dead_time=0.05 "
          "--set laps=1 --progress never");
  EXPECT_EQ(dead.code, 2);
  EXPECT_NE(dead.err.find("plant.brake_dead_time: 0.05 s is outside the feasible range 0-0 s"),
            std::string::npos)
      << dead.err;
}

}  // namespace
}  // namespace scw
