// The schema verbs beyond fields and lists of structs (params/schema/field.h): lists of texts with
// a per-element rule, 64-bit integers, std::optional members and groups, variant list entries
// (a struct or a single-key block), and ordered maps whose keys are data. Loader, validator,
// writer and docs table all derive from the one description below.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "params/io/docs.h"
#include "params/io/load.h"
#include "params/io/write.h"
#include "params/schema/field.h"

namespace scw::params {
namespace {

std::string CheckTag(const std::string& t) {
  return t.find(':') == std::string::npos ? "must look like kind:value, got '" + t + "'" : "";
}
constexpr TextRule kTagRule{"kind:value", &CheckTag};

std::string CheckLowerCase(const std::string& k) {
  for (char c : k)
    if (c >= 'A' && c <= 'Z') return "'" + k + "' must be lower case";
  return "";
}
constexpr TextRule kLowerCase{"lower case", &CheckLowerCase};

struct Draw {
  std::optional<std::vector<double>> range;
  std::optional<std::vector<std::string>> pick;
  std::optional<double> step;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.range, {.key = "range", .doc = "[low, high].", .min_size = 0});
    v.Field(s.pick, {.key = "pick", .doc = "Values."});
    v.Field(s.step, {.key = "step", .lo = 0.0, .doc = "Rounding."});
  }
  static void CrossCheck(const Draw& d, Problems& pr) {
    if (d.range.has_value() == d.pick.has_value()) pr.Add("", "give exactly one of range, pick");
  }
};

struct Item {
  std::string name;
  std::vector<std::string> tags;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.name, {.key = "name", .doc = "Name.", .rule = kNotEmpty});
    v.Field(s.tags,
            {.key = "tags", .doc = "Tags.", .optional = true, .min_size = 0, .rule = kTagRule});
  }
};

struct Block {
  static constexpr Meta kBlock{.key = "many", .doc = "Many items at once."};
  std::string name;
  std::int64_t seed = 1;
  std::optional<OrderedMap<Draw>> draws;
  std::optional<OrderedMap<std::vector<std::string>>> axes;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.name, {.key = "name", .doc = "Prefix.", .rule = kNotEmpty});
    v.Field(s.seed, {.key = "seed", .lo = 0, .doc = "Seed.", .optional = true});
    v.Map(s.draws, {.key = "draws", .doc = "Draw per key.", .rule = kLowerCase});
    v.Map(s.axes, {.key = "axes", .doc = "Values per key.", .rule = kLowerCase});
  }
};

struct Costs {
  double a = 1.0;
  double b = 2.0;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.a, {.key = "a", .lo = 0.0, .doc = "A."});
    v.Field(s.b, {.key = "b", .lo = 0.0, .doc = "B.", .optional = true});
  }
};

using Entry = std::variant<Item, Block>;

struct Doc {
  std::string title = "doc";
  std::optional<Costs> costs;
  std::vector<Entry> items;
  std::optional<std::vector<Entry>> extra;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.title, {.key = "title", .optional = true});
    v.Nested("costs", s.costs);
    v.List(s.items, {.key = "items", .doc = "The items."});
    v.List(s.extra, {.key = "extra", .doc = "More items."});
  }
};

Doc Load(const std::string& text) { return LoadPlainText<Doc>(text, "doc.yaml"); }

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

