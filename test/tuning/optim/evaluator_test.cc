#include "tuning/optim/evaluator.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

#include "tuning/optim/space.h"
#include "tuning/optim/tuner.h"

namespace scw::tuning {
namespace {

std::vector<ScenarioEntry> SmallSet() {
  return {{"short_nominal", 1.0, "", {"laps=1", "gg_scale=1.1"}},
          {"short_oversteer",
           2.0,
           "",
           {"laps=1", "grip.rear_mu_y=0.8", "gg_scale=1.3", "abort.lock_slip_pct=100"}}};
}

TEST(EvaluatorTest, DefaultSetFileEqualsBuiltIn) {
  const auto file =
      ScenarioSet::FromFile(std::string(SCW_SOURCE_DIR) + "/params/scenarios/default_set.yaml");
  EXPECT_EQ(file.ToYaml(), ScenarioSet::Default().ToYaml())
      << "regenerate with: scw tune --print-scenarios > params/scenarios/default_set.yaml";
}

TEST(EvaluatorTest, BadSetFilesNameEntryAndRule) {
  const char* bad[] = {
      "training: []\n",
      "training:\n  - {weight: 1.0}\n",
      "training:\n  - {name: a, weight: -1.0}\n",
      "training:\n  - {name: a, set: [gg_scale]}\n",
      "training:\n  - {name: a, colour: red}\n",
      "name: x\n",
      "training:\n  - {name: a}\ncost: {sideslip_weight: -2.0}\n",
  };
  for (const char* text : bad) {
    SCOPED_TRACE(text);
    EXPECT_THROW(ScenarioSet::FromYamlText(text, "set.yaml"), ConfigError);
  }
}

TEST(EvaluatorTest, ResultsAreIdenticalForOneAndTwoThreads) {
  const params::CostWeights w;
  const auto one = BatchEvaluator::FromEntries(SmallSet(), "", w, 1);
  const auto two = BatchEvaluator::FromEntries(SmallSet(), "", w, 2);
  params::StabilityParams a, b;
  b.ESC.kp_psi_dot = 4.0;
  const auto r1 = one.Evaluate(std::vector<params::StabilityParams>{a, b});
  const auto r2 = two.Evaluate(std::vector<params::StabilityParams>{a, b});
  ASSERT_EQ(r1.size(), 2u);
  for (std::size_t s = 0; s < 2; ++s) {
    EXPECT_EQ(r1[s].total, r2[s].total);
    for (std::size_t k = 0; k < r1[s].runs.size(); ++k) {
      EXPECT_EQ(r1[s].runs[k].lap_times, r2[s].runs[k].lap_times);
      EXPECT_EQ(r1[s].runs[k].max_abs_sideslip, r2[s].runs[k].max_abs_sideslip);
    }
  }
  // Weighted sum of the per-scenario costs.
  EXPECT_DOUBLE_EQ(r1[0].total, r1[0].costs[0].total + 2.0 * r1[0].costs[1].total);
}

TEST(EvaluatorTest, LongestFirstSortsByDecreasingLengthTiesByIndex) {
  EXPECT_EQ(LongestFirst({0.01, 0.07, 0.03, 0.07, 0.0}), (std::vector<int>{1, 3, 2, 0, 4}));
  EXPECT_TRUE(LongestFirst({}).empty());
}

// The second call hands the jobs out in the order the first call's run times give (longest
// first), the first call by planned distance: the results must not depend on it.
TEST(EvaluatorTest, JobOrderLearnedFromEarlierCallsDoesNotChangeResults) {
  const params::CostWeights w;
  std::vector<ScenarioEntry> entries = SmallSet();
  entries.push_back({"short_abort", 1.0, "", {"laps=1", "grip.rear_mu_y=0.5", "gg_scale=1.4"}});
  const auto ev = BatchEvaluator::FromEntries(entries, "", w, 2);
  params::StabilityParams a, b;
  b.ESC.kp_psi_dot = 4.0;
  const std::vector<params::StabilityParams> sets{a, b};
  const auto first = ev.Evaluate(sets);
  const auto second = ev.Evaluate(sets);
  const auto fresh = BatchEvaluator::FromEntries(entries, "", w, 1).Evaluate(sets);
  for (std::size_t s = 0; s < sets.size(); ++s) {
    EXPECT_EQ(first[s].total, second[s].total);
    EXPECT_EQ(first[s].total, fresh[s].total);
    for (std::size_t k = 0; k < entries.size(); ++k) {
      EXPECT_EQ(EncodeRunMetrics(first[s].runs[k]), EncodeRunMetrics(second[s].runs[k]));
      EXPECT_EQ(EncodeRunMetrics(first[s].runs[k]), EncodeRunMetrics(fresh[s].runs[k]));
    }
  }
}

// A memo shared by evaluators returns the runs they made before, bit for bit, without running
// them again: across calls, within a call (a repeated set), across evaluators whose entries
// coincide (a subset of the scenarios), never for an entry that differs (another override); the
// progress still counts every job; a memo too small to hold a set forgets and stays exact.
TEST(EvaluatorTest, ARunMemoReturnsTheRunsItHoldsBitForBit) {
  const params::CostWeights w;
  params::StabilityParams a, b, bad;
  b.ESC.kp_psi_dot = 4.0;
  bad.ESC.beta_threshold_activate = {0.1, 0.2, 0.3};
  const std::vector<params::StabilityParams> sets{a, b, a, bad};
  const auto plain = BatchEvaluator::FromEntries(SmallSet(), "", w, 2).Evaluate(sets);
  const auto same = [&](const std::vector<SetEvaluation>& got, std::size_t scenario_offset) {
    for (std::size_t s = 0; s < sets.size(); ++s) {
      EXPECT_EQ(got[s].invalid, plain[s].invalid);
      for (std::size_t k = 0; k < got[s].runs.size(); ++k)
        EXPECT_EQ(EncodeRunMetrics(got[s].runs[k]),
                  EncodeRunMetrics(plain[s].runs[k + scenario_offset]));
    }
  };
  for (std::size_t capacity : {std::size_t{1}, RunMemo::kDefaultMaxSets}) {
    SCOPED_TRACE(capacity);
    auto memo = std::make_shared<RunMemo>(capacity);
    const auto ev = BatchEvaluator::FromEntries(SmallSet(), "", w, 2, {}, nullptr, memo);
    int last_done = 0, calls = 0;
    const auto first = ev.Evaluate(sets, [&](int done, int total) {
      EXPECT_EQ(total, 8);
      EXPECT_EQ(done, last_done + 1);
      last_done = done;
      ++calls;
    });
    EXPECT_EQ(calls, 8);
    same(first, 0);
    EXPECT_EQ(memo->reused_runs(), 0);  // the repeated set copies within the call
    EXPECT_EQ(memo->made_runs(), 6);    // a, b, bad: 2 runs each
    const auto again = ev.Evaluate(sets);
    same(again, 0);
    if (capacity > 1) {
      EXPECT_EQ(memo->reused_runs(), 6);  // a, b, bad: 2 runs each
      // An evaluator of the second entry alone finds its runs; one with another override does not.
      const auto sub = BatchEvaluator::FromEntries({SmallSet()[1]}, "", w, 1, {}, nullptr, memo);
      same(sub.Evaluate(sets), 1);
      EXPECT_EQ(memo->reused_runs(), 9);
      auto other_entry = SmallSet()[1];
      other_entry.overrides.push_back("grip.rear_mu_y=0.81");
      BatchEvaluator::FromEntries({other_entry}, "", w, 1, {}, nullptr, memo).Evaluate(sets);
      EXPECT_EQ(memo->reused_runs(), 9);
    }
  }
}

// Full, the memo forgets the set it learnt first and keeps the later ones.
TEST(EvaluatorTest, AFullRunMemoForgetsTheOldestSet) {
  RunMemo memo(2);
  const std::vector<std::string> entries = {"e1", "e2"};
  RunMetrics runs[2];
  runs[1].max_speed = 42.0;
  const std::string invalid[2] = {"", "why"};
  for (const char* set : {"s1", "s2", "s3"}) memo.Store(set, entries, runs, invalid);
  std::vector<RunMetrics> got;
  std::vector<std::string> why;
  EXPECT_FALSE(memo.Find("s1", entries, &got, &why));
  ASSERT_TRUE(memo.Find("s2", entries, &got, &why));
  ASSERT_TRUE(memo.Find("s3", entries, &got, &why));
  EXPECT_EQ(got[1].max_speed, 42.0);
  EXPECT_EQ(why[1], "why");
  EXPECT_FALSE(memo.Find("s3", {"e1", "e3"}, &got, &why));  // an entry it never ran
  EXPECT_EQ(memo.made_runs(), 6);
  EXPECT_EQ(memo.reused_runs(), 4);
  memo.Store("s2", entries, runs, invalid);  // known: nothing forgotten
  EXPECT_TRUE(memo.Find("s3", entries, &got, &why));
}

TEST(EvaluatorTest, AnInvalidSetIsAResultWithAStatus) {
  const auto ev = BatchEvaluator::FromEntries({SmallSet()[0]}, "", params::CostWeights{}, 2);
  params::StabilityParams bad;
  bad.ESC.beta_threshold_activate = {0.1, 0.2, 0.3};  // unequal array lengths
  const auto r = ev.Evaluate(bad);
  EXPECT_EQ(r.runs[0].status, RunStatus::kInvalidParams);
  EXPECT_FALSE(r.invalid.empty());
  EXPECT_TRUE(std::isfinite(r.total));
}

TEST(EvaluatorTest, TuneIsDeterministicForOneAndTwoThreads) {
  const auto space = ParameterSpace::Default();
  const params::StabilityParams base;
  auto run = [&](int threads, const std::string& log) {
    const auto ev =
        BatchEvaluator::FromEntries({SmallSet()[1]}, "", params::CostWeights{}, threads);
    TunerOptions o;
    o.max_evals = 8;
    o.seed = 5;
    o.log_path = log;
    return Tune(
        space.Encode(base),
        [&](const std::vector<double>& u) {
          Problems pr;
          const auto p = space.Decode(u, base, &pr);
          return Evaluation{pr.empty() ? ev.Evaluate(p).total : 1e4, "ok", {}};
        },
        o);
  };
  const auto dir = std::filesystem::temp_directory_path();
  const auto a = run(1, (dir / "scw_tune_t1.csv").string());
  const auto b = run(2, (dir / "scw_tune_t2.csv").string());
  EXPECT_EQ(a.best_u, b.best_u);
  EXPECT_EQ(a.best_cost, b.best_cost);
}

}  // namespace
}  // namespace scw::tuning

