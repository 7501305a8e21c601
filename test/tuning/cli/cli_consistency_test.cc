// One consistent command line (issue 15), end to end with the built `scw` program: unknown
// commands get a suggestion and exit 2; a bare group lists its commands; non-numeric and negative
// numbers are refused with a plain message; missing files and folders are named without the
// standard library's "filesystem error:" text; validate, check and argument errors share one
// format; `params diff` exits like diff; `--version` names the git revision; `--progress` shows
// (always) or hides (never) the progress line of sweep, evaluate and simulate without changing
// their results; the old output spellings still work as hidden aliases.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "test/common/cli_run.h"

namespace scw {
namespace {

namespace fs = std::filesystem;

using Result = test::CliResult;
using test::Slurp;

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("scw_cli_" + std::to_string(::getpid()) + "_" + std::string(info->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  /// Runs `scw args` (stdout and stderr into files: not a terminal).
  Result Scw(const std::string& args) { return test::RunCli(SCW_BIN, args, dir_); }

  /// A one-scenario set of one lap (a few seconds per run).
  std::string TinySet() {
    const std::string set = Path("set.yaml");
    std::ofstream(set) << "name: tiny\n"
                          "training:\n"
                          "  - {name: one_lap, weight: 1.0, set: [laps=1, gg_scale=1.1]}\n";
    return set;
  }

  fs::path dir_;
};

const std::string kShipped = std::string(SCW_SOURCE_DIR) + "/params/stability/default.yaml";

bool HasProgressLine(const std::string& err, const std::string& phase) {
  return err.find("  " + phase + "  ") != std::string::npos &&
         err.find("elapsed ") != std::string::npos && err.find("eta ") != std::string::npos;
}

TEST_F(CliTest, UnknownCommandSuggestsTheClosestOneAndExits2) {
  Result r = Scw("tnue");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown command 'tnue' (did you mean tune?)"), std::string::npos) << r.err;

  r = Scw("params valdate " + kShipped);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("scw params: unknown command 'valdate' (did you mean validate?)"),
            std::string::npos)
      << r.err;

  r = Scw("tune --max-eval 3");  // an unknown option gets the same help
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown option '--max-eval' (did you mean --max-evals?)"),
            std::string::npos)
      << r.err;
}

TEST_F(CliTest, BareGroupCommandListsItsCommands) {
  Result r = Scw("vehicle");
  EXPECT_EQ(r.code, 0) << r.all();
  for (const char* sub : {"gg", "balance", "envelope", "lap", "init", "validate"})
    EXPECT_NE(r.out.find("\n  " + std::string(sub) + " "), std::string::npos) << sub << r.out;
  EXPECT_NE(r.out.find("scw vehicle"), std::string::npos) << r.out;

  r = Scw("params");
  EXPECT_EQ(r.code, 0) << r.all();
  for (const char* sub : {"import", "export", "validate", "check", "diff", "init", "docs"})
    EXPECT_NE(r.out.find("\n  " + std::string(sub) + " "), std::string::npos) << sub << r.out;
}

TEST_F(CliTest, NumbersThatAreNotNumbersOrAreNegativeSeedsAreBadInput) {
  // Each would start a tune if accepted: a tiny one into the test folder.
  const std::string tiny = "--scenarios " + TinySet() + " --max-evals 1 --threads 1 --out-dir " +
                           Path("run") + " --progress never";
  Result r = Scw("tune --max-evals abc --scenarios " + TinySet());
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("scw tune: --max-evals: 'abc' is not a number"), std::string::npos) << r.err;

  r = Scw("tune " + tiny + " --seed -1");
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("scw tune: --seed: -1 is negative"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(Path("run/evaluations.csv")));

  r = Scw("tune " + tiny + " --threads 1.5");
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("--threads: '1.5' is not a whole number"), std::string::npos) << r.err;

  r = Scw("sweep --threads abc");
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("scw sweep: --threads: 'abc' is not a number"), std::string::npos) << r.err;

  r = Scw("track line --gg-scale x -o " + Path("line.csv"));
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("--gg-scale: 'x' is not a number"), std::string::npos) << r.err;
}

