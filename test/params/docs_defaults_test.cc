// Default values quoted in the prose documentation (README.md, docs/*.md, experiments/README.md)
// are the schema's (issue 27: the README said limit_fraction 0.6 while the code has 0.7). Every
// mention of the forms
//     default `key` VALUE          `key` (default VALUE ...)          `key` = VALUE
// whose key is a schema key (stability, tracking, scenario, vehicle, cost) is compared with the
// default of that key (VALUE may be in backticks). The generated tables (docs/parameters-*.md) are
// checked by their own test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "params/io/write.h"
#include "params/schema/cost_params.h"
#include "params/schema/scenario_params.h"
#include "params/schema/stability_params.h"
#include "params/schema/tracking_params.h"
#include "params/schema/vehicle_params.h"

namespace scw::params {
namespace {

namespace fs = std::filesystem;

// Schema key → rendered defaults (a key may be in more than one schema).
using Defaults = std::multimap<std::string, std::string>;

template <class P>
void Collect(Defaults* out) {
  const P p{};
  ForEachField(p, [&](const std::string& path, const auto& value, const Meta&) {
    out->emplace(path, detail::RenderValue(value));
  });
}

Defaults AllDefaults() {
  Defaults d;
  Collect<StabilityParams>(&d);
  Collect<TrackingParams>(&d);
  Collect<ScenarioParams>(&d);
  Collect<VehicleParams>(&d);
  Collect<CostWeights>(&d);
  return d;
}

bool SameValue(const std::string& doc, const std::string& schema) {
  if (doc == schema) return true;
  char* end_a = nullptr;
  char* end_b = nullptr;
  const double a = std::strtod(doc.c_str(), &end_a);
  const double b = std::strtod(schema.c_str(), &end_b);
  return end_a != doc.c_str() && *end_a == '\0' && end_b != schema.c_str() && *end_b == '\0' &&
         a == b;
}

struct Mention {
  std::string file, key, value;
  int line;
};

std::vector<Mention> Mentions(const fs::path& file) {
  static const std::regex forms[] = {
      std::regex(R"(default `([A-Za-z_][\w.]*)` `?([-+0-9.eE]+|true|false)`?( ?[A-Za-z%]+)?)"),
      std::regex(R"(`([A-Za-z_][\w.]*)` \(default `?([-+0-9.eE]+|true|false)`?( ?[A-Za-z%]+)?)"),
      std::regex(R"(`([A-Za-z_][\w.]*)` = `?([-+0-9.eE]+|true|false)`?( ?[A-Za-z%]+)?)"),
  };
  // A value with a unit other than the schema's SI one (`tS` = 10 ms) is not compared.
  static const std::set<std::string> units = {"ms",  "s", "m", "km", "bar", "Hz", "kHz", "deg",
                                              "rad", "%", "N", "kN", "kg",  "mm", "us"};
  std::vector<Mention> out;
  std::ifstream in(file);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n)
    for (const auto& re : forms)
      for (auto it = std::sregex_iterator(line.begin(), line.end(), re);
           it != std::sregex_iterator(); ++it) {
        std::string unit = (*it)[3];
        while (!unit.empty() && unit.front() == ' ') unit.erase(unit.begin());
        if (units.count(unit)) continue;
        std::string value = (*it)[2];
        while (!value.empty() && value.back() == '.') value.pop_back();  // end of a sentence
        out.push_back({file.filename().string(), (*it)[1], value, n});
      }
  return out;
}

TEST(DocsDefaultsTest, DefaultsQuotedInTheDocsAreTheSchemas) {
  const fs::path root = SCW_SOURCE_DIR;
  std::vector<fs::path> files = {root / "README.md", root / "experiments" / "README.md"};
  for (const auto& e : fs::directory_iterator(root / "docs"))
    if (e.path().extension() == ".md" && e.path().filename().string().rfind("parameters-", 0) != 0)
      files.push_back(e.path());
  const Defaults defaults = AllDefaults();
  int checked = 0;
  bool limit_fraction = false;
  for (const auto& f : files)
    for (const Mention& m : Mentions(f)) {
      const auto [lo, hi] = defaults.equal_range(m.key);
      if (lo == hi) continue;  // not a schema key (an option, a column, ...)
      ++checked;
      limit_fraction = limit_fraction || m.key == "limit_fraction";
      bool match = false;
      std::string known;
      for (auto it = lo; it != hi; ++it) {
        match = match || SameValue(m.value, it->second);
        known += (known.empty() ? "" : " or ") + it->second;
      }
      EXPECT_TRUE(match) << m.file << ":" << m.line << ": `" << m.key << "` is said to default to "
                         << m.value << ", the schema's default is " << known;
    }
  // The check must see the mentions it exists for.
  EXPECT_TRUE(limit_fraction) << "the docs no longer quote the default limit_fraction";
  EXPECT_GE(checked, 3);
}

// Issue 50 finding 19: the ratio ranges the prose quotes for the default search space
// (README.md said [0.3, 1] where params/spaces/default.yaml and `scw space show` have
// [0.3, 0.98]). Every "ratio range [a, b]" and "ratio in [a, b]" in README.md and docs/*.md is the
// range of the ratio entry named last before it (the key the sentence is about; any ratio entry
// when none is named before it), and every grown range "KEY: [a, b] ->" starts from KEY's range.
TEST(DocsDefaultsTest, RatioRangesQuotedInTheDocsAreTheDefaultSpaces) {
  const fs::path root = SCW_SOURCE_DIR;
  // Ratio entries of the space file: {key: K, transform: ratio, ..., lo: A, hi: B, ...}.
  std::map<std::string, std::pair<double, double>> ratio;
  {
    std::ifstream in(root / "params" / "spaces" / "default.yaml");
    const std::regex entry(
        R"(key: ([\w.\[\]]+), transform: ratio,.* lo: ([-0-9.eE]+), hi: ([-0-9.eE]+))");
    std::smatch m;
    for (std::string line; std::getline(in, line);)
      if (std::regex_search(line, m, entry)) ratio[m[1]] = {std::stod(m[2]), std::stod(m[3])};
  }
  ASSERT_GE(ratio.size(), 3u) << "no ratio entries read from params/spaces/default.yaml";
  std::vector<fs::path> files = {root / "README.md"};
  for (const auto& e : fs::directory_iterator(root / "docs"))
    if (e.path().extension() == ".md") files.push_back(e.path());
  // A key, a quoted range or a grown range, in the order they appear.
  const std::regex token(
      R"(([A-Za-z_][\w.]*): \[([-0-9.]+), ([-0-9.]+)\] ->|ratio (?:range|in) \[([-0-9.]+), ([-0-9.]+)\]|([A-Z][A-Za-z]*\.[\w.]+))");
  int checked = 0;
  for (const auto& f : files) {
    std::ifstream in(f);
    std::stringstream buffer;
    buffer << in.rdbuf();
    const std::string text = buffer.str();
    std::string last_key;  // the ratio entry named last
    for (auto it = std::sregex_iterator(text.begin(), text.end(), token);
         it != std::sregex_iterator(); ++it) {
      const std::smatch& m = *it;
      const auto line = 1 + std::count(text.begin(), text.begin() + m.position(0), '\n');
      if (m[1].matched) {  // a grown range
        const auto r = ratio.find(m[1]);
        if (r == ratio.end()) continue;
        ++checked;
        EXPECT_EQ(std::make_pair(std::stod(m[2]), std::stod(m[3])), r->second)
            << f.filename() << ":" << line << ": " << m[0];
        last_key = m[1];
      } else if (m[4].matched) {  // a quoted range
        const std::pair<double, double> quoted{std::stod(m[4]), std::stod(m[5])};
        ++checked;
        if (!last_key.empty()) {
          EXPECT_EQ(quoted, ratio[last_key])
              << f.filename() << ":" << line << ": " << m[0] << " (about " << last_key << ")";
          continue;
        }
        bool any = false;
        for (const auto& [key, r] : ratio) any = any || r == quoted;
        EXPECT_TRUE(any) << f.filename() << ":" << line << ": " << m[0]
                         << " is no ratio range of params/spaces/default.yaml";
      } else if (ratio.count(m[6])) {
        last_key = m[6];
      }
    }
  }
  EXPECT_GE(checked, 3) << "README.md and docs/*.md no longer quote the ratio range";
}

}  // namespace
}  // namespace scw::params
