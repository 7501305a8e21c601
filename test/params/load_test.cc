#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "params/io/load.h"
#include "params/io/ros2_check.h"
#include "params/io/suggest.h"
#include "params/io/write.h"
#include "params/schema/stability_params.h"
#include "test/params/test_util.h"

namespace scw::params {
namespace {

std::string DefaultText() { return ToRosYaml(StabilityParams{}, kStabilityNodeKey); }

StabilityParams LoadStrict(const std::string& text) {
  return LoadRosText<StabilityParams>(text, "stability.yml", kStabilityNodeKey);
}

// Replaces the first occurrence of `from` (must exist) by `to`.
std::string Edit(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "test bug: '" << from << "' not in the default file";
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

TEST(LoadTest, DefaultsRoundTrip) {
  const StabilityParams p = LoadStrict(DefaultText());
  EXPECT_TRUE(DifferingKeys(p, StabilityParams{}).empty());
}

TEST(LoadTest, NestedNodeKeyAndMissingSlashAreAccepted) {
  std::string text = DefaultText();
  text = Edit(text, "/core/control/StabilityController:\n  ros__parameters:",
              "core/control:\n  StabilityController:\n   ros__parameters:");
  // Re-indent is not needed: the nested form above keeps the parameters under ros__parameters
  // deeper than the key, which YAML accepts.
  const StabilityParams p = LoadStrict(text);
  EXPECT_EQ(p.ESC.kp_psi_dot, 8.0);
}

TEST(LoadTest, PlainLayoutAcceptsIntegersForDoubles) {
  const std::string text = "tS: 0.01\nESC:\n  kp_psi_dot: 9\n";
  LoadOptions opt;
  opt.layout = Layout::kPlain;
  opt.int_for_double = true;
  // Required keys are missing here; the error must list them all, not just the first.
  try {
    LoadFromText<StabilityParams>(text, "plain.yaml", opt);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_GT(e.problems().size(), 50u);
    for (const auto& pr : e.problems()) EXPECT_NE(pr.path, "ESC.kp_psi_dot");
  }
}

struct BadCase {
  const char* name;
  std::string text;
  std::string key;   // expected in the message
  std::string rule;  // expected in the message
};

std::vector<BadCase> BadCases() {
  const std::string d = DefaultText();
  return {
      {"below_bound", Edit(d, "kp_psi_dot: 8.0", "kp_psi_dot: -1.0"), "ESC.kp_psi_dot",
       "-1 is below the lower bound 0"},
      {"above_bound", Edit(d, "slip_angle_filter_pole: 0.7", "slip_angle_filter_pole: 1.5"),
       "SlipControl.slip_angle_filter_pole", "above the upper bound"},
      {"unknown_key", Edit(d, "kp_psi_dot: 8.0", "kp_psi_dot: 8.0\n      kp_psi_dott: 1.0"),
       "ESC.kp_psi_dott", "unknown key"},
      {"duplicate_key", Edit(d, "kp_psi_dot: 8.0", "kp_psi_dot: 8.0\n      kp_psi_dot: 9.0"),
       "ESC.kp_psi_dot", "given 2 times"},
      {"int_for_double", Edit(d, "kp_psi_dot: 8.0", "kp_psi_dot: 8"), "ESC.kp_psi_dot",
       "expected a double, got the integer 8"},
      {"double_for_int", Edit(d, "operation_mode: 0", "operation_mode: 0.0"),
       "SlipControl.ABS.operation_mode", "expected an integer"},
      {"string_for_double", Edit(d, "kp_psi_dot: 8.0", "kp_psi_dot: fast"), "ESC.kp_psi_dot",
       "expected a number"},
      {"quoted_number", Edit(d, "kp_psi_dot: 8.0", "kp_psi_dot: \"8.0\""), "ESC.kp_psi_dot",
       "expected a number"},
      {"string_for_bool", Edit(d, "enabled: true", "enabled: maybe"), "enabled",
       "expected true or false"},
      {"nan", Edit(d, "kp_psi_dot: 8.0", "kp_psi_dot: .nan"), "ESC.kp_psi_dot", "not a finite"},
      {"inf", Edit(d, "kp_beta: 25.0", "kp_beta: .inf"), "ESC.kp_beta", "not a finite"},
      {"huge_number", Edit(d, "kp_beta: 25.0", "kp_beta: 1e400"), "ESC.kp_beta", "not a finite"},
      {"huge_integer",
       Edit(d, "moving_average_fx_window_length: 50",
            "moving_average_fx_window_length: 99999999999"),
       "moving_average_fx_window_length", "out of the integer range"},
      {"empty_array", Edit(d, "threshold_velocities: [25.0, 50.0]", "threshold_velocities: []"),
       "ESC.threshold_velocities", "empty list"},
      {"mixed_array",
       Edit(d, "threshold_velocities: [25.0, 50.0]", "threshold_velocities: [25, 50.0]"),
       "ESC.threshold_velocities", "mixes integer and double"},
      {"int_array", Edit(d, "threshold_velocities: [25.0, 50.0]", "threshold_velocities: [25, 50]"),
       "ESC.threshold_velocities", "list of integers"},
      {"unequal_arrays",
       Edit(d, "beta_threshold_activate: [0.035, 0.0174]",
            "beta_threshold_activate: [0.035, 0.0174, 0.01]"),
       "ESC.beta_threshold_activate", "same length as threshold_velocities"},
      {"short_array",
       Edit(Edit(Edit(Edit(d, "threshold_velocities: [25.0, 50.0]", "threshold_velocities: [25.0]"),
                      "beta_threshold_activate: [0.035, 0.0174]",
                      "beta_threshold_activate: [0.035]"),
                 "psi_dot_error_threshold_activate: [0.0401, 0.0349]",
                 "psi_dot_error_threshold_activate: [0.0401]"),
            "beta_error_threshold_activate: [0.061, 0.035]",
            "beta_error_threshold_activate: [0.061]"),
       "ESC.threshold_velocities", "at least 2"},
      {"not_ascending",
       Edit(d, "threshold_velocities: [25.0, 50.0]", "threshold_velocities: [50.0, 25.0]"),
       "ESC.threshold_velocities", "ascending"},
      {"scalar_for_array",
       Edit(d, "threshold_velocities: [25.0, 50.0]", "threshold_velocities: 25.0"),
       "ESC.threshold_velocities", "expected a list"},
      {"array_for_scalar", Edit(d, "kp_psi_dot: 8.0", "kp_psi_dot: [8.0]"), "ESC.kp_psi_dot",
       "expected a number"},
      {"map_for_scalar", Edit(d, "kp_psi_dot: 8.0", "kp_psi_dot:\n        a: 1.0"),
       "ESC.kp_psi_dot", "got a map"},
      {"missing_key", Edit(d, "      kp_psi_dot: 8.0\n", ""), "ESC.kp_psi_dot",
       "required key is missing"},
      {"empty_value", Edit(d, "kp_psi_dot: 8.0", "kp_psi_dot:"), "ESC.kp_psi_dot", "empty value"},
      {"wrong_node", Edit(d, "/core/control/StabilityController:", "/core/control/Other:"), "",
       "no `/core/control/StabilityController: ros__parameters:` section"},
      {"wildcard_node", Edit(d, "/core/control/StabilityController:", "/**:"), "", "wildcard"},
      {"truncated", d.substr(0, d.find("ESC:") + 4) + "\n  kp: [1.0, 2", "", "YAML syntax error"},
      {"tab_indent", Edit(d, "      kp_psi_dot: 8.0", "\tkp_psi_dot: 8.0"), "", "line"},
      {"alias",
       Edit(Edit(d, "kp_psi_dot: 8.0", "kp_psi_dot: &k 8.0"), "kp_beta: 25.0", "kp_beta: *k"), "",
       "anchor"},
      {"ordering", Edit(d, "slip_threshold_safe: -7.0", "slip_threshold_safe: -11.0"),
       "SlipControl.ABS.front.slip_threshold_hold_reduce", "must be <= slip_threshold_safe"},
      {"tc_ordering",
       Edit(d, "slip_threshold_hold_reduce: 8.0", "slip_threshold_hold_reduce: 10.0"),
       "SlipControl.TC.rear.slip_threshold_hold_reduce", "must be <="},
      {"empty_file", "", "", "empty"},
      {"top_level_list", "- 1.0\n- 2.0\n", "", "top level must be a map"},
      {"two_documents", d + "---\n" + d, "", "more than one YAML document"},
  };
}

TEST(LoadTest, BadFilesFailWithKeyAndRule) {
  const auto cases = BadCases();
  EXPECT_GE(cases.size(), 25u);
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    try {
      LoadStrict(c.text);
      ADD_FAILURE() << c.name << ": loaded without error";
    } catch (const ConfigError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("stability.yml: "), std::string::npos) << msg;
      if (!c.key.empty()) {
        EXPECT_NE(msg.find(c.key), std::string::npos) << msg;
      }
      EXPECT_NE(msg.find(c.rule), std::string::npos) << msg;
    } catch (const std::exception& e) {
      ADD_FAILURE() << c.name << ": wrong exception type: " << e.what();
    }
  }
}

TEST(LoadTest, EveryProblemIsListedAtOnce) {
  std::string t = DefaultText();
  t = Edit(t, "kp_psi_dot: 8.0", "kp_psi_dot: -1.0");
  t = Edit(t, "ki_psi_dot: 1.0", "ki_psi_dot: 1");
  t = Edit(t, "kd_psi_dot: 0.6", "kd_psi_dot: 0.6\n      bogus: 1.0");
  try {
    LoadStrict(t);
    FAIL();
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("ESC.ki_psi_dot"), std::string::npos) << msg;
    EXPECT_NE(msg.find("ESC.bogus"), std::string::npos) << msg;
  }
  // Bounds are checked once types are right; the bound problem is then reported with its line.
  std::string b = Edit(DefaultText(), "kp_psi_dot: 8.0", "kp_psi_dot: -1.0");
  b = Edit(b, "kp_beta: 25.0", "kp_beta: -2.0");
  try {
    LoadStrict(b);
    FAIL();
  } catch (const ConfigError& e) {
    ASSERT_EQ(e.problems().size(), 2u) << e.what();
    EXPECT_NE(std::string(e.what()).find("(line "), std::string::npos);
  }
}