// `scw track` reads --track by the scenario's rule (tuning/sim/track_csv.h LoadScenarioTrack):
// a name without extension is a built-in track, a file needs .csv, .yaml or .yml.
TEST_F(CliTest, TrackCommandsReadTheTrackAsAScenarioDoes) {
  Result r = Scw("track info --track monza");
  EXPECT_EQ(r.code, 0) << r.all();
  EXPECT_NE(r.out.find("(built-in)"), std::string::npos) << r.out;
  std::ofstream(Path("oval.txt")) << "x\n";
  r = Scw("track info --track " + Path("oval.txt"));
  EXPECT_NE(r.code, 0) << r.all();
  EXPECT_NE(r.err.find("unknown track file type (expected .csv, .yaml or .yml)"), std::string::npos)
      << r.err;
  r = Scw("track info --track nurburgring");
  EXPECT_NE(r.code, 0) << r.all();
  EXPECT_NE(r.err.find("unknown built-in track (known: "), std::string::npos) << r.err;
}

TEST_F(CliTest, MissingFilesAndFoldersAreNamedWithoutFilesystemErrorText) {
  const std::string missing = Path("missing.yaml");
  const std::string not_a_folder = Path("plain_file");
  std::ofstream(not_a_folder) << "x\n";
  struct Case {
    std::string args;
    int code;
    std::string names;
  };
  const Case cases[] = {
      {"params validate " + missing, 2, missing},
      {"params diff " + missing + " " + kShipped, 2, missing},
      {"simulate --scenario " + missing, 2, missing},
      {"evaluate " + missing, 2, missing},
      {"vehicle gg --vehicle " + missing, 2, missing},
      {"tune --scenarios " + missing, 2, missing},
      {"tune --scenarios " + TinySet() + " --max-evals 1 --progress never --out-dir " +
           not_a_folder + "/run",
       1, not_a_folder},
  };
  for (const auto& c : cases) {
    const Result r = Scw(c.args);
    EXPECT_EQ(r.code, c.code) << c.args << "\n" << r.all();
    EXPECT_EQ(r.all().find("filesystem error"), std::string::npos) << c.args << "\n" << r.all();
    EXPECT_NE(r.err.find(c.names), std::string::npos) << c.args << "\n" << r.all();
    EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << c.args << "\n" << r.all();
  }
}

TEST_F(CliTest, ValidateCheckAndArgumentErrorsShareOneFormat) {
  std::string text = Slurp(kShipped);
  const std::string key = "kp_psi_dot: 8.0";
  ASSERT_NE(text.find(key), std::string::npos);
  text.replace(text.find(key), key.size(), "kp_psi_dot: -1.0");
  const std::string bad = Path("bad.yaml");
  std::ofstream(bad) << text;

  // "error: invalid input", then one `<source>: <key>: <rule>` line per problem.
  const Result validate = Scw("params validate " + bad);
  EXPECT_EQ(validate.code, 2) << validate.all();
  const Result check = Scw("params check " + bad);
  EXPECT_EQ(check.code, 2) << check.all();
  const Result args = Scw("tune --max-evals abc");
  EXPECT_EQ(args.code, 2) << args.all();
  for (const Result* r : {&validate, &check, &args})
    EXPECT_EQ(r->err.rfind("error: invalid input\n", 0), 0u) << r->err;
  const std::regex line("(^|\n)" + bad + ": ESC\\.kp_psi_dot: [^\n]*-1[^\n]*lower bound");
  EXPECT_TRUE(std::regex_search(validate.err, line)) << validate.err;
  EXPECT_TRUE(std::regex_search(check.err, line)) << check.err;
  EXPECT_NE(args.err.find("\nscw tune: --max-evals: "), std::string::npos) << args.err;
}

TEST_F(CliTest, ParamsDiffExitsLikeDiff) {
  Result r = Scw("params diff " + kShipped + " " + kShipped);
  EXPECT_EQ(r.code, 0) << r.all();
  EXPECT_NE(r.err.find("0 key(s) differ"), std::string::npos) << r.err;

  std::string text = Slurp(kShipped);
  const std::string key = "kp_psi_dot: 8.0";
  ASSERT_NE(text.find(key), std::string::npos);
  text.replace(text.find(key), key.size(), "kp_psi_dot: 9.0");
  const std::string changed = Path("changed.yaml");
  std::ofstream(changed) << text;
  r = Scw("params diff " + kShipped + " " + changed);
  EXPECT_EQ(r.code, 1) << r.all();
  EXPECT_NE(r.out.find("ESC.kp_psi_dot: 8.0 -> 9.0"), std::string::npos) << r.out;

  r = Scw("params diff " + kShipped + " " + Path("missing.yaml"));
  EXPECT_EQ(r.code, 2) << r.all();
}