#include "params/io/write.h"
#include "tuning/sim/scenario.h"

namespace scw::tuning {
namespace {

TEST(ScenarioFilesTest, ShippedScenarioFilesLoadAndDefaultEqualsBuiltIn) {
  const std::string dir = std::string(SCW_SOURCE_DIR) + "/params/scenarios";
  int loaded = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    // Scenario sets (*_set.yaml) are read by their own tests; the rest are scenario files.
    const bool set_file = name.size() > 9 && name.substr(name.size() - 9) == "_set.yaml";
    if (set_file || entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(name);
    EXPECT_NO_THROW(LoadScenario(entry.path().string()));
    ++loaded;
  }
  EXPECT_GE(loaded, 4);
  EXPECT_EQ(params::ToPlainYaml(LoadScenario(dir + "/default.yaml")),
            params::ToPlainYaml(DefaultScenario()))
      << "regenerate with: scw simulate --print-scenario > params/scenarios/default.yaml";
}

// A maneuver in a scenario set (kind: maneuver): the evaluator runs RunManeuver, its cost is the
// failed-criteria term (tuning/optim/cost.h), and a set file writes the criteria weight only when
// it is changed.
TEST(EvaluatorTest, ManeuverScenarioInASet) {
  ScenarioSet set = ScenarioSet::FromYamlText(
      "training:\n"
      "  - {name: swd, set: [kind=maneuver, maneuver.name=sine_with_dwell, maneuver.speed=40,\n"
      "      \"maneuver.amplitude_factors=[5.0, 6.5]\", maneuver.extend_to_270deg=false]}\n",
      "set.yaml");
  EXPECT_EQ(set.ToYaml().find("failed_criterion_weight"), std::string::npos);  // at its default
  set.cost.failed_criterion_weight = 50.0;
  EXPECT_NE(set.ToYaml().find("failed_criterion_weight: 50.0"), std::string::npos);
  EXPECT_EQ(ScenarioSet::Default().ToYaml().find("failed_criterion_weight"), std::string::npos);
  const BatchEvaluator ev = BatchEvaluator::FromEntries(set.training, "", set.cost, 1);
  ASSERT_EQ(ev.scenarios().size(), 1u);
  EXPECT_EQ(ev.scenarios()[0].track, nullptr);  // a maneuver drives no track
  const params::StabilityParams base;
  const SetEvaluation e = ev.Evaluate(base);
  const RunMetrics& m = e.runs[0];
  EXPECT_EQ(m.criteria_checked, 2 * 3);  // two amplitudes from 5 A on: two ratios, displacement
  EXPECT_DOUBLE_EQ(e.costs[0].criteria, 50.0 * (m.criteria_failed + m.criteria_miss));
  EXPECT_DOUBLE_EQ(e.costs[0].lap_time, 0.0);
  EXPECT_DOUBLE_EQ(e.total, e.costs[0].total);
  // The same maneuver with every subsystem off is a different run (the switches apply).
  params::StabilityParams off = base;
  off.ESC.enabled = off.countersteer_system.enabled = false;
  off.SlipControl.ABS.enabled = off.SlipControl.TC.enabled = false;
  const RunMetrics m_off = ev.Evaluate(off).runs[0];
  EXPECT_EQ(m_off.esc_count + m_off.cs_count + m_off.abs_count + m_off.tc_count, 0);
}

}  // namespace
}  // namespace scw::tuning
