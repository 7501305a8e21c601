// The list verb of the schema (v.List): a list of maps, each entry a struct with its own Visit.
// Loader, validator, writer and docs table all derive from the one description below.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "params/io/docs.h"
#include "params/io/load.h"
#include "params/io/write.h"
#include "params/schema/field.h"

namespace scw::params {
namespace {

struct Gain {
  std::string key;
  std::string mode = "fixed";
  double lo = 0.0;
  double hi = 1.0;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.key, {.key = "key", .doc = "Which gain."});
    v.Field(s.mode, {.key = "mode",
                     .doc = "fixed or free.",
                     .optional = true,
                     .choices = "fixed|free",
                     .omit_default = true});
    v.Field(s.lo, {.key = "lo", .lo = -10.0, .hi = 10.0, .doc = "Lower end."});
    v.Field(s.hi, {.key = "hi", .lo = -10.0, .hi = 10.0, .doc = "Upper end."});
  }
  static void CrossCheck(const Gain& g, Problems& pr) {
    if (!(g.lo < g.hi)) pr.Add("hi", "must be above lo");
  }
};

struct Table {
  std::string name = "table";
  std::vector<Gain> gains;
  std::vector<Gain> extras;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.name, {.key = "name", .optional = true});
    v.List(s.gains, {.key = "gains", .doc = "The gains.", .min_size = 1});
    v.List(s.extras, {.key = "extras", .doc = "More.", .optional = true, .min_size = 0});
  }
};

Table Load(const std::string& text) { return LoadPlainText<Table>(text, "table.yaml"); }

// Every problem of one load, as "path: message".
std::vector<std::string> Problems(const std::string& text) {
  try {
    Load(text);
  } catch (const ConfigError& e) {
    std::vector<std::string> out;
    for (const auto& p : e.problems()) out.push_back(p.path + ": " + p.message);
    return out;
  }
  return {};
}

TEST(ListTest, LoadsFlowAndBlockEntriesAndKeepsDefaults) {
  const Table t = Load(
      "gains:\n"
      "  - {key: a, lo: 1, hi: 2.5}\n"
      "  - key: b\n"
      "    mode: free\n"
      "    lo: -1.0\n"
      "    hi: 0.0\n");
  EXPECT_EQ(t.name, "table");
  ASSERT_EQ(t.gains.size(), 2u);
  EXPECT_EQ(t.gains[0].key, "a");
  EXPECT_EQ(t.gains[0].mode, "fixed");
  EXPECT_EQ(t.gains[0].lo, 1.0);
  EXPECT_EQ(t.gains[0].hi, 2.5);
  EXPECT_EQ(t.gains[1].mode, "free");
  EXPECT_EQ(t.gains[1].lo, -1.0);
  EXPECT_TRUE(t.extras.empty());
}

TEST(ListTest, EveryStructuralProblemIsListedWithItsPathAndLine) {
  const auto pr = Problems(
      "gains:\n"
      "  - 5\n"
      "  - {key: a, lo: 1.0}\n"
      "  - {key: b, lo: x, hi: 1.0, mdoe: free}\n"
      "  - {key: c, lo: 0.0, hi: 1.0, hi: 2.0}\n"
      "extras: {key: d}\n");
  const std::vector<std::string> expect = {
      "gains[0]: expected a map {key, mode, lo, hi}, got the integer 5 (line 2)",
      "gains[1].hi: required key is missing (line 3)",
      "gains[2].lo: expected a number (double), got the string x (line 4)",
      "gains[2].mdoe: unknown key (did you mean mode?) (line 4)",
      "gains[3].hi: given 2 times (line 5: 1.0, line 5: 2.0); the car's node uses the last one "
      "(2.0); give each key once",
      "extras: expected a list of maps, got a map (line 6)",
  };
  EXPECT_EQ(pr, expect);
}

TEST(ListTest, RulesOfEachEntryNameTheEntry) {
  const auto pr = Problems(
      "gains:\n"
      "  - {key: a, lo: -20.0, hi: 1.0}\n"
      "  - {key: b, mode: loose, lo: 2.0, hi: 1.0}\n");
  const std::vector<std::string> expect = {
      "gains[0].lo: -20 is below the lower bound -10 (line 2)",
      "gains[1].mode: 'loose' is not one of fixed|free (line 3)",
      "gains[1].hi: must be above lo (line 3)",
  };
  EXPECT_EQ(pr, expect);
  EXPECT_EQ(Problems("gains: []\n"),
            std::vector<std::string>{"gains: needs at least 1 entry, has 0 (line 1)"});
  EXPECT_EQ(Problems("name: x\n"), std::vector<std::string>{"gains: required key is missing"});
  const auto empty = Problems("gains:\n");
  ASSERT_EQ(empty.size(), 1u);
  EXPECT_EQ(
      empty[0].rfind("gains: expected a list of maps {key, mode, lo, hi}, got an empty value", 0),
      0u)
      << empty[0];
}

TEST(ListTest, ValidateNamesTheEntry) {
  Table t;
  t.gains = {{"a", "fixed", 0.0, 1.0}, {"b", "fixed", 0.0, 11.0}};
  const auto pr = Validate(t);
  ASSERT_EQ(pr.size(), 1u);
  EXPECT_EQ(pr.items()[0].path, "gains[1].hi");
}

TEST(ListTest, WritesOneFlowMapPerEntryAndReadsItBack) {
  Table t;
  t.name = "t";
  t.gains = {{"a", "fixed", 1.0, 2.0}, {"b[1]", "free", -0.5, 1e-05}, {"null", "fixed", 0, 3}};
  const std::string yaml = ToPlainYaml(t);
  EXPECT_EQ(yaml,
            "name: \"t\"\n"
            "gains:\n"
            "  - {key: a, lo: 1.0, hi: 2.0}\n"
            "  - {key: \"b[1]\", mode: free, lo: -0.5, hi: 1e-05}\n"
            "  - {key: \"null\", lo: 0.0, hi: 3.0}\n"
            "extras: []\n");
  const Table back = Load(yaml);
  EXPECT_EQ(ToPlainYaml(back), yaml);
  EXPECT_EQ(back.gains[1].key, "b[1]");
  EXPECT_EQ(back.gains[2].key, "null");
}

TEST(ListTest, DocsTableHasOneRowPerEntryField) {
  const std::string md = MarkdownTable<Table>();
  EXPECT_NE(md.find("| `gains` | list | - | `[]` | >= 1 entry | fixed | yes | The gains. |"),
            std::string::npos)
      << md;
  EXPECT_NE(
      md.find("| `gains[].mode` | string | - | `\"fixed\"` |  | fixed | no | fixed or free. |"),
      std::string::npos)
      << md;
  EXPECT_NE(md.find("| `gains[].lo` | double | - | `0.0` | [-10, 10] | fixed | yes | Lower end. |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| `extras` | list | - | `[]` | >= 0 entries | fixed | no | More. |"),
            std::string::npos)
      << md;
}

}  // namespace
}  // namespace scw::params