TEST_F(CliTest, VersionNamesTheGitRevision) {
  const Result r = Scw("--version");
  EXPECT_EQ(r.code, 0) << r.all();
  EXPECT_TRUE(std::regex_search(
      r.out,
      std::regex(
          "^scw [0-9]+\\.[0-9]+\\.[0-9]+ \\(git revision ([0-9a-f]{7,40}(\\+dirty)?|unknown)\\)")))
      << r.out;
}

TEST_F(CliTest, ProgressAlwaysShowsTheLineNeverHidesItAndResultsStayTheSame) {
  // stderr is a file here: the default (auto) shows nothing, `always` does. The old output
  // spellings (sweep --out, evaluate --csv) write the same files as -o.
  const Result sweep_always =
      Scw("sweep --set laps=1 --vary gg_scale=1.1 --threads 1 "
          "--progress always -o " +
          Path("a.csv"));
  EXPECT_EQ(sweep_always.code, 0) << sweep_always.all();
  EXPECT_TRUE(HasProgressLine(sweep_always.err, "sweep")) << sweep_always.err;
  EXPECT_NE(sweep_always.err.find("1/1 runs"), std::string::npos) << sweep_always.err;
  const Result sweep_never = Scw(
      "sweep --set laps=1 --vary gg_scale=1.1 --threads 1 --progress never --out " + Path("b.csv"));
  EXPECT_EQ(sweep_never.code, 0) << sweep_never.all();
  EXPECT_EQ(sweep_never.err.find("elapsed"), std::string::npos) << sweep_never.err;
  EXPECT_EQ(sweep_always.out, sweep_never.out);
  EXPECT_EQ(Slurp(Path("a.csv")), Slurp(Path("b.csv")));
  EXPECT_NE(Slurp(Path("a.csv")).find("gg_scale"), std::string::npos);

  const std::string set = TinySet();
  const Result eval_always =
      Scw("evaluate " + kShipped + " --scenarios " + set + " --threads 1 --labels shipped " +
          "--progress always -o " + Path("e1.csv"));
  EXPECT_EQ(eval_always.code, 0) << eval_always.all();
  EXPECT_TRUE(HasProgressLine(eval_always.err, "evaluate")) << eval_always.err;
  EXPECT_NE(eval_always.out.find("| shipped "), std::string::npos) << eval_always.out;
  const Result eval_default = Scw("evaluate " + kShipped + " --scenarios " + set +
                                  " --threads 1 --labels shipped --csv " + Path("e2.csv"));
  EXPECT_EQ(eval_default.code, 0) << eval_default.all();
  EXPECT_EQ(eval_default.err.find("elapsed"), std::string::npos) << eval_default.err;
  EXPECT_EQ(eval_always.out, eval_default.out);
  EXPECT_EQ(Slurp(Path("e1.csv")), Slurp(Path("e2.csv")));
  EXPECT_NE(Slurp(Path("e1.csv")).find(",shipped,"), std::string::npos);

  const Result sim_always = Scw("simulate --set laps=1 --progress always");
  EXPECT_EQ(sim_always.code, 0) << sim_always.all();
  EXPECT_TRUE(HasProgressLine(sim_always.err, "simulate")) << sim_always.err;
  EXPECT_NE(sim_always.err.find("lap 1/1"), std::string::npos) << sim_always.err;
  const Result sim_never = Scw("simulate --set laps=1 --progress never");
  EXPECT_EQ(sim_never.code, 0) << sim_never.all();
  EXPECT_EQ(sim_never.err.find("elapsed"), std::string::npos) << sim_never.err;
  EXPECT_EQ(sim_always.out, sim_never.out);
  // Rounded to what the numbers mean: "926× real time", not "926.475x".
  EXPECT_TRUE(std::regex_search(sim_never.err, std::regex("\\([0-9.]+× real time\\)")))
      << sim_never.err;
}

