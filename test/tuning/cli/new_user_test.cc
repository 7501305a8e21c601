// What a new user runs into, round 2 (issue 27), end to end with the built `scw` program: a
// write-protected output is refused (3), `params diff` notes unknown and repeated keys (4), a
// folder or an empty file is one problem (5), two outputs of one command cannot share a path (7),
// a key set twice on the command line and a --base without --overrides-only are refused (14), a
// YAML file cut off mid-key is a syntax error at that line (15), and `scw simulate --trace`
// records the run beside the trace (9).
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

using Result = test::CliResult;
using test::Slurp;

std::size_t Count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

const std::string kShipped = std::string(SCW_SOURCE_DIR) + "/params/stability/default.yaml";

class NewUserTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("scw_new_user_" + std::to_string(::getpid()) + "_" + std::string(info->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add, ec);
    fs::remove_all(dir_, ec);
  }

  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  Result Scw(const std::string& args) { return test::RunCli(SCW_BIN, args, dir_); }

  /// The shipped file with `edit` applied to its text.
  std::string Edited(const std::string& name, const std::string& from, const std::string& to) {
    std::string text = Slurp(kShipped);
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    std::ofstream(Path(name)) << text;
    return Path(name);
  }

  fs::path dir_;
};

// 3: as `cp` and the shell's `>`; root too (the check cannot pass by the kernel's EACCES).
TEST_F(NewUserTest, WriteProtectedOutputIsRefused) {
  const std::string f = Path("f.yaml");
  std::ofstream(f) << "old\n";
  fs::permissions(f, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  const Result r = Scw("params init -o " + f);
  EXPECT_EQ(r.code, 1) << r.all();
  EXPECT_NE(r.err.find(f + ": is write-protected (mode 0444); the file was not changed"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(Slurp(f), "old\n");
  // A folder as -o: the cause, not "rename failed (Not a directory)".
  const Result d = Scw("params init -o " + Path("") + "/");
  EXPECT_EQ(d.code, 1) << d.all();
  EXPECT_NE(d.err.find("it is a folder; give a file name"), std::string::npos) << d.err;
  EXPECT_EQ(d.err.find("rename"), std::string::npos) << d.err;
}

// 4: "0 key(s) differ" never hides an unknown or a repeated key.
TEST_F(NewUserTest, ParamsDiffNotesUnknownAndRepeatedKeys) {
  const std::string unknown =
      Edited("unknown.yaml", "    ESC:\n", "    ESC:\n      kp_psi_dott: 3.0\n");
  Result r = Scw("params diff " + unknown + " " + kShipped);
  EXPECT_EQ(r.code, 0) << r.all();
  EXPECT_NE(r.err.find(unknown + ": note: ESC.kp_psi_dott: unknown key"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("0 key(s) differ; 1 note(s) above"), std::string::npos) << r.err;
  // A duplicate: noted, and compared as the node reads it (the last value).
  const std::string twice =
      Edited("twice.yaml", "    ESC:\n", "    ESC:\n      kp_psi_dot: 99.0\n");
  r = Scw("params diff " + kShipped + " " + twice);
  EXPECT_NE(r.err.find(twice + ": note: ESC.kp_psi_dot: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("1 note(s) above"), std::string::npos) << r.err;
  // An invalid file: exit 2.
  const std::string bad = Edited("bad.yaml", "      kp_psi_dot: 8.0\n", "      kp_psi_dot: -1.0\n");
  r = Scw("params diff " + bad + " " + kShipped);
  EXPECT_EQ(r.code, 2) << r.all();
}

// 5: one line, not "the file is empty" and 90 missing keys.
TEST_F(NewUserTest, FolderOrEmptyFileIsOneProblem) {
  Result r = Scw("params validate " + dir_.string());
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find(dir_.string() + ": is a directory, not a file"), std::string::npos) << r.err;
  EXPECT_EQ(Count(r.err, "\n"), 2u) << r.err;  // "error: invalid input" and the one problem
  std::ofstream(Path("empty.yaml")).flush();
  r = Scw("params validate " + Path("empty.yaml"));
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("the file is empty"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("required key is missing"), std::string::npos) << r.err;
  EXPECT_EQ(Count(r.err, "\n"), 2u) << r.err;
  // A binary file says so.
  std::ofstream(Path("binary.yaml"), std::ios::binary) << std::string("\x89PNG\r\n\x1a\n\0\0", 10);
  r = Scw("params validate " + Path("binary.yaml"));
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("line 3: a NUL byte: this is a binary file, not YAML text"),
            std::string::npos)
      << r.err;
  // A missing file names the reason.
  r = Scw("params validate " + Path("missing.yaml"));
  EXPECT_NE(r.err.find("cannot open the file for reading (No such file or directory)"),
            std::string::npos)
      << r.err;
}

// 7: two outputs of one command never share a path, also through a symlink.
TEST_F(NewUserTest, OutputsOfOneCommandCannotShareAPath) {
  const std::string same = Path("same.csv");
  Result r = Scw("simulate --set laps=1 --trace " + same + " --controller-log " + same);
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("scw simulate: --controller-log: writes the same file as --trace"),
            std::string::npos)
      << r.err;
  fs::create_symlink(same, Path("link.csv"));
  r = Scw("simulate --set laps=1 --trace " + same + " --summary " + Path("link.csv"));
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("--summary: writes the same file as --trace"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(same));  // refused before the run
}

// 14: a key set twice, and --base that export would ignore.
TEST_F(NewUserTest, RepeatedSetKeysAndAnUnusedBaseAreRefused) {
  Result r = Scw("simulate --set laps=2 laps=3 --print-scenario");
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("scw simulate: --set: laps is given twice (laps=2, laps=3)"),
            std::string::npos)
      << r.err;
  r = Scw("sweep --set laps=1 laps=1 --vary gg_scale=1.0");
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("laps is given twice"), std::string::npos) << r.err;
  r = Scw("params export " + kShipped + " -o " + Path("b.yaml") + " --base " + kShipped);
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("--base: is used only with --overrides-only"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(Path("b.yaml")));
  // An unknown key that lacks its unit suffix gets a suggestion.
  r = Scw("simulate --set abort.max_sideslip=10 --print-scenario");
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("(did you mean abort.max_sideslip_deg?)"), std::string::npos) << r.err;
}

