// scw tune's workflow as a library call (issue 17 part 3): TuneStudy::Run on a tiny problem — two
// dimensions, two one-lap training scenarios on the centre line and one held-out scenario (from
// test/golden/golden_set.yaml) — without the program. Relations, not numbers: the best is no worse
// than the base, every evaluation is counted and logged, the observer sees every phase in order,
// the stop flag ends the optimisation with the best so far, the same inputs give the same report,
// and scw evaluate's table of the base and tuned sets is the tune's comparison.csv.
#include "tuning/optim/tune_study.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "params/io/load.h"
#include "params/io/write.h"
#include "params/io/yaml_doc.h"
#include "tuning/optim/comparison.h"
#include "tuning/sim/run_summary.h"

namespace scw::tuning {
namespace {

namespace fs = std::filesystem;
using params::StabilityParams;

constexpr char kSet[] = R"(name: tiny
training:
  - {name: clean_gg1.1, set: [motion.raceline=centerline, kind=clean, gg_scale=1.1, laps=1]}
  - {name: power_on_c1, set: [motion.raceline=centerline, kind=critical, laps=1, abort.max_lateral_error=10, "events.throttle.corner=[1]", "events.throttle.s=[20]", "events.throttle.lap=[1]", "events.throttle.duration=[1.0]", "events.throttle.value=[1.0]"]}
held_out:
  - {name: late_braking_c7, set: [motion.raceline=centerline, kind=critical, laps=1, abort.max_lateral_error=10, "events.late_braking.corner=[7]", "events.late_braking.s=[0]", "events.late_braking.distance=[20]"]}
)";

// The countersteer gain and the TC activation threshold: both act in the scenarios above.
ParameterSpace TwoDimensions() {
  return ParameterSpace("two", {{"SlipControl.TC.rear.slip_threshold_hold_reduce", -1, 3.0, 20.0,
                                 params::Scale::kLinear, Transform::kDirect, "", -1},
                                {"countersteer_system.steering_factor", -1, 0.3, 1.5,
                                 params::Scale::kLinear, Transform::kDirect, "", -1}});
}

std::string ReadOrEmpty(const std::string& path) {
  try {
    return params::ReadTextFile(path);
  } catch (const std::exception&) {
    return "";
  }
}

class TuneStudyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("scw_tune_study_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// A study of the tiny problem that logs into `log` (one thread: the result is the same for
  /// any count, and the test stays light on a shared machine).
  /// At each vehicle's own step unless `search_plant_step` says otherwise (the search step has
  /// its own test below).
  TuneStudy Study(const std::string& log, int max_evals, bool sensitivity,
                  const std::atomic<bool>* stop = nullptr, double search_plant_step = 0.0,
                  const PlantStepTolerances& tolerances = {},
                  const std::function<void(TuneStudyOptions&)>& tweak = {},
                  const std::string& set_text = kSet) const {
    TuneStudyOptions o;
    o.max_evals = max_evals;
    o.search_plant_step = search_plant_step;
    o.search_plant_step_tolerances = tolerances;
    o.threads = 1;
    o.sensitivity = sensitivity;
    o.evaluation_log = (dir_ / log).string();
    o.stop = stop;
    o.run_folder = dir_.string();
    o.tool_version = "test";
    o.git_revision = "none";
    o.date_utc = [] { return std::string("2026-01-01T00:00:00Z"); };
    if (tweak) tweak(o);
    return TuneStudy(StabilityParams{}, TwoDimensions(),
                     ScenarioSet::FromYamlText(set_text, "tiny"), o);
  }

  fs::path dir_;
};

/// Records what a study tells its observer.
class Recorder : public TuneObserver {
 public:
  void OnPhaseBegin(TunePhase phase, int total) override {
    events.push_back(std::string("begin ") + TunePhaseName(phase));
    totals.push_back(total);
  }
  void OnJobs(TunePhase phase, int done, int total) override {
    last_jobs[static_cast<int>(phase)] = {done, total};
  }
  void OnEvaluation(const Progress& p) override {
    evaluations.push_back(p.evals);
    if (stop_after > 0 && p.evals == stop_after) stop = true;
  }
  void OnPhaseEnd(TunePhase phase, const TuneReport& report) override {
    events.push_back(std::string("end ") + TunePhaseName(phase));
    if (phase == TunePhase::kExport) at_export = report;
  }

