// Replay reproduces the simulation it was recorded from (issue 15), end to end:
// `scw simulate --controller-log` followed by `scw replay` with the same params file, compared bit
// for bit with what the simulation's controller produced (its trace) and with the interventions
// the run counted (its summary).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "params/io/load.h"
#include "params/io/write.h"
#include "test/tuning/replay/log_stories.h"
#include "tuning/replay/log_setup.h"
#include "tuning/replay/replay.h"
#include "tuning/sim/scenario.h"

namespace scw::tuning::replay {
namespace {

using testing::CsvTable;
using testing::ReadCsv;
using testing::ReadFile;
using testing::SameBits;
using testing::TempDir;

std::string Shipped() { return std::string(SCW_SOURCE_DIR) + "/params/stability/default.yaml"; }

int RunScw(const std::string& args, const std::string& capture) {
  const std::string cmd = std::string(SCW_BIN) + " " + args + " > " + capture + " 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// ---------------------------------------------------------------------------------------------
// End to end: scw simulate, then scw replay of its controller log.

/// Interventions of the replay summary (stdout of `scw replay LOG --params F`).
std::map<std::string, long> SummaryInterventions(const std::string& text) {
  std::map<std::string, long> counts;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string name;
    long n = -1;
    if (words >> name >> n) counts[name] = n;
  }
  return counts;
}

/// Integer `key: N` of the run summary YAML.
long YamlInt(const std::string& text, const std::string& key) {
  const std::size_t at = text.find("\n" + key + ": ");
  if (at == std::string::npos) return -1;
  return std::stol(text.substr(at + key.size() + 3));
}

TEST(SimulateReplay, ReplayOfASimulatedLogReproducesTheRunBitForBit) {
  const TempDir dir("scw_simulate_replay");
  const std::string log = dir.File("clog.csv");
  const std::string txt = dir.File("stdout.txt");
  // The low-grip traction scenario on the car's params file, one lap: ESC, countersteer, ABS and
  // TC all act before the car spins (an abort ends the run with exit code 1, the files are
  // written all the same).
  const std::string simulate = "simulate --scenario " + std::string(SCW_SOURCE_DIR) +
                               "/params/scenarios/low_mu_traction.yaml --stability " + Shipped() +
                               " --set laps=1 --controller-log " + log + " --trace " +
                               dir.File("trace.csv") + " --summary " + dir.File("summary.yaml");
  const int rc = RunScw(simulate, txt);
  ASSERT_TRUE(rc == 0 || rc == 1) << ReadFile(txt);
  ASSERT_TRUE(std::filesystem::exists(log + ".setup.yaml")) << ReadFile(txt);

  // The log is a plain CSV with units in the names, the loads the controller used filled in.
  const CsvTable in = ReadCsv(log);
  ASSERT_GT(in.rows.size(), 1000u);
  for (const char* w : kWheelNames)
    for (std::size_t k = 0; k < in.rows.size(); ++k)
      ASSERT_GT(in.At(k, std::string("fz_") + w + "_N"), 0.0) << "row " << k;

  ASSERT_EQ(RunScw("replay " + log + " --params " + Shipped() + " -o " + dir.File("out.csv"), txt),
            0)
      << ReadFile(txt);
  EXPECT_NE(ReadFile(txt).find("recorded with the log"), std::string::npos) << ReadFile(txt);

  // What the simulation's controller produced: its trace (written every controller step at the
  // default log rate of 100 Hz, with shortest round-trip numbers).
  const CsvTable trace = ReadCsv(dir.File("trace.csv"));
  const CsvTable out = ReadCsv(dir.File("out.csv"));
  ASSERT_EQ(out.rows.size(), in.rows.size());
  ASSERT_EQ(trace.rows.size(), out.rows.size());
  const std::vector<std::string> same_name = {
      "t_s",          "steer_out_rad", "p_out_fl_bar", "p_out_fr_bar", "p_out_rl_bar",
      "p_out_rr_bar", "throttle_out",  "esc_active",   "cs_active",    "yaw_moment_Nm"};
  std::size_t mismatches = 0;
  auto any_wheel = [&](std::size_t k, const std::string& prefix) {
    bool on = false;
    for (const char* w : kWheelNames) on = on || out.At(k, prefix + w) != 0.0;
    return on ? 1.0 : 0.0;
  };
  for (std::size_t k = 0; k < out.rows.size(); ++k) {
    for (const auto& c : same_name)
      if (!SameBits(out.At(k, c), trace.At(k, c)) && mismatches++ < 10)
        ADD_FAILURE() << "row " << k << ", " << c << ": replay " << out.At(k, c) << ", simulation "
                      << trace.At(k, c);
    if (any_wheel(k, "abs_state_") != trace.At(k, "abs_active") && mismatches++ < 10)
      ADD_FAILURE() << "row " << k << ": ABS differs";
    if (any_wheel(k, "tc_state_") != trace.At(k, "tc_active") && mismatches++ < 10)
      ADD_FAILURE() << "row " << k << ": TC differs";
  }
  EXPECT_EQ(mismatches, 0u) << "of " << out.rows.size() << " rows";

  // The interventions the run counted, and the replay's summary.
  ASSERT_EQ(RunScw("replay " + log + " --params " + Shipped(), txt), 0) << ReadFile(txt);
  const auto replayed = SummaryInterventions(ReadFile(txt));
  const std::string run = ReadFile(dir.File("summary.yaml"));
  EXPECT_EQ(replayed.at("ESC"), YamlInt(run, "esc_count"));
  EXPECT_EQ(replayed.at("countersteer"), YamlInt(run, "cs_count"));
  EXPECT_EQ(replayed.at("ABS"), YamlInt(run, "abs_count"));
  EXPECT_EQ(replayed.at("TC"), YamlInt(run, "tc_count"));
  for (const char* key : {"esc_count", "cs_count", "abs_count", "tc_count"})
    EXPECT_GT(YamlInt(run, key), 0) << key << ": the scenario no longer provokes every subsystem";

  // The vehicle file as the closed loop injects it gives the same outputs (the loads recorded).
  ASSERT_EQ(RunScw("replay " + log + " --params " + Shipped() + " --vehicle " + SCW_SOURCE_DIR +
                       "/params/vehicles/eav24.yaml --no-log-setup -o " + dir.File("out2.csv"),
                   txt),
            0)
      << ReadFile(txt);
  EXPECT_EQ(ReadFile(dir.File("out2.csv")), ReadFile(dir.File("out.csv")));

  // A log cut after its setup was written: the setup is refused (bad input), naming the way out.
  std::string text = ReadFile(log);
  text.erase(text.rfind('\n', text.size() - 2) + 1);
  std::ofstream(log, std::ios::trunc) << text;
  EXPECT_EQ(RunScw("replay " + log + " --params " + Shipped(), txt), 2);
  EXPECT_NE(ReadFile(txt).find("--no-log-setup"), std::string::npos) << ReadFile(txt);
  EXPECT_EQ(RunScw("replay " + log + " --params " + Shipped() + " --no-log-setup", txt), 0)
      << ReadFile(txt);
  EXPECT_NE(ReadFile(txt).find("code defaults (--no-log-setup"), std::string::npos)
      << ReadFile(txt);
}

}  // namespace
}  // namespace scw::tuning::replay