// 15: cut off mid-key is a syntax error at that line, not an unknown key and missing keys.
TEST_F(NewUserTest, FileCutOffMidKeyIsASyntaxErrorAtThatLine) {
  const std::string text = Slurp(kShipped);
  const auto at = text.find("      kp_psi_dot:");
  ASSERT_NE(at, std::string::npos);
  const std::string cut = text.substr(0, at) + "      kp_ps";
  std::ofstream(Path("cut.yaml")) << cut;
  const int line = static_cast<int>(Count(cut, "\n")) + 1;
  const Result r = Scw("params validate " + Path("cut.yaml"));
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("line " + std::to_string(line) +
                       ": YAML syntax error: 'kp_ps' is not "
                       "followed by ':'"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("unknown key"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("missing"), std::string::npos) << r.err;
  // `key:` with an empty value stays what it was (a type problem of that key, not syntax).
  std::ofstream(Path("empty_value.yaml")) << text.substr(0, at) + "      kp_psi_dot:\n";
  const Result e = Scw("params validate " + Path("empty_value.yaml"));
  EXPECT_EQ(e.err.find("YAML syntax error"), std::string::npos) << e.err;
}

// 9: the trace's meta file names the scenario and the parameter set (plot titles).
TEST_F(NewUserTest, SimulateRecordsTheRunBesideTheTrace) {
  const Result r = Scw("simulate --set laps=1 gg_scale=1.1 --stability " + kShipped + " --trace " +
                       Path("t.csv") + " --progress never");
  ASSERT_LE(r.code, 1) << r.all();
  const std::string meta = Slurp(Path("t.csv.meta.yaml"));
  EXPECT_NE(meta.find("scenario: \"default\"\n"), std::string::npos) << meta;
  EXPECT_NE(meta.find("overrides: [\"laps=1\", \"gg_scale=1.1\"]\n"), std::string::npos) << meta;
  EXPECT_NE(meta.find("stability: \"" + kShipped + "\"\n"), std::string::npos) << meta;
  EXPECT_NE(meta.find("stability_sha256: "), std::string::npos) << meta;
  EXPECT_NE(meta.find("\nstatus: "), std::string::npos) << meta;
  // The trace itself has the ESC reference for the yaw-rate panel and the tyre forces.
  const std::string head = Slurp(Path("t.csv")).substr(0, 2000);
  EXPECT_NE(head.find(",yaw_rate_ref_radps,"), std::string::npos) << head.substr(0, 200);
  EXPECT_NE(head.find(",fx_rr_N\n"), std::string::npos) << head.substr(0, 200);
}

// 12: every --help lists the exit codes (130 included) once, and the defaults of the options.
TEST_F(NewUserTest, EveryHelpShowsExitCodesAndDefaults) {
  for (const std::string cmd :
       {"", "tune", "evaluate", "sweep", "bench", "track line", "params diff", "vehicle gg"}) {
    const Result r = Scw(cmd + " --help");
    EXPECT_EQ(r.code, 0) << cmd;
    EXPECT_EQ(Count(r.out, "Exit codes: 0 success"), 1u) << cmd << ":\n" << r.out;
    EXPECT_NE(r.out.find("130 interrupted"), std::string::npos) << cmd;
  }
  EXPECT_NE(Scw("bench --help").out.find("--duration NUMBER in [1, 1e+06]=600"), std::string::npos);
  EXPECT_NE(Scw("evaluate --help").out.find("--threads INT"), std::string::npos);
}

// 12: the vehicle tables take -o FILE as every other output does.
TEST_F(NewUserTest, VehicleTablesWriteTheirCsvWithDashO) {
  const Result r = Scw("vehicle gg --speeds 30 -o " + Path("gg.csv"));
  EXPECT_EQ(r.code, 0) << r.all();
  EXPECT_EQ(Slurp(Path("gg.csv")).rfind("speed_mps,lateral_max_mps2,", 0), 0u)
      << Slurp(Path("gg.csv"));
  EXPECT_EQ(r.out.find("speed_mps"), std::string::npos) << r.out;
}

// 11: several bad values on one command line are reported together, before anything runs.
TEST_F(NewUserTest, EveryBadValueOfACommandLineIsReportedAtOnce) {
  const Result r = Scw("tune --seed -1 --threads -1 --max-evals 0 --out-dir " + Path("run"));
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("scw tune: --seed: -1 is negative"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("scw tune: --threads: -1 is outside [0, 1024]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("scw tune: --max-evals: 0 is outside"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(Path("run")));
  // One bad value: one line, as before.
  const Result one = Scw("tune --max-evals abc");
  EXPECT_EQ(one.code, 2);
  EXPECT_EQ(Count(one.err, "scw tune: "), 1u) << one.err;
}

}  // namespace
}  // namespace scw
