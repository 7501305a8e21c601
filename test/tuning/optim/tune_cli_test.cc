// `scw tune` end to end with the built program (issue 15): a 1-evaluation tune from the shipped
// file exports exactly the base set and an empty overrides file, both with the provenance header
// and both passing `scw params check`; evaluation 0 is the base set; --base-outside refuse names
// the key the shipped file has outside the default space; `scw space show` warns about it;
// --batch needs the batched design and gives the same evaluations on 1 and 2 threads.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "params/io/load.h"
#include "params/io/write.h"
#include "params/io/yaml_doc.h"
#include "params/schema/stability_params.h"
#include "test/common/cli_run.h"

namespace scw {
namespace {

namespace fs = std::filesystem;
using params::StabilityParams;
using test::CliResult;
using test::Slurp;

StabilityParams LoadText(const std::string& text, const std::string& name) {
  return params::LoadRosText<StabilityParams>(text, name, params::kStabilityNodeKey);
}

class TuneCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("scw_tune_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    set_ = (dir_ / "set.yaml").string();
    std::ofstream(set_) << "name: tiny\n"
                           "training:\n"
                           "  - {name: one_lap, weight: 1.0, set: [laps=1, gg_scale=1.1]}\n";
    shipped_ = std::string(SCW_SOURCE_DIR) + "/params/stability/default.yaml";
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  CliResult Scw(const std::string& args) const { return test::RunCli(SCW_BIN, args, dir_); }

  fs::path dir_;
  std::string set_, shipped_;
};

TEST_F(TuneCliTest, OneEvaluationExportsTheBaseSetWithProvenanceAndPassesTheChecker) {
  const std::string run = Path("run");
  const CliResult tune = Scw("tune --scenarios " + set_ + " --base " + shipped_ +
                             " --max-evals 1 --threads 1 --progress never --max-time 0 "
                             "--no-sensitivity --no-freeze --search-plant-step 0 --out " +
                             run);
  ASSERT_EQ(tune.code, 0) << tune.all();
  EXPECT_NE(tune.all().find("note: ESC.beta_threshold_deactivate"), std::string::npos)
      << tune.all();

  const std::string full = Slurp(run + "/stability_tuned.yaml");
  const std::string over = Slurp(run + "/stability_overrides.yaml");
  const std::string shipped = Slurp(shipped_);
  // Exactly the base set: every value bit for bit (equal shortest round-trip texts).
  EXPECT_TRUE(params::DifferingKeys(LoadText(full, "full"), LoadText(shipped, "shipped")).empty());
  // ... and an overrides file that changes nothing.
  Problems pr;
  const params::YamlNode parsed = params::ParseYaml(over, "over");
  const auto doc = params::Flatten(parsed, params::Layout::kRos2, params::kStabilityNodeKey, &pr);
  EXPECT_TRUE(pr.empty());
  EXPECT_TRUE(doc.entries.empty()) << over;
  EXPECT_NE(over.find("ros__parameters: {}"), std::string::npos) << over;

  // Provenance header in both files.
  for (const std::string& text : {full, over}) {
    EXPECT_EQ(text.rfind("# Tuned by scw tune ", 0), 0u) << text;
    for (const std::string& item :
         {std::string("(git "), "# run folder: " + run, "# base: " + shipped_,
          std::string("# search: sbplx"), std::string("#   training (1 scenario): "),
          std::string("# changed keys: none")})
      EXPECT_NE(text.find(item), std::string::npos) << item << "\n" << text;
  }
  // The project's ROS 2 checker accepts both.
  for (const std::string args :
       {"/stability_tuned.yaml", "/stability_overrides.yaml --overrides"}) {
    const CliResult check = Scw("params check " + run + args);
    EXPECT_EQ(check.code, 0) << check.all();
  }

  // Evaluation 0 is the base set; training costs before and after are equal (the search at the
  // vehicle's own step: at another the optimisation's costs are that step's, tune_study_test).
  const std::string log = Slurp(run + "/evaluations.csv");
  const auto row0 = log.find('\n') + 1;
  EXPECT_EQ(log.compare(row0, 8, "0,start,"), 0) << log;
  const std::string manifest = Slurp(run + "/manifest.yaml");
  EXPECT_NE(manifest.find("changed_keys: 0\n"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("grown_ranges: 1\n"), std::string::npos) << manifest;
  const auto cost = [&](const std::string& key) {
    const auto at = manifest.find("\n" + key + ": ");
    return at == std::string::npos
               ? std::string("?")
               : manifest.substr(at + key.size() + 3,
                                 manifest.find('\n', at + 1) - at - key.size() - 3);
  };
  EXPECT_EQ(cost("baseline_cost"), cost("tuned_cost")) << manifest;
  EXPECT_EQ(cost("baseline_stability"), cost("start_cost")) << manifest;
  EXPECT_EQ(cost("objective"), "constrained") << manifest;
  EXPECT_EQ(cost("search_plant_step"), "0.0") << manifest;
  EXPECT_EQ(cost("search_plant_step_check"), "\"not run\"") << manifest;
}

// Resume is safe: a --resume with another seed is refused with exit 2 before anything is written
// (the log and its identity file stay byte for byte), one with the same options replays the log.
TEST_F(TuneCliTest, ADivergingResumeExitsTwoAndLeavesTheLogByteIdentical) {
  const std::string space = Path("space.yaml");
  std::ofstream(space) << "name: two\n"
                          "parameters:\n"
                          "  - {key: countersteer_system.steering_factor, lo: 0.3, hi: 1.5}\n"
                          "  - {key: SlipControl.TC.rear.slip_threshold_hold_reduce, lo: 3.0, "
                          "hi: 20.0}\n";
  const std::string run = Path("run");
  const std::string base = "tune --scenarios " + set_ + " --space " + space +
                           " --threads 1 --progress never --no-sensitivity --out-dir " + run;
  const std::string common = base + " --max-evals 3";
  const CliResult first = Scw(common);
  ASSERT_EQ(first.code, 0) << first.all();
  const std::string log = run + "/evaluations.csv";
  const std::string logged = Slurp(log), identity = Slurp(run + "/evaluations.identity.yaml");
  ASSERT_FALSE(identity.empty());
  const CliResult seed = Scw(common + " --seed 2 --resume " + log);
  EXPECT_EQ(seed.code, 2) << seed.all();
  EXPECT_NE(seed.all().find("seed: the log was written with 1, this run has 2"), std::string::npos)
      << seed.all();
  // A smaller budget cannot continue the log.
  const CliResult fewer = Scw(base + " --max-evals 2 --resume " + log);
  EXPECT_EQ(fewer.code, 2) << fewer.all();
  EXPECT_NE(fewer.all().find("a resume may raise the budget, never lower it"), std::string::npos)
      << fewer.all();
  EXPECT_EQ(Slurp(log), logged);
  EXPECT_EQ(Slurp(run + "/evaluations.identity.yaml"), identity);
  // The same options on the finished run: it says so and rewrites nothing.
  const std::string manifest = Slurp(run + "/manifest.yaml"),
                    tuned = Slurp(run + "/stability_tuned.yaml");
  const CliResult same = Scw(common + " --resume " + log);
  ASSERT_EQ(same.code, 0) << same.all();
  EXPECT_NE(same.all().find("already holds the whole run (3 evaluations, stop: max_evals); "
                            "nothing was written"),
            std::string::npos)
      << same.all();
  EXPECT_EQ(Slurp(log), logged);
  EXPECT_EQ(Slurp(run + "/manifest.yaml"), manifest);
  EXPECT_EQ(Slurp(run + "/stability_tuned.yaml"), tuned);
  // A larger budget extends the search where it ended (the folder is the log's by default): the
  // logged rows stay, and the log equals that of one run with the larger budget, bit for bit.
  const CliResult more = Scw(base + " --max-evals 5 --resume " + log);
  ASSERT_EQ(more.code, 0) << more.all();
  EXPECT_NE(more.all().find("(3 replayed)"), std::string::npos) << more.all();
  const std::string extended = Slurp(log);
  EXPECT_EQ(extended.compare(0, logged.size(), logged), 0);
  const std::string once = Path("once");
  const std::string once_cmd = "tune --scenarios " + set_ + " --space " + space +
                               " --threads 1 --progress never --no-sensitivity --max-evals 5 "
                               "--out-dir " +
                               once;
  const CliResult one = Scw(once_cmd);
  ASSERT_EQ(one.code, 0) << one.all();
  EXPECT_EQ(Slurp(once + "/evaluations.csv"), extended);
  // The same tuned file below its provenance header (run folder and date differ).
  const auto body = [](const std::string& text) { return text.substr(text.find("\n/core")); };
  EXPECT_EQ(body(Slurp(once + "/stability_tuned.yaml")),
            body(Slurp(run + "/stability_tuned.yaml")));
  // The console is short: verdicts and totals, no tables.
  EXPECT_NE(first.all().find("training (1 scenario): cost "), std::string::npos) << first.all();
  EXPECT_EQ(first.all().find("| "), std::string::npos) << first.all();
}

TEST_F(TuneCliTest, RefuseNamesTheKeyOutsideTheSpaceAndSpaceShowWarns) {
  const std::string run = Path("refused");
  const CliResult refuse =
      Scw("tune --scenarios " + set_ + " --base " + shipped_ +
          " --base-outside refuse --max-evals 1 --progress never --out " + run);
  EXPECT_EQ(refuse.code, 2);
  const std::string out = refuse.all();
  EXPECT_NE(out.find("ESC.beta_threshold_deactivate: the base value 0.035 is 2.011 × "
                     "min(ESC.beta_threshold_activate), outside the ratio range [0.3, 0.98]"),
            std::string::npos)
      << out;
  EXPECT_FALSE(fs::exists(run)) << "a refused run must not leave a run folder";
  // --check-set applies the same rule (it used to grow the range regardless).
  const CliResult check = Scw("tune --check-set --scenarios " + set_ + " --base " + shipped_ +
                              " --base-outside refuse --progress never");
  EXPECT_EQ(check.code, 2);
  EXPECT_NE(check.all().find("ESC.beta_threshold_deactivate"), std::string::npos) << check.all();

  const CliResult space_show = Scw("space show");
  EXPECT_EQ(space_show.code, 0);
  const std::string show = space_show.all();
  EXPECT_NE(show.find("warning: ESC.beta_threshold_deactivate"), std::string::npos) << show;
  EXPECT_NE(show.find("grows the range to [0.3, 2.02]"), std::string::npos) << show;
}

TEST_F(TuneCliTest, ArgumentProblemsAreFoundBeforeAnyFolderIsCreated) {
  const std::string run = Path("never");
  const CliResult alg =
      Scw("tune --scenarios " + set_ + " --algorithm crs3 --max-evals 1 --out-dir " + run);
  EXPECT_EQ(alg.code, 2);
  const std::string out = alg.all();
  EXPECT_NE(out.find("unknown algorithm 'crs3'"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(run));
  EXPECT_EQ(Scw("tune --scenarios " + set_ + " --resume " + Path("missing.csv") +
                " --max-evals 1 --out-dir " + run)
                .code,
            2);
  EXPECT_FALSE(fs::exists(run));
  std::ofstream(Path("a_file")) << "x\n";
  const CliResult file =
      Scw("tune --scenarios " + set_ + " --max-evals 1 --out-dir " + Path("a_file"));
  EXPECT_EQ(file.code, 2);
  EXPECT_NE(file.all().find("is not a folder"), std::string::npos);
}

TEST_F(TuneCliTest, AnExistingRunFolderIsRefusedUnlessForcedAndTheManifestHashesTheFiles) {
  const std::string run = Path("run");
  const std::string args = "tune --scenarios " + set_ +
                           " --max-evals 1 --progress never --no-sensitivity --out-dir " + run;
  const CliResult first = Scw(args);
  ASSERT_EQ(first.code, 0) << first.all();
  const std::string log = Slurp(run + "/evaluations.csv");
  const CliResult refused = Scw(args);
  EXPECT_EQ(refused.code, 2);
  const std::string second = refused.all();
  EXPECT_NE(second.find("already holds files"), std::string::npos) << second;
  EXPECT_EQ(Slurp(run + "/evaluations.csv"), log) << "a refused run must not touch the folder";
  const CliResult forced_run = Scw(args + " --force");
  EXPECT_EQ(forced_run.code, 0) << forced_run.all();

  // files_sha256 equals sha256sum of each file as written.
  const std::string manifest = Slurp(run + "/manifest.yaml");
  for (const std::string f :
       {"stability_tuned.yaml", "stability_overrides.yaml", "comparison.csv"}) {
    const auto at = manifest.find("  " + f + ": ");
    ASSERT_NE(at, std::string::npos) << manifest;
    const std::string digest = manifest.substr(at + f.size() + 4, 64);
    if (const CliResult sum = test::RunCli("sha256sum", run + "/" + f, dir_); sum.code == 0) {
      EXPECT_EQ(sum.out.substr(0, 64), digest) << f;
    }
  }
  EXPECT_NE(manifest.find("hash_algorithm: sha256"), std::string::npos);

  // The pictures, embedded in comparison.md (when python3 with matplotlib is installed; without
  // it the run says so once and still succeeds).
  const std::string forced = forced_run.all();
  if (forced.find("note: no plots") != std::string::npos) {
    EXPECT_FALSE(fs::exists(run + "/convergence.png"));
  } else {
    for (const char* png : {"convergence.png", "comparison.png"}) {
      ASSERT_TRUE(fs::exists(run + "/" + png)) << png << "\n" << forced;
      EXPECT_GT(fs::file_size(run + "/" + png), 1000u) << png;
      EXPECT_NE(Slurp(run + "/comparison.md").find(std::string("](") + png + ")"),
                std::string::npos)
          << png;
    }
  }
}

TEST_F(TuneCliTest, BatchedTuneNeedsTheBatchedDesignAndIsTheSameOnAnyThreadCount) {
  const std::string never = Path("never");
  const CliResult batch =
      Scw("tune --scenarios " + set_ + " --batch 2 --max-evals 4 --out-dir " + never);
  EXPECT_EQ(batch.code, 2);
  EXPECT_NE(batch.all().find("--batch"), std::string::npos);
  EXPECT_NE(batch.all().find("lhs+sbplx"), std::string::npos) << batch.all();
  EXPECT_FALSE(fs::exists(never));

  const std::string set2 = Path("set2.yaml");
  std::ofstream(set2) << "name: tiny2\n"
                         "training:\n"
                         "  - {name: a, weight: 1.0, set: [laps=1, gg_scale=1.1]}\n"
                         "  - {name: b, weight: 1.0, set: [laps=1, gg_scale=1.2]}\n";
  std::string logs[2];
  for (int threads : {1, 2}) {
    const std::string run = Path("batch" + std::to_string(threads));
    const CliResult tune = Scw(
        "tune --scenarios " + set2 + " --algorithm lhs+sbplx --batch 2 --max-evals 9 --threads " +
        std::to_string(threads) + " --progress never --no-sensitivity --out-dir " + run);
    ASSERT_EQ(tune.code, 0) << tune.all();
    logs[threads - 1] = Slurp(run + "/evaluations.csv");
    EXPECT_NE(Slurp(run + "/manifest.yaml").find("\nbatch: 2\n"), std::string::npos);
    EXPECT_NE(Slurp(run + "/comparison.md").find("(lhs+sbplx, batch 2, seed 1)"),
              std::string::npos);
  }
  EXPECT_EQ(std::count(logs[0].begin(), logs[0].end(), '\n'), 10);  // header + 9 evaluations
  EXPECT_EQ(logs[0], logs[1]);
}

}  // namespace
}  // namespace scw