  std::vector<std::string> events;
  std::vector<int> totals;  ///< per OnPhaseBegin
  std::pair<int, int> last_jobs[10] = {};
  std::vector<int> evaluations;  ///< Progress::evals of every OnEvaluation
  TuneReport at_export;
  int stop_after = 0;  ///< raise `stop` after this evaluation (0: never)
  std::atomic<bool> stop{false};
};

int Rows(const std::string& csv) {
  return static_cast<int>(std::count(csv.begin(), csv.end(), '\n'));
}

TEST_F(TuneStudyTest, BestIsNoWorseThanTheBaseAndTheObserverSeesEveryPhase) {
  const TuneStudy study = Study("evaluations.csv", 8, true);
  Recorder rec;
  const TuneReport r = study.Run(rec);
  const TuneResult& opt = r.optimisation;

  // The best is no worse than the base (evaluation 0), and the comparison reproduces both merits:
  // the base set's and the exported set's runs are the optimisation's own (nothing reverted).
  EXPECT_EQ(opt.stop_reason, "max_evals");
  EXPECT_LE(opt.best_cost, opt.start_cost);
  ASSERT_EQ(r.training.size(), 2u);
  EXPECT_EQ(r.base_value.merit, opt.start_cost);
  EXPECT_EQ(r.base_value.stability, r.training[0].costs[1].total);  // the critical scenario
  EXPECT_TRUE(r.frozen.empty()) << r.frozen.front();
  if (r.reverted.empty()) {
    EXPECT_EQ(r.tuned_value.merit, opt.best_cost);
  }
  // Within the clean-lap budget, as every exported set of the constrained objective.
  EXPECT_TRUE(r.tuned_value.within_budget());
  EXPECT_TRUE(r.unexported_gain.empty()) << r.unexported_gain;
  EXPECT_EQ(r.held_out.size(), 2u);
  EXPECT_EQ(r.provenance.training_before, r.training[0].total);
  EXPECT_FALSE(r.convergence.empty());
  EXPECT_TRUE(r.new_findings.empty());

  // Every evaluation counted, reported and logged (a header and one row each).
  EXPECT_EQ(opt.evals, 8);
  EXPECT_EQ(opt.replayed, 0);
  EXPECT_EQ(rec.evaluations, (std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(Rows(ReadOrEmpty((dir_ / "evaluations.csv").string())), 1 + opt.evals);
  EXPECT_FALSE(ReadOrEmpty((dir_ / "evaluations.identity.yaml").string()).empty());

  // The phases in order; each job count ends at its total.
  EXPECT_EQ(rec.events,
            (std::vector<std::string>{"begin prepare", "end prepare", "begin screen", "end screen",
                                      "begin optimise", "end optimise", "begin sensitivity",
                                      "end sensitivity", "begin revert", "end revert",
                                      "begin compare", "end compare", "begin neighbourhood",
                                      "end neighbourhood", "end export"}));
  ASSERT_EQ(rec.totals.size(), 7u);
  EXPECT_EQ(rec.totals[0], 2 * 2);  // training scenarios prepared, the base set run on them
  EXPECT_EQ(rec.totals[1], r.screening.sets * 2);    // the range screen
  EXPECT_EQ(rec.totals[2], 8);                       // the budget
  EXPECT_EQ(rec.totals[3], r.sensitivity.sets * 2);  // the sensitivity
  EXPECT_EQ(rec.totals[5], 3 * 1);  // the training runs are known; held-out: prepare + 2 sets
  for (TunePhase phase : {TunePhase::kPrepare, TunePhase::kScreen, TunePhase::kSensitivity,
                          TunePhase::kCompare, TunePhase::kNeighbourhood}) {
    const auto p = static_cast<int>(phase);
    EXPECT_EQ(rec.last_jobs[p].first, rec.last_jobs[p].second) << p;
    EXPECT_GT(rec.last_jobs[p].first, 0) << p;
  }
  // The knife-edge check ran on both groups.
  EXPECT_TRUE(r.neighbourhood_done);
  EXPECT_GE(r.neighbourhood.neighbours.size(), 10u);  // at least the plant's ten

  // At the export the outputs are complete, the sensitivity in them.
  EXPECT_EQ(rec.at_export.sensitivity_state, SensitivityState::kDone);
  EXPECT_EQ(rec.at_export.tuned_file, r.tuned_file);
  EXPECT_EQ(rec.at_export.comparison_csv, r.comparison_csv);
  EXPECT_EQ(r.sensitivity_state, SensitivityState::kDone);
  EXPECT_NE(r.comparison_markdown.find("Parameter sensitivity"), std::string::npos);
  EXPECT_NE(r.comparison_markdown.find("## What the tuned file changes"), std::string::npos);
  EXPECT_EQ(r.sensitivity.dimensions.size(), 2u);
  EXPECT_FALSE(r.sensitivity_csv.empty());

  // The tuned file is the tuned set; the overrides list exactly the changed keys.
  const auto tuned =
      params::LoadRosText<StabilityParams>(r.tuned_file, "tuned", params::kStabilityNodeKey);
  EXPECT_TRUE(params::DifferingKeys(tuned, r.tuned).empty());
  Problems pr;
  const params::YamlNode parsed = params::ParseYaml(r.overrides_file, "over");
  const auto over = params::Flatten(parsed, params::Layout::kRos2, params::kStabilityNodeKey, &pr);
  EXPECT_TRUE(pr.empty());
  std::vector<std::string> overridden;
  for (const auto& e : over.entries) overridden.push_back(e.key);
  std::sort(overridden.begin(), overridden.end());
  const std::set<std::string> changed = params::DifferingKeys(r.tuned, StabilityParams{});
  EXPECT_EQ(std::vector<std::string>(changed.begin(), changed.end()), r.changed);
  EXPECT_EQ(overridden, r.changed);
  EXPECT_NE(r.tuned_file.find("2026-01-01T00:00:00Z"), std::string::npos);

  // The manifest names the outcome.
  const std::string manifest = study.ManifestYaml(r, {});
  EXPECT_NE(manifest.find("evaluations: 8\n"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("sensitivity: \"done\"\n"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("changed_keys: " + std::to_string(r.changed.size()) + "\n"),
            std::string::npos)
      << manifest;
}

// The search step: the base set at both steps decides; the optimiser's costs are the search
// step's, the comparison's the vehicle's own; a failed check falls back to the vehicle's step.
TEST_F(TuneStudyTest, TheSearchStepIsUsedWhereItsCheckPassesAndTheReportRunsAtTheOwnStep) {
  Recorder rec;
  // The sum objective: its merit is the training total at each step (the constrained objective's
  // own search-step behaviour, the select phase, has a test of its own).
  const auto sum = [](TuneStudyOptions& o) { o.objective = ObjectiveKind::kSum; };
  const TuneStudy coarse = Study("coarse.csv", 4, false, nullptr, 0.002, {}, sum);
  const TuneReport r = coarse.Run(rec);
  EXPECT_TRUE(r.plant_step.ran);
  EXPECT_TRUE(r.plant_step.passed) << PlantStepCheckMarkdown(r.plant_step);
  EXPECT_EQ(r.plant_step.used(), 0.002);
  ASSERT_EQ(r.plant_step.scenarios.size(), 2u);
  EXPECT_EQ(r.plant_step.scenarios[1].scenario, "power_on_c1");
  // Evaluation 0 is the base set at the search step; the comparison's baseline at the own step.
  EXPECT_EQ(r.optimisation.start_cost, r.plant_step.coarse_total);
  EXPECT_EQ(r.training[0].total, r.plant_step.fine_total);
  EXPECT_NE(r.plant_step.fine_total, r.plant_step.coarse_total);
  // The preparation counts both evaluators and the base set's two runs per scenario.
  ASSERT_FALSE(rec.totals.empty());
  EXPECT_EQ(rec.totals[0], 4 * 2);
  EXPECT_EQ(rec.last_jobs[0].first, 4 * 2);
  EXPECT_NE(r.comparison_markdown.find("## Search plant step"), std::string::npos);
  const std::string manifest = coarse.ManifestYaml(r, {});
  EXPECT_NE(manifest.find("search_plant_step: 0.002\n"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("search_plant_step_check: \"passed\"\n"), std::string::npos);
  EXPECT_NE(manifest.find("search_plant_step_used: 0.002\n"), std::string::npos);

  // No tolerance at all: the check fails and the search runs at the vehicle's own step, so the
  // optimisation starts from the comparison's baseline cost.
  PlantStepTolerances none;
  none.lap_time_s = none.progress = none.max_beta_deg = none.total_cost = 0.0;
  const TuneReport f = Study("fallback.csv", 4, false, nullptr, 0.002, none, sum).Run();
  EXPECT_TRUE(f.plant_step.ran);
  EXPECT_FALSE(f.plant_step.passed);
  EXPECT_EQ(f.plant_step.used(), 0.0);
  EXPECT_EQ(f.optimisation.start_cost, f.training[0].total);
  EXPECT_EQ(f.training[0].total, r.training[0].total);
  EXPECT_NE(f.comparison_markdown.find("own step instead"), std::string::npos);

  // The vehicles' own step asked for: nothing to check.
  const TuneReport same = Study("same.csv", 2, false, nullptr, 0.001, {}, sum).Run();
  EXPECT_FALSE(same.plant_step.ran);
  EXPECT_EQ(same.optimisation.start_cost, same.training[0].total);

  // A step outside [0, 5 ms] is refused before anything runs.
  EXPECT_THROW(Study("bad.csv", 2, false, nullptr, 0.01), std::invalid_argument);
}

TEST_F(TuneStudyTest, SameInputsGiveTheSameReport) {
  const TuneReport a = Study("a.csv", 6, false).Run();
  const TuneReport b = Study("b.csv", 6, false).Run();
  EXPECT_EQ(ReadOrEmpty((dir_ / "a.csv").string()), ReadOrEmpty((dir_ / "b.csv").string()));
  EXPECT_EQ(a.optimisation.best_u, b.optimisation.best_u);
  EXPECT_EQ(a.optimisation.best_cost, b.optimisation.best_cost);
  EXPECT_EQ(a.optimisation.best_eval, b.optimisation.best_eval);
  EXPECT_EQ(a.optimisation.evals, b.optimisation.evals);
  EXPECT_EQ(a.optimisation.stop_reason, b.optimisation.stop_reason);
  EXPECT_EQ(a.changed, b.changed);
  EXPECT_EQ(a.tuned_file, b.tuned_file);
  EXPECT_EQ(a.overrides_file, b.overrides_file);
  EXPECT_EQ(a.comparison_markdown, b.comparison_markdown);
  EXPECT_EQ(a.comparison_csv, b.comparison_csv);
  EXPECT_EQ(a.sensitivity_state, SensitivityState::kSkipped);
  EXPECT_EQ(b.sensitivity_state, SensitivityState::kSkipped);
  EXPECT_TRUE(a.sensitivity_csv.empty());
}

TEST_F(TuneStudyTest, TheStopFlagEndsTheOptimisationWithTheBestSoFar) {
  Recorder rec;
  rec.stop_after = 3;
  const TuneStudy study = Study("evaluations.csv", 50, true, &rec.stop);
  const TuneReport r = study.Run(rec);
  // The evaluation under way when the flag rose is the last one; nothing after it is logged.
  EXPECT_EQ(r.optimisation.stop_reason, "interrupted");
  EXPECT_EQ(r.optimisation.evals, 3);
  EXPECT_EQ(Rows(ReadOrEmpty((dir_ / "evaluations.csv").string())), 1 + 3);
  EXPECT_LT(r.optimisation.best_eval, 3);
  EXPECT_LE(r.optimisation.best_cost, r.optimisation.start_cost);
  // The best so far is compared and exported as usual; the sensitivity is skipped, and the
  // files say that nothing was checked for untested changes.
  ASSERT_EQ(r.training.size(), 2u);
  EXPECT_EQ(r.tuned_value.merit, r.optimisation.best_cost);
  EXPECT_NE(r.tuned_file.find("not checked for untested changes"), std::string::npos);
  EXPECT_FALSE(r.tuned_file.empty());
  EXPECT_EQ(r.sensitivity_state, SensitivityState::kSkipped);
  EXPECT_FALSE(r.neighbourhood_done);  // interrupted: no knife-edge check either
  EXPECT_EQ(rec.events.back(), "end export");
  EXPECT_NE(study.ManifestYaml(r, {}).find("sensitivity: \"skipped (interrupted)\"\n"),
            std::string::npos);

  // scw evaluate's table of the base and the tuned set is the tune's comparison.csv.
  const SetsEvaluation table =
      EvaluateSets(study.scenarios(), {study.base(), r.tuned}, {"baseline", "tuned"}, 1);
  EXPECT_EQ(table.csv, r.comparison_csv);
  // Its summary gives per set the total, the distribution over the scenarios and the activations.
  EXPECT_NE(
      table.markdown.find("| set | total cost | mean cost | 90th percentile | worst | aborts | "
                          "ESC/CS/ABS/TC [count] |"),
      std::string::npos)
      << table.markdown;
  const CostDistribution d = Distribution(r.training[1]);
  EXPECT_NE(table.markdown.find("| tuned | " + FormatFixed(r.training[1].total, 3) + " | " +
                                FormatFixed(d.mean, 3) + " | "),
            std::string::npos)
      << table.markdown;
}

TEST_F(TuneStudyTest, TheBaseOutsideARangeGrowsItOrIsRefusedBeforeAnythingRuns) {
  // The shipped ESC.beta_threshold_deactivate lies outside the default space's ratio range.
  const ScenarioSet set = ScenarioSet::FromYamlText(kSet, "tiny");
  const TuneStudy grown(StabilityParams{}, ParameterSpace::Default(), set, {});
  ASSERT_EQ(grown.grown().size(), 1u);
  EXPECT_NE(grown.grown()[0].find("ESC.beta_threshold_deactivate"), std::string::npos);
  EXPECT_TRUE(params::DifferingKeys(
                  grown.space().Decode(grown.start_point(), grown.base(), nullptr), grown.base())
                  .empty());
  TuneStudyOptions refuse;
  refuse.base_outside = BaseOutsideSpace::kRefuse;
  EXPECT_THROW(TuneStudy(StabilityParams{}, ParameterSpace::Default(), set, refuse), ConfigError);
  TuneStudyOptions bad;
  bad.algorithm = "crs3";
  EXPECT_THROW(TuneStudy(StabilityParams{}, TwoDimensions(), set, bad), std::invalid_argument);
}

// Never export what was not tested: with countersteer switched off in every training scenario,
// no run can respond to its gain, so the screen freezes it at the base value; the exported files
// keep the base value and say why.
TEST_F(TuneStudyTest, AKeyNoTrainingRunCanExerciseIsFrozenAndExportedAtTheBaseValue) {
  std::string no_cs = kSet;
  for (std::string::size_type at = 0;
       (at = no_cs.find("laps=1", at)) != std::string::npos && at < no_cs.find("held_out"); at += 7)
    no_cs.replace(at, 6, "laps=1, subsystems.cs=false");
  const TuneReport r = Study("frozen.csv", 6, true, nullptr, 0.0, {}, {}, no_cs).Run();
  ASSERT_TRUE(r.screened);
  ASSERT_EQ(r.frozen_dims, std::vector<int>{1});
  ASSERT_EQ(r.frozen.size(), 1u);
  EXPECT_EQ(r.frozen[0].rfind("countersteer_system.steering_factor (", 0), 0u) << r.frozen[0];
  EXPECT_EQ(r.tuned.countersteer_system.steering_factor,
            StabilityParams{}.countersteer_system.steering_factor);
  const std::string body = r.overrides_file.substr(r.overrides_file.find("/core/control"));
  EXPECT_EQ(body.find("steering_factor"), std::string::npos) << body;
  EXPECT_NE(r.tuned_file.find("frozen before the search"), std::string::npos);
  EXPECT_NE(r.comparison_markdown.find("frozen before the search at the base value (1"),
            std::string::npos);
  // The optimiser never moved it: the log has no coordinate for it, its argument stays put.
  const std::string log = ReadOrEmpty((dir_ / "frozen.csv").string());
  EXPECT_EQ(log.find("u:countersteer_system.steering_factor"), std::string::npos);
  EXPECT_NE(log.find("u:SlipControl.TC.rear.slip_threshold_hold_reduce"), std::string::npos);
  EXPECT_NE(ReadOrEmpty((dir_ / "frozen.identity.yaml").string())
                .find("frozen: [countersteer_system.steering_factor]"),
            std::string::npos);
  // Whatever the sensitivity reverted is at the base value too.
  for (const auto& rev : r.reverted) EXPECT_NE(rev.find("("), std::string::npos);
  EXPECT_TRUE(r.new_findings.empty());
}

// Resume: an interrupted log continued with the same settings gives the uninterrupted run's log,
// appended to and never rewritten; a log that belongs to another run (seed, scenarios) is
// refused before a byte is written.
TEST_F(TuneStudyTest, ResumeIsExactAndADivergingResumeIsRefusedBeforeAnythingIsWritten) {
  (void)Study("full.csv", 6, false).Run();
  const std::string full = ReadOrEmpty((dir_ / "full.csv").string());
  Recorder rec;
  rec.stop_after = 3;
  (void)Study("part.csv", 6, false, &rec.stop).Run(rec);
  const std::string part = ReadOrEmpty((dir_ / "part.csv").string());
  const std::string part_id = ReadOrEmpty((dir_ / "part.identity.yaml").string());
  ASSERT_EQ(Rows(part), 1 + 3);
  ASSERT_EQ(full.rfind(part, 0), 0u);

  const auto resume = [this](TuneStudyOptions& o) { o.resume_log = (dir_ / "part.csv").string(); };
  // Another seed, and another scenario set with the same names: refused, the log untouched.
  const auto other_seed = [&](TuneStudyOptions& o) {
    resume(o);
    o.seed = 2;
  };
  EXPECT_THROW(Study("part.csv", 6, false, nullptr, 0.0, {}, other_seed).Run(), ConfigError);
  std::string other_set = kSet;
  other_set.replace(other_set.find("gg_scale=1.1"), 12, "gg_scale=1.2");
  try {
    (void)Study("part.csv", 6, false, nullptr, 0.0, {}, resume, other_set).Run();
    ADD_FAILURE() << "a resume with other scenarios was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("scenarios_sha256"), std::string::npos) << e.what();
  }
  EXPECT_EQ(ReadOrEmpty((dir_ / "part.csv").string()), part);
  EXPECT_EQ(ReadOrEmpty((dir_ / "part.identity.yaml").string()), part_id);

  // The same settings: the logged rows are replayed, the rest appended; the uninterrupted log.
  const TuneReport r = Study("part.csv", 6, false, nullptr, 0.0, {}, resume).Run();
  EXPECT_EQ(r.optimisation.replayed, 3);
  EXPECT_EQ(ReadOrEmpty((dir_ / "part.csv").string()), full);
  EXPECT_EQ(ReadOrEmpty((dir_ / "part.identity.yaml").string()), part_id);
}

// Valid by construction: every point of the default space, decoded against the car's shipped
// set, adds no `scw params check` finding the shipped set does not have (the hysteresis ratios
// refer to the smallest activation threshold the car interpolates, not the smallest breakpoint).
TEST(TunedSetFindings, NoPointOfTheDefaultSpaceAddsACheckFinding) {
  const StabilityParams base;
  const ParameterSpace space =
      ParameterSpace::Default().WithBase(base, BaseOutsideSpace::kGrow, nullptr);
  const auto design = LatinHypercube(400, space.size(), 7);
  int feasible = 0;
  for (auto u : design) {
    Problems pr;
    const StabilityParams p = space.Decode(u, base, &pr);
    if (!pr.empty()) continue;
    ++feasible;
    const auto found = NewCheckFindings(base, p);
    EXPECT_TRUE(found.empty()) << found.front();
  }
  EXPECT_GT(feasible, 300);
  // The corners of the cube too.
  for (double c : {0.0, 1.0}) {
    Problems pr;
    const StabilityParams p = space.Decode(std::vector<double>(space.size(), c), base, &pr);
    if (pr.empty()) {
      const auto found = NewCheckFindings(base, p);
      EXPECT_TRUE(found.empty()) << found.front();
    }
  }
  // The check itself sees an inverted hysteresis it is given.
  StabilityParams inverted = base;
  inverted.ESC.psi_dot_error_threshold_deactivate = 0.034;
  EXPECT_FALSE(NewCheckFindings(base, inverted).empty());
}

}  // namespace
}  // namespace scw::tuning