TEST(VerbsTest, LoadsEveryVerb) {
  const Doc d = Load(
      "costs: {a: 3}\n"
      "items:\n"
      "  - {name: x, tags: [\"a:1\", b:2]}\n"
      "  - many:\n"
      "      name: m\n"
      "      seed: 5000000000\n"
      "      draws:\n"
      "        z.first: {range: [0, 1], step: 0.5}\n"
      "        a.second: {pick: [p, \"q r\"]}\n"
      "      axes: {k: [1.0, 2]}\n"
      "  - name: y\n");
  ASSERT_TRUE(d.costs.has_value());
  EXPECT_EQ(d.costs->a, 3.0);
  EXPECT_EQ(d.costs->b, 2.0);
  EXPECT_FALSE(d.extra.has_value());
  ASSERT_EQ(d.items.size(), 3u);
  const Item& x = std::get<Item>(d.items[0]);
  EXPECT_EQ(x.tags, (std::vector<std::string>{"a:1", "b:2"}));
  const Block& m = std::get<Block>(d.items[1]);
  EXPECT_EQ(m.seed, 5000000000);
  // The map keeps the written order and keys with dots whole.
  ASSERT_TRUE(m.draws.has_value());
  ASSERT_EQ(m.draws->size(), 2u);
  EXPECT_EQ((*m.draws)[0].first, "z.first");
  EXPECT_EQ((*m.draws)[0].second.range, (std::vector<double>{0.0, 1.0}));
  EXPECT_EQ((*m.draws)[0].second.step, 0.5);
  EXPECT_FALSE((*m.draws)[0].second.pick.has_value());
  EXPECT_EQ((*m.draws)[1].first, "a.second");
  EXPECT_EQ((*m.draws)[1].second.pick, (std::vector<std::string>{"p", "q r"}));
  ASSERT_TRUE(m.axes.has_value());
  EXPECT_EQ((*m.axes)[0].second, (std::vector<std::string>{"1.0", "2"}));  // verbatim
  EXPECT_EQ(std::get<Item>(d.items[2]).name, "y");
  EXPECT_TRUE(std::get<Item>(d.items[2]).tags.empty());
  // Absent optional members stay absent, an absent group keeps nothing.
  const Doc plain = Load("items: [{name: a}]\n");
  EXPECT_FALSE(plain.costs.has_value());
}

TEST(VerbsTest, StructuralProblemsNameTheKeyPathAndLine) {
  const auto pr = Problems(
      "costs: 5\n"
      "items:\n"
      "  - {name: x, tags: [{a: 1}]}\n"
      "  - many: {name: m, draws: {k: 5}, axes: {k: x}}\n"
      "  - {many: {name: n}, name: y}\n"
      "  - many: 7\n"
      "  - {name: z, tags: a}\n"
      "  - many: {name: o, draws: {k: {range: [0, 1]}, k: {pick: [a]}}, seeds: 1}\n"
      "extra: {name: q}\n");
  const std::vector<std::string> expect = {
      "costs: expected a map, got the integer 5 (line 1)",
      "items[0].tags: element [0]: expected a text value, got a map (line 3)",
      "items[1].many.draws.k: expected a map {range, pick, step}, got the integer 5 (line 4)",
      "items[1].many.axes.k: expected a list like [a, b], got the string x (line 4)",
      "items[2].name: unknown key: a many entry has no other keys (line 5)",
      "items[3].many: expected a map {name, seed, draws, axes}, got the integer 7 (line 6)",
      "items[4].tags: expected a list like [a, b], got the string a (line 7)",
      "items[5].many.draws.k: given twice (line 8 repeats a key given above); give each key once",
      "items[5].many.seeds: unknown key (did you mean seed?) (line 8)",
      "extra: expected a list of maps, got a map (line 9)",
  };
  EXPECT_EQ(pr, expect);
}

TEST(VerbsTest, RulesNameTheKeyPathAndLine) {
  const auto pr = Problems(
      "costs: {b: 1.0}\n"
      "items:\n"
      "  - {name: \"\", tags: [\"a:1\", nocolon]}\n"
      "  - many:\n"
      "      name: m\n"
      "      seed: -1\n"
      "      draws:\n"
      "        Upper: {range: [0, 1]}\n"
      "        both: {range: [0, 1], pick: [a], step: -1}\n"
      "        none: {pick: []}\n"
      "      axes: {}\n"
      "extra: []\n");
  // A present group is complete (costs.a), checked before the rules.
  ASSERT_EQ(pr, std::vector<std::string>{"costs.a: required key is missing (line 1)"});
  const auto rules = Problems(
      "items:\n"
      "  - {name: \"\", tags: [\"a:1\", nocolon]}\n"
      "  - many:\n"
      "      name: m\n"
      "      seed: -1\n"
      "      draws:\n"
      "        Upper: {range: [0, 1]}\n"
      "        both: {range: [0, 1], pick: [a], step: -1}\n"
      "        none: {pick: []}\n"
      "      axes: {}\n"
      "extra: []\n");
  const std::vector<std::string> expect = {
      "items[0].name: must not be empty (line 2)",
      "items[0].tags[1]: must look like kind:value, got 'nocolon' (line 2)",
      "items[1].many.seed: -1 is below the lower bound 0 (line 5)",
      "items[1].many.draws.Upper: 'Upper' must be lower case (line 7)",
      "items[1].many.draws.both.step: -1 is below the lower bound 0 (line 8)",
      "items[1].many.draws.both: give exactly one of range, pick (line 8)",
      "items[1].many.draws.none.pick: needs at least 1 value, has 0 (line 9)",
      "items[1].many.axes: needs at least 1 key, has 0 (line 10)",
      "extra: needs at least 1 entry, has 0 (line 11)",
  };
  EXPECT_EQ(rules, expect);
}