TEST(LoadTest, ImportModeKeepsLastDuplicateAndReportsIt) {
  const std::string t = Edit(DefaultText(), "max_brake_pressure: 80.0",
                             "max_brake_pressure: 60.0\n      max_brake_pressure: 80.0");
  LoadOptions opt;
  opt.layout = Layout::kRos2;
  opt.node_key = kStabilityNodeKey;
  opt.lenient = true;
  LoadReport rep;
  const auto p = LoadFromText<StabilityParams>(t, "car.yml", opt, &rep);
  EXPECT_EQ(p.ESC.max_brake_pressure, 80.0);
  ASSERT_EQ(rep.notes.size(), 1u);
  EXPECT_NE(rep.notes[0].message.find("60.0"), std::string::npos);
  EXPECT_NE(rep.notes[0].message.find("uses the last one (80.0)"), std::string::npos);
}

TEST(LoadTest, OptionalKeysKeepDefaultsAndAreTracked) {
  const std::string t =
      Edit(DefaultText(), "    tS: 0.01\n", "    tS: 0.01\n    tire_stiffness_front: 150000.0\n");
  LoadReport rep;
  const auto p = LoadRosText<StabilityParams>(t, "stability.yml", kStabilityNodeKey, &rep);
  EXPECT_EQ(p.tire_stiffness_front, 150000.0);
  EXPECT_EQ(p.tire_stiffness_rear, 200000.0);
  EXPECT_TRUE(rep.present.count("tire_stiffness_front"));
  EXPECT_FALSE(rep.present.count("tire_stiffness_rear"));
  EXPECT_EQ(rep.present.size(), 86u);
}

}  // namespace
}  // namespace scw::params

