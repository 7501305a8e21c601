// Scenario-set files (tuning/sim/scenario_set.h) through the schema: every member described,
// strict errors with key paths and lines, the shipped files, and the round trip of the file form
// (Monte-Carlo blocks included) through the writer.
#include "tuning/sim/scenario_set.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "params/io/docs.h"
#include "params/io/load.h"
#include "params/io/write.h"
#include "params/io/yaml_doc.h"
#include "test/common/field_count.h"

namespace scw::tuning {
namespace {

// The number of members a Visit lists.
struct CountVisitor {
  int n = 0;
  template <class T>
  void Field(const T&, const params::Meta&) {
    ++n;
  }
  template <class T>
  void List(const T&, const params::Meta&) {
    ++n;
  }
  template <class T>
  void Map(const T&, const params::Meta&) {
    ++n;
  }
  template <class T>
  void Nested(std::string_view, const T&, bool = false) {
    ++n;
  }
};
template <class S>
std::size_t Listed() {
  CountVisitor v;
  const S s{};
  S::Visit(s, v);
  return static_cast<std::size_t>(v.n);
}

TEST(ScenarioSetTest, EveryMemberIsDescribed) {
  EXPECT_EQ(Listed<ScenarioEntry>(), test::FieldCount<ScenarioEntry>());
  EXPECT_EQ(Listed<MonteCarloDraw>(), test::FieldCount<MonteCarloDraw>());
  EXPECT_EQ(Listed<MonteCarloBlock>(), test::FieldCount<MonteCarloBlock>());
  EXPECT_EQ(Listed<ScenarioSetFile>(), test::FieldCount<ScenarioSetFile>());
}

TEST(ScenarioSetTest, DefaultSetFileIsTheBuiltInSetByteForByte) {
  const std::string path = std::string(SCW_SOURCE_DIR) + "/params/scenarios/default_set.yaml";
  EXPECT_EQ(params::ReadTextFile(path), ScenarioSet::Default().ToYaml())
      << "regenerate with: scw tune --print-scenarios > params/scenarios/default_set.yaml";
}

TEST(ScenarioSetTest, FileIsWrittenLikeEveryOtherText) {
  const ScenarioSet s = ScenarioSet::FromYamlText(
      "name: \"my set\"\n"
      "training:\n"
      "  - {name: a, weight: 2, file: wet.yaml, set: [\"x=1 2\"]}\n"
      "  - {name: b, file: \"dir/with space.yaml\"}\n",
      "dir/set.yaml");
  EXPECT_EQ(s.base_dir, "dir");
  const std::string yaml = s.ToYaml();
  EXPECT_NE(yaml.find("name: \"my set\"\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("  - {name: a, weight: 2.0, file: wet.yaml, set: [\"x=1 2\"]}\n"),
            std::string::npos)
      << yaml;
  EXPECT_NE(yaml.find("  - {name: b, weight: 1.0, file: \"dir/with space.yaml\", set: []}\n"),
            std::string::npos)
      << yaml;
  EXPECT_EQ(yaml.find("held_out"), std::string::npos) << yaml;  // none: left out
  EXPECT_EQ(ScenarioSet::FromYamlText(yaml, "dir/set.yaml").ToYaml(), yaml);
}

// The file form with its blocks unexpanded is written through the schema (one flow map per entry,
// a block as {monte_carlo: {...}}) and reads back to the same file and the same scenarios.
TEST(ScenarioSetTest, BlocksRoundTripThroughTheSchemaWriter) {
  const std::string path = std::string(SCW_SOURCE_DIR) + "/params/scenarios/robust_set.yaml";
  const auto file = params::LoadPlainFile<ScenarioSetFile>(path);
  const std::string yaml = params::ToPlainYaml(file, "", params::TextStyle::kPlainWhereSafe);
  EXPECT_NE(yaml.find("  - {monte_carlo: {name: power_on, count: 48, seed: 1, weight: 1.0, set: "
                      "[kind=critical, laps=1, abort.max_lateral_error=10, "
                      "plan_with_nominal_grip=true, \"events.throttle.lap=[1]\"], vary: "
                      "{events.throttle.corner: {choice: [1, 2, 3, 5, 7, 8, 9]}, "
                      "events.throttle.s: {uniform: [0.0, 25.0], step: 1.0}, "),
            std::string::npos)
      << yaml;
  EXPECT_NE(yaml.find("grid: {gg_scale: [1.05, 1.1, 1.15, 1.2]}"), std::string::npos) << yaml;
  const auto back = params::LoadPlainText<ScenarioSetFile>(yaml, "printed.yaml");
  EXPECT_EQ(params::ToPlainYaml(back, "", params::TextStyle::kPlainWhereSafe), yaml);
  EXPECT_EQ(ScenarioSet::FromYamlText(yaml, path).ToYaml(), ScenarioSet::FromFile(path).ToYaml());
}

// The built-in robust set is the shipped file, and it draws the plant values we do not know within
// the ranges docs/scenarios.md states, in every scenario.
TEST(ScenarioSetTest, TheBuiltInRobustSetIsTheFileAndDrawsThePlantWithinItsRanges) {
  const std::string path = std::string(SCW_SOURCE_DIR) + "/params/scenarios/robust_set.yaml";
  const ScenarioSet robust = ScenarioSet::FromNameOrFile("robust");
  EXPECT_EQ(robust.ToYaml(), ScenarioSet::FromFile(path).ToYaml());
  EXPECT_EQ(ScenarioSet::FromNameOrFile("default").ToYaml(), ScenarioSet::Default().ToYaml());
  ASSERT_EQ(robust.training.size(), 128u);
  ASSERT_EQ(robust.held_out.size(), 40u);
  std::set<double> dead_times;
  for (const auto* group : {&robust.training, &robust.held_out})
    for (const auto& e : *group) {
      const params::ScenarioParams sc = LoadEntry(e, robust.base_dir);
      EXPECT_GE(sc.plant.brake_dead_time, 0.04) << e.name;
      EXPECT_LE(sc.plant.brake_dead_time, 0.116) << e.name;
      EXPECT_GE(sc.plant.steering_delay, 0.0) << e.name;
      EXPECT_LE(sc.plant.steering_delay, 0.06) << e.name;
      EXPECT_GE(sc.plant.rear_tire_falloff, 0.5) << e.name;
      EXPECT_LE(sc.plant.rear_tire_falloff, 1.5) << e.name;
      EXPECT_GE(sc.plant.yaw_inertia_scale, 0.8) << e.name;
      EXPECT_LE(sc.plant.yaw_inertia_scale, 1.2) << e.name;
      dead_times.insert(sc.plant.brake_dead_time);
    }
  EXPECT_GT(dead_times.size(), 20u);  // drawn, not one value
}

TEST(ScenarioSetTest, BadFilesNameTheKeyPathTheRuleAndTheLine) {
  const std::string mc =
      "training:\n"
      "  - monte_carlo:\n"
      "      name: mc\n"
      "      count: 4\n"
      "      set: [kind=critical]\n";
  const struct {
    std::string text, first_problem;
  } cases[] = {
      {"training: []\n", "training: needs at least 1 entry, has 0 (line 1)"},
      {"name: x\n", "training: required key is missing"},
      {"training: {name: a}\n", "training: expected a list of maps, got a map (line 1)"},
      {"training: [5]\n",
       "training[0]: expected a map {name, weight, file, set} or {monte_carlo: {...}}, got the "
       "integer 5 (line 1)"},
      {"training:\n  - {weight: 1.0}\n", "training[0].name: required key is missing (line 2)"},
      {"training:\n  - {name: \"\"}\n", "training[0].name: must not be empty (line 2)"},
      {"training:\n  - {name: a, weight: -1.0}\n",
       "training[0].weight: -1 is below the lower bound 0 (line 2)"},
      {"training:\n  - {name: a, set: [laps=1, gg_scale]}\n",
       "training[0].set[1]: must look like key=value, got 'gg_scale' (line 2)"},
      {"training:\n  - {name: a, colour: red}\n",
       "training[0].colour: unknown key (expected name, weight, file, set) (line 2)"},
      {"trainig:\n  - {name: a}\n", "training: required key is missing"},
      {"training:\n  - {name: a}\nheld_out: []\n",
       "held_out: needs at least 1 entry, has 0 (line 3)"},
      {"training:\n  - {name: a}\ncost: {sideslip_weight: 2.0}\n",
       "cost.sideslip_allowed_deg: required key is missing (line 3)"},
      {"training:\n  - {name: a}\ncost: 5\n", "cost: expected a map, got the integer 5 (line 3)"},
      {"training:\n  - {name: a}\n  - {name: a}\n",
       "training[1].name: 'a' is already the name of training[0] (line 3)"},
      {"training:\n  - {name: a, name: b}\n",
       "training[0].name: given 2 times (line 2: a, line 2: b); the car's node uses the last one "
       "(b); give each key once"},
      {"training:\n  - monte_carlo: {name: mc}\n    weight: 2.0\n",
       "training[0].weight: unknown key: a monte_carlo entry has no other keys (line 3)"},
      {"training:\n  - monte_carlo: 5\n",
       "training[0].monte_carlo: expected a map {name, count, seed, weight, file, set, vary, "
       "grid}, got the integer 5 (line 2)"},
      {"training:\n  - monte_carlo: {count: 2}\n",
       "training[0].monte_carlo.name: required key is missing (line 2)"},
      {"training:\n  - monte_carlo: {name: mc, count: 0}\n",
       "training[0].monte_carlo.count: 0 is below the lower bound 1 (line 2)"},
      {"training:\n  - monte_carlo: {name: mc, seed: -1}\n",
       "training[0].monte_carlo.seed: -1 is below the lower bound 0 (line 2)"},
      {"training:\n  - monte_carlo: {name: mc, set: [a]}\n",
       "training[0].monte_carlo.set[0]: must look like key=value, got 'a' (line 2)"},
      {mc + "      colour: red\n",
       "training[0].monte_carlo.colour: unknown key (expected name, count, seed, weight, file, "
       "set, "
       "vary, grid) (line 6)"},
      {mc + "      vary: {}\n",
       "training[0].monte_carlo.vary: needs at least 1 key, has 0 (line 6)"},
      {mc + "      vary:\n        grip.rear_muy: {uniform: [0.9, 1.1]}\n",
       "training[0].monte_carlo.vary.grip.rear_muy: unknown scenario key 'grip.rear_muy' (did you "
       "mean grip.rear_mu_y?) (line 7)"},
      {mc + "      vary:\n        seed: 5\n",
       "training[0].monte_carlo.vary.seed: expected a map {uniform, integer, choice, step}, got "
       "the integer 5 (line 7)"},
      {mc + "      vary:\n        seed: {uniform: [2, 1]}\n",
       "training[0].monte_carlo.vary.seed.uniform: must be [low, high] with finite numbers, low <= "
       "high (line 7)"},
      {mc + "      vary:\n        seed: {uniform: []}\n",
       "training[0].monte_carlo.vary.seed.uniform: must be [low, high] with finite numbers, low <= "
       "high (line 7)"},
      {mc + "      vary:\n        seed: {integer: [1.5, 3]}\n",
       "training[0].monte_carlo.vary.seed.integer: the bounds must be whole numbers (|n| <= 1e15) "
       "(line 7)"},
      {mc + "      vary:\n        seed: {choice: []}\n",
       "training[0].monte_carlo.vary.seed.choice: needs at least 1 value, has 0 (line 7)"},
      {mc + "      vary:\n        seed: {choice: [1], uniform: [1, 2]}\n",
       "training[0].monte_carlo.vary.seed: give exactly one of uniform, integer, choice (line 7)"},
      {mc + "      vary:\n        seed: {integer: [1, 2], step: 1}\n",
       "training[0].monte_carlo.vary.seed.step: only a uniform draw takes a step (line 7)"},
      {mc + "      vary:\n        gg_scale: {uniform: [1.0, 1.2], step: 0}\n",
       "training[0].monte_carlo.vary.gg_scale.step: must be a number > 0 (line 7)"},
      {mc + "      grid:\n        laps: []\n",
       "training[0].monte_carlo.grid.laps: needs at least 1 value, has 0 (line 7)"},
      {mc + "      grid:\n        lapz: [1, 2]\n",
       "training[0].monte_carlo.grid.lapz: unknown scenario key 'lapz' (did you mean laps?) (line "
       "7)"},
      {"training:\n  - monte_carlo:\n      name: mc\n      count: 100000\n      grid:\n"
       "        laps: [1, 2]\n",
       "training[0].monte_carlo: expands to more than 100000 scenarios (count × grid sizes) (line "
       "3)"},
      {"training:\n  - monte_carlo: {name: mc, count: 2}\nheld_out:\n  - {name: mc_001}\n",
       "held_out[0].name: 'mc_001' is already the name of scenario 1 of training[0].monte_carlo "
       "(line 4)"},
      {"training:\n  - {name: mc_001}\n  - monte_carlo: {name: mc, count: 3}\n",
       "training[1].monte_carlo.name: 'mc_001' (its scenario 1) is already the name of "
       "training[0] (line 3)"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.text);
    try {
      ScenarioSet::FromYamlText(c.text, "bad.yaml");
      ADD_FAILURE() << "accepted";
    } catch (const ConfigError& e) {
      ASSERT_FALSE(e.problems().empty());
      EXPECT_EQ(e.problems()[0].path + ": " + e.problems()[0].message, c.first_problem);
      EXPECT_EQ(std::string(e.what()).rfind("bad.yaml: ", 0), 0u) << e.what();
    }
  }
}

TEST(ScenarioSetTest, TwoBlocksOfOneNameAreOneProblem) {
  try {
    ScenarioSet::FromYamlText(
        "training:\n"
        "  - monte_carlo: {name: mc, count: 50}\n"
        "  - monte_carlo: {name: mc, count: 50}\n",
        "dup.yaml");
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    ASSERT_EQ(e.problems().size(), 1u) << e.what();
    EXPECT_EQ(e.problems()[0].message,
              "'mc_000' (its scenario 0) is already the name of scenario 0 of "
              "training[0].monte_carlo (and 49 more) (line 3)");
  }
}

TEST(ScenarioSetTest, DocsTableDescribesEntriesAndBlocks) {
  const std::string md = params::MarkdownTable<ScenarioSetFile>();
  for (const char* key :
       {"`name`", "`cost`", "`cost.sideslip_weight`", "`training`", "`training[].name`",
        "`training[].set`", "`training[].monte_carlo`", "`training[].monte_carlo.count`",
        "`training[].monte_carlo.vary`", "`training[].monte_carlo.vary.<key>.uniform`",
        "`training[].monte_carlo.grid`", "`held_out[].monte_carlo.vary.<key>.step`"})
    EXPECT_NE(md.find("| " + std::string(key) + " |"), std::string::npos) << key << "\n" << md;
  EXPECT_NE(md.find("| string[] | - | `[]` | >= 0 values; each: key=value |"), std::string::npos)
      << md;
}

TEST(ScenarioSetTest, DocsPageIsCurrent) {
  const std::string path = std::string(SCW_SOURCE_DIR) + "/docs/parameters-scenario-set.md";
  const std::string page = params::ReadTextFile(path);
  const std::string md = params::MarkdownTable<ScenarioSetFile>();
  EXPECT_NE(page.find(md), std::string::npos)
      << "regenerate with: scw params docs --kind scenario-set -o docs/parameters-scenario-set.md";
}

}  // namespace
}  // namespace scw::tuning
