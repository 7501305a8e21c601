// Monte-Carlo blocks of scenario sets (tuning/sim/monte_carlo.h): deterministic expansion with
// stable names, grids, list keys, rules on bad input, and the shipped robust set.
#include "tuning/sim/monte_carlo.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>

#include "tuning/sim/scenario.h"
#include "tuning/sim/scenario_set.h"

namespace scw::tuning {
namespace {

std::string Set(const std::string& block, const std::string& count = "4") {
  return "training:\n"
         "  - monte_carlo:\n"
         "      name: mc\n"
         "      count: " +
         count +
         "\n"
         "      seed: 7\n"
         "      set: [kind=critical, laps=1]\n" +
         block + "held_out:\n  - {name: clean, set: [laps=1]}\n";
}

const std::string kVary =
    "      vary:\n"
    "        events.throttle.corner: {choice: [1, 3, 5]}\n"
    "        events.throttle.s: {uniform: [0, 20], step: 1}\n"
    "        events.throttle.lap: {choice: [1]}\n"
    "        events.throttle.duration: {uniform: [0.5, 1.0]}\n"
    "        events.throttle.value: {uniform: [0.8, 1.0], step: 0.05}\n"
    "        grip.rear_mu_y: {uniform: [0.9, 1.1]}\n"
    "        seed: {integer: [1, 6]}\n";

// The value a key ends with (the last override of it wins).
std::string Value(const ScenarioEntry& e, const std::string& key) {
  std::string v = "<none>";
  for (const auto& o : e.overrides)
    if (o.rfind(key + "=", 0) == 0) v = o.substr(key.size() + 1);
  return v;
}

TEST(MonteCarloTest, ExpandsDeterministicallyWithStableNames) {
  const ScenarioSet a = ScenarioSet::FromYamlText(Set(kVary), "a.yaml");
  const ScenarioSet b = ScenarioSet::FromYamlText(Set(kVary), "b.yaml");
  ASSERT_EQ(a.training.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(a.training[i].name, "mc_00" + std::to_string(i));
    EXPECT_EQ(a.training[i].overrides, b.training[i].overrides);
    // The base overrides first, then one per drawn key, in the order written.
    ASSERT_EQ(a.training[i].overrides.size(), 9u);
    EXPECT_EQ(a.training[i].overrides[0], "kind=critical");
  }
  // More draws keep the first ones: a draw depends only on (seed, index).
  const ScenarioSet more = ScenarioSet::FromYamlText(Set(kVary, "40"), "c.yaml");
  ASSERT_EQ(more.training.size(), 40u);
  EXPECT_EQ(more.training[0].name, "mc_000");
  EXPECT_EQ(more.training[39].name, "mc_039");
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_EQ(more.training[i].overrides, a.training[i].overrides);
  // Another seed, other draws.
  std::string other = Set(kVary);
  other.replace(other.find("seed: 7"), 7, "seed: 8");
  const ScenarioSet c = ScenarioSet::FromYamlText(other, "d.yaml");
  EXPECT_NE(c.training[0].overrides, a.training[0].overrides);
}

TEST(MonteCarloTest, DrawsStayInTheirRangesAndListKeysBecomeLists) {
  const ScenarioSet s = ScenarioSet::FromYamlText(Set(kVary, "200"), "a.yaml");
  std::set<std::string> corners, seeds;
  for (const auto& e : s.training) {
    corners.insert(Value(e, "events.throttle.corner"));
    seeds.insert(Value(e, "seed"));
    const std::string v = Value(e, "events.throttle.value");
    ASSERT_TRUE(v.size() > 2 && v.front() == '[' && v.back() == ']') << v;
    const double value = std::stod(v.substr(1, v.size() - 2));
    EXPECT_GE(value, 0.8);
    EXPECT_LE(value, 1.0);
    EXPECT_NEAR(value / 0.05, std::round(value / 0.05), 1e-9) << value;
    const double mu = std::stod(Value(e, "grip.rear_mu_y"));  // a scalar key: no brackets
    EXPECT_GE(mu, 0.9);
    EXPECT_LE(mu, 1.1);
    // Every expanded entry is a valid scenario.
    EXPECT_NO_THROW(LoadEntry(e, "")) << e.name;
  }
  EXPECT_EQ(corners, (std::set<std::string>{"[1]", "[3]", "[5]"}));
  EXPECT_EQ(seeds, (std::set<std::string>{"1", "2", "3", "4", "5", "6"}));
}

TEST(MonteCarloTest, GridTimesCountFirstKeySlowest) {
  const ScenarioSet s = ScenarioSet::FromYamlText(Set("      grid:\n"
                                                      "        gg_scale: [1.0, 1.1]\n"
                                                      "        laps: [1, 2, 3]\n",
                                                      "2"),
                                                  "g.yaml");
  ASSERT_EQ(s.training.size(), 12u);
  EXPECT_EQ(Value(s.training[0], "gg_scale"), "1.0");
  EXPECT_EQ(Value(s.training[1], "laps"), "1");  // the two draws of the first point
  EXPECT_EQ(Value(s.training[2], "laps"), "2");
  EXPECT_EQ(Value(s.training[5], "laps"), "3");
  EXPECT_EQ(Value(s.training[6], "gg_scale"), "1.1");
  EXPECT_EQ(Value(s.training[11], "laps"), "3");
  // The base override comes first, the grid value after it wins.
  EXPECT_EQ(s.training[0].overrides[1], "laps=1");
  EXPECT_EQ(LoadEntry(s.training[11], "").laps, 3);
}

TEST(MonteCarloTest, BadBlocksNameTheFileTheKeyAndTheRule) {
  auto problem = [](const std::string& block, const std::string& count = "4") {
    try {
      ScenarioSet::FromYamlText(Set(block, count), "bad.yaml");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(problem("      vary:\n        grip.rear_muy: {uniform: [0.9, 1.1]}\n")
                .find("bad.yaml: training[0].monte_carlo.vary.grip.rear_muy: unknown scenario key"),
            std::string::npos);
  EXPECT_NE(problem("      vary:\n        seed: {uniform: [2, 1]}\n").find("low <= high"),
            std::string::npos);
  EXPECT_NE(problem("      vary:\n        seed: {integer: [1.5, 3]}\n").find("whole numbers"),
            std::string::npos);
  EXPECT_NE(problem("      vary:\n        seed: {choice: []}\n")
                .find("training[0].monte_carlo.vary.seed.choice: needs at least 1 value, has 0"),
            std::string::npos);
  EXPECT_NE(
      problem("      vary:\n        seed: {choice: [1], uniform: [1, 2]}\n").find("exactly one of"),
      std::string::npos);
  EXPECT_NE(problem("      vary:\n        seed: {integer: [1, 2], step: 1}\n")
                .find("only a uniform draw takes a step"),
            std::string::npos);
  EXPECT_NE(problem("", "0").find("training[0].monte_carlo.count: 0 is below the lower bound 1"),
            std::string::npos);
  EXPECT_NE(problem("      grid:\n        laps: [1, 2]\n        gg_scale: [1.0, 1.1]\n", "100000")
                .find("expands to more than"),
            std::string::npos);
  EXPECT_NE(problem("      colour: red\n").find("unknown key"), std::string::npos);
  // A drawn value the scenario rejects is an error when the scenario is loaded, naming the key.
  const ScenarioSet s = ScenarioSet::FromYamlText(
      Set("      vary:\n        laps: {integer: [200, 300]}\n"), "x.yaml");
  EXPECT_THROW(LoadEntry(s.training[0], ""), ConfigError);
}

TEST(MonteCarloTest, NamesAreUniqueAcrossTheSet) {
  const std::string text =
      "training:\n"
      "  - monte_carlo: {name: mc, count: 2, vary: {seed: {integer: [1, 9]}}}\n"
      "held_out:\n"
      "  - {name: mc_001, set: [laps=1]}\n";
  try {
    ScenarioSet::FromYamlText(text, "dup.yaml");
    FAIL() << "a duplicate name must be refused";
  } catch (const ConfigError& e) {
    // The earlier name is that of the block's scenario 1 (the file has no training[1]).
    EXPECT_NE(std::string(e.what()).find("held_out[0].name: 'mc_001' is already the name of "
                                         "scenario 1 of training[0].monte_carlo (line 4)"),
              std::string::npos)
        << e.what();
  }
}

TEST(MonteCarloTest, ShippedRobustSetIsLargeDisjointAndValid) {
  const std::string path = std::string(SCW_SOURCE_DIR) + "/params/scenarios/robust_set.yaml";
  const ScenarioSet s = ScenarioSet::FromFile(path);
  EXPECT_GE(s.training.size(), 128u);
  EXPECT_GE(s.held_out.size(), 16u);
  std::set<std::vector<std::string>> train;
  for (const auto& e : s.training) {
    train.insert(e.overrides);
    EXPECT_NO_THROW(LoadEntry(e, s.base_dir)) << e.name;
  }
  for (const auto& e : s.held_out) {
    EXPECT_EQ(train.count(e.overrides), 0u) << e.name << " repeats a training scenario";
    EXPECT_NO_THROW(LoadEntry(e, s.base_dir)) << e.name;
  }
  // Printing the set and reading it back gives the same scenarios (scw tune --print-scenarios).
  const ScenarioSet back = ScenarioSet::FromYamlText(s.ToYaml(), path);
  ASSERT_EQ(back.training.size(), s.training.size());
  for (std::size_t i = 0; i < s.training.size(); ++i) {
    EXPECT_EQ(back.training[i].name, s.training[i].name);
    EXPECT_EQ(back.training[i].overrides, s.training[i].overrides);
  }
}

}  // namespace
}  // namespace scw::tuning