TEST(VerbsTest, ValidateNamesTheEntryOfProgrammaticValues) {
  Doc d;
  Block b;
  b.name = "m";
  b.axes.emplace();
  b.axes->push_back({"k", {}});
  b.axes->push_back({"k", {"1"}});
  d.items = {Item{"a", {"x"}}, b};
  std::vector<std::string> pr;
  const auto problems = Validate(d);
  for (const auto& p : problems.items()) pr.push_back(p.path + ": " + p.message);
  const std::vector<std::string> expect = {
      "items[0].tags[0]: must look like kind:value, got 'x'",
      "items[1].many.axes.k: needs at least 1 value, has 0",
      "items[1].many.axes.k: given twice; give each key once",
  };
  EXPECT_EQ(pr, expect);
}

TEST(VerbsTest, WritesFlowCollectionsAndReadsThemBack) {
  Doc d;
  d.title = "t";
  d.costs = Costs{};
  Block b;
  b.name = "m";
  b.seed = 5000000000;
  b.draws.emplace();
  b.draws->push_back({"z.first", Draw{std::vector<double>{0, 1}, std::nullopt, 0.5}});
  b.draws->push_back({"a", Draw{std::nullopt, std::vector<std::string>{"p", "q r"}, std::nullopt}});
  d.items = {Item{"x", {"a:1", "b:2"}}, b};
  d.extra = std::vector<Entry>{Item{"y", {}}};
  const std::string yaml = ToPlainYaml(d);
  EXPECT_EQ(yaml,
            "title: \"t\"\n"
            "costs:\n"
            "  a: 1.0\n"
            "  b: 2.0\n"
            "items:\n"
            "  - {name: x, tags: [\"a:1\", \"b:2\"]}\n"
            "  - {many: {name: m, seed: 5000000000, draws: {z.first: {range: [0.0, 1.0], step: "
            "0.5}, a: {pick: [p, \"q r\"]}}}}\n"
            "extra:\n"
            "  - {name: y, tags: []}\n");
  const Doc back = Load(yaml);
  EXPECT_EQ(ToPlainYaml(back), yaml);
  // Texts outside flow maps: quoted, or plain where they read back unchanged.
  EXPECT_EQ(ToPlainYaml(back, "", TextStyle::kPlainWhereSafe).substr(0, 9), "title: t\n");
  // Absent optional members are left out.
  Doc bare;
  bare.items = {Item{"x", {}}};
  EXPECT_EQ(ToPlainYaml(bare), "title: \"doc\"\nitems:\n  - {name: x, tags: []}\n");
}

TEST(VerbsTest, DocsTableHasRowsForEveryVerb) {
  const std::string md = MarkdownTable<Doc>();
  for (const char* row : {
           "| `costs` | map | - | — |  | fixed | no |",
           "| `costs.a` | double | - | `1.0` | >= 0 | fixed | yes | A. |",
           "| `items` | list | - | `[]` | >= 1 entry | fixed | yes | The items. |",
           "| `items[].name` | string | - | `\"\"` | not empty | fixed | yes | Name. |",
           "| `items[].tags` | string[] | - | `[]` | >= 0 values; each: kind:value | fixed | no | "
           "Tags. |",
           "| `items[].many` | map | - |  |  | fixed | no | An entry written as a single-key map "
           "{many: {...}}. Many items at once. |",
           "| `items[].many.seed` | int64 | - | `1` | >= 0 | fixed | no | Seed. |",
           "| `items[].many.draws` | map | - | — | >= 1 key; keys: lower case | fixed | no | Draw "
           "per key. |",
           "| `items[].many.draws.<key>.range` | double[] | - | — |  | fixed | no | [low, high]. |",
           "| `items[].many.axes` | map of string[] | - | — | >= 1 key; keys: lower case; each >= "
           "1 "
           "value | fixed | no | Values per key. |",
           "| `extra` | list | - | — | >= 1 entry | fixed | no | More items. |",
       })
    EXPECT_NE(md.find(row), std::string::npos) << row << "\n" << md;
}

}  // namespace
}  // namespace scw::params