namespace scw::params {
namespace {

// Full table (Levenshtein plus swaps of neighbours): the reference the bounded search in SuggestKey
// must agree with.
std::size_t FullEditDistance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min(
          {d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0u : 1u)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

std::string ReferenceSuggestion(const std::string& unknown, const std::vector<std::string>& known) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(3, unknown.size() / 5) + 1;
  for (const auto& k : known) {
    const std::size_t d = FullEditDistance(unknown, k);
    if (d < best_d) {
      best_d = d;
      best = k;
    }
  }
  if (!best.empty()) return best;
  // Else a key that is `unknown` plus "_word" (a unit suffix left off), the shortest such.
  for (const auto& k : known) {
    const std::string rest = k.rfind(unknown + "_", 0) == 0 ? k.substr(unknown.size() + 1) : "";
    if (!rest.empty() && rest.find_first_of("._") == std::string::npos &&
        (best.empty() || k.size() < best.size()))
      best = k;
  }
  return best;
}

TEST(LoadTest, KeySuggestionsEqualThoseOfTheFullEditDistance) {
  std::vector<std::string> known;
  for (const auto& d : DeclaredParams<StabilityParams>()) known.push_back(d.key);
  ASSERT_GT(known.size(), 50u);
  // Typos of every kind against every key, plus keys far from all of them.
  std::vector<std::string> probes = {"",
                                     "x",
                                     "ESC",
                                     "ESC.kp_psi_dott",
                                     "ESC.kp_psi_do",
                                     "SlipControl.ABS.front.slip_treshold",
                                     "zzzzzzzzzzzzzzzz",
                                     "tS",
                                     "ts",
                                     "vehicle.mass_",
                                     "countersteer"};
  for (const auto& k : known) {
    std::string drop = k, swap = k, sub = k;
    drop.erase(drop.size() / 2, 1);
    if (swap.size() > 3) std::swap(swap[1], swap[2]);
    sub[0] = sub[0] == 'q' ? 'r' : 'q';
    probes.insert(probes.end(), {drop, swap, sub, k + "xyz", "a." + k});
  }
  for (const auto& p : probes)
    EXPECT_EQ(detail::SuggestKey(p, known), ReferenceSuggestion(p, known)) << p;
  EXPECT_EQ(detail::SuggestKey("ESC.kp_psi_dott", known), "ESC.kp_psi_dot");
}

TEST(LoadTest, OnlyTheFirstUnknownKeysOfAFileGetHints) {
  std::string text = std::string(kStabilityNodeKey) + ":\n  ros__parameters:\n";
  for (int i = 0; i < detail::kMaxKeySuggestions + 4; ++i)
    text += "    ESC.kp_psi_dot" + std::string(1, static_cast<char>('a' + i)) + ": 1.0\n";
  try {
    (void)LoadRosText<StabilityParams>(text, "many.yaml", kStabilityNodeKey);
    FAIL() << "unknown keys accepted";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    std::size_t hints = 0, unknown = 0;
    for (auto p = msg.find("did you mean"); p != std::string::npos;
         p = msg.find("did you mean", p + 1))
      ++hints;
    for (auto p = msg.find("unknown key"); p != std::string::npos;
         p = msg.find("unknown key", p + 1))
      ++unknown;
    EXPECT_EQ(unknown, static_cast<std::size_t>(detail::kMaxKeySuggestions + 4)) << msg;
    EXPECT_EQ(hints, static_cast<std::size_t>(detail::kMaxKeySuggestions)) << msg;
  }
}

TEST(LoadTest, EditDistanceStopsAtItsLimitAndIsExactBelowIt) {
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3u);
  EXPECT_EQ(EditDistance("", "abc"), 3u);
  EXPECT_EQ(EditDistance("abc", "abc"), 0u);
  EXPECT_GE(EditDistance("kitten", "sitting", 2), 2u);
  EXPECT_EQ(EditDistance("kitten", "sitting", 4), 3u);
  EXPECT_EQ(EditDistance("tnue", "tune"), 1u);  // a swap of neighbours is one edit
  EXPECT_EQ(EditDistance("ca", "abc"), 3u);
  const std::string long_a(300, 'a'), long_b = std::string(299, 'a') + "b";
  EXPECT_EQ(EditDistance(long_a, long_b), 1u);  // beyond the stack rows
  EXPECT_EQ(ClosestWord("tnue", {"simulate", "tune", "sweep"}, 3), "tune");
  EXPECT_EQ(ClosestWord("xyz", {"simulate", "tune", "sweep"}, 3), "");
}

}  // namespace
}  // namespace scw::params