TEST_F(CliTest, OldOutputSpellingsAreHiddenAliases) {
  // track line: --gg-scale (kebab case, issue 27) and the scenario key's spelling --gg_scale.
  Result r = Scw("track line --gg_scale 1.2 -o " + Path("new.csv"));
  EXPECT_EQ(r.code, 0) << r.all();
  r = Scw("track line --gg-scale 1.2 --output " + Path("old.csv"));
  EXPECT_EQ(r.code, 0) << r.all();
  EXPECT_EQ(Slurp(Path("new.csv")), Slurp(Path("old.csv")));

  // The help names the new spellings only.
  const Result tune = Scw("tune --help");
  EXPECT_NE(tune.out.find("--out-dir"), std::string::npos) << tune.out;
  EXPECT_EQ(tune.out.find("--out TEXT"), std::string::npos) << tune.out;
  const Result sweep = Scw("sweep --help");
  EXPECT_NE(sweep.out.find("-o,--output"), std::string::npos) << sweep.out;
  EXPECT_EQ(sweep.out.find("--out TEXT"), std::string::npos) << sweep.out;
  const Result evaluate = Scw("evaluate --help");
  EXPECT_NE(evaluate.out.find("-o,--output"), std::string::npos) << evaluate.out;
  EXPECT_EQ(evaluate.out.find("--csv"), std::string::npos) << evaluate.out;
  const Result line = Scw("track line --help");
  EXPECT_NE(line.out.find("--gg-scale"), std::string::npos) << line.out;
  EXPECT_EQ(line.out.find("--gg_scale"), std::string::npos) << line.out;
}

TEST_F(CliTest, EvaluateLabelsMustNameEverySetOnce) {
  Result r = Scw("evaluate " + kShipped + " --labels a,b");
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("scw evaluate: --labels: 2 label(s) for 1 parameter set(s)"),
            std::string::npos)
      << r.err;
  r = Scw("evaluate " + kShipped + " " + kShipped + " --labels a,a");
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("'a' is given twice"), std::string::npos) << r.err;
}

// scw maneuver: bad subsystem names and unknown maneuvers are bad input (exit 2) naming the
// option; a run writes its trace (simulate's columns, one block per run) and its JSON; the exit
// code says whether every criterion passed (0) or one failed (1), whatever the outcome is.
TEST_F(CliTest, ManeuverOptionsOutputsAndExitCodes) {
  Result r = Scw("maneuver sine_with_dwell --subsystems esc,abx");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("scw maneuver: --subsystems: unknown subsystem 'abx'"), std::string::npos)
      << r.err;
  r = Scw("maneuver sine_with_dwel");
  EXPECT_EQ(r.code, 2) << r.all();
  r = Scw("maneuver power_off_in_turn --set maneuver.speedd=30");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("maneuver.speedd: unknown key (did you mean maneuver.speed?)"),
            std::string::npos)
      << r.err;

  r =
      Scw("maneuver braking_in_turn --subsystems none --set \"maneuver.decelerations=[3.0, 6.0]\" "
          "--trace " +
          Path("t.csv") + " --json " + Path("r.json"));
  ASSERT_TRUE(r.code == 0 || r.code == 1) << r.all();
  const std::string json = Slurp(Path("r.json"));
  EXPECT_NE(json.find("\"maneuver\": \"braking_in_turn\""), std::string::npos);
  const bool failed = json.find("\"passed\": false") != std::string::npos;
  EXPECT_EQ(r.code, failed ? 1 : 0);
  EXPECT_NE(r.out.find("| 3.0 m/s^2 |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| 6.0 m/s^2 |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("subsystems: none"), std::string::npos) << r.out;
  const std::string trace = Slurp(Path("t.csv"));
  EXPECT_EQ(trace.rfind("t_s,lap,s_m,", 0), 0u) << trace.substr(0, 80);
  EXPECT_NE(trace.find("\n-3,0,"), std::string::npos);  // run 0 settles from t = -3 s
  EXPECT_NE(trace.find("\n-3,1,"), std::string::npos);  // run 1 in the same file

  // The figure: drawn, or (no matplotlib) a note and the same exit code; no temporary file left.
  r = Scw("maneuver power_off_in_turn --plot " + Path("p.png"));
  EXPECT_TRUE(r.code == 0 || r.code == 1) << r.all();
  EXPECT_TRUE(fs::exists(Path("p.png")) || r.err.find("note: no plot written") != std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(Path("p.png.result.json")));
}

}  // namespace
}  // namespace scw
