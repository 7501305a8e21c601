#include "tuning/optim/space.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>

#include "params/io/stability_lint.h"
#include "params/io/write.h"
#include "params/io/yaml_doc.h"

namespace scw::tuning {
namespace {

using params::StabilityParams;

// Calls fn(key, text of a, text of b) for every field; the shortest round-trip text of a double
// is unique to its bits (also for -0.0), so equal texts mean bit-identical values.
template <class Fn>
void ForEachPair(const StabilityParams& a, const StabilityParams& b, Fn fn) {
  std::vector<std::pair<std::string, std::string>> ta, tb;
  params::ForEachField(a, [&](const std::string& k, const auto& v, const params::Meta&) {
    ta.emplace_back(k, params::detail::RenderValue(v));
  });
  params::ForEachField(b, [&](const std::string& k, const auto& v, const params::Meta&) {
    tb.emplace_back(k, params::detail::RenderValue(v));
  });
  ASSERT_EQ(ta.size(), tb.size());
  for (std::size_t i = 0; i < ta.size(); ++i) fn(ta[i].first, ta[i].second, tb[i].second);
}

void ExpectBitIdentical(const StabilityParams& a, const StabilityParams& b) {
  ForEachPair(a, b, [](const std::string& key, const std::string& x, const std::string& y) {
    EXPECT_EQ(x, y) << key;
  });
  // And the raw bits of every double, to be explicit.
  std::vector<double> da, db;
  auto collect = [](std::vector<double>& out) {
    return [&out](const std::string&, const auto& v, const params::Meta&) {
      using T = std::decay_t<decltype(v)>;
      if constexpr (std::is_same_v<T, double>) out.push_back(v);
      if constexpr (std::is_same_v<T, std::vector<double>>)
        out.insert(out.end(), v.begin(), v.end());
    };
  };
  params::ForEachField(a, collect(da));
  params::ForEachField(b, collect(db));
  ASSERT_EQ(da.size(), db.size());
  EXPECT_EQ(std::memcmp(da.data(), db.data(), da.size() * sizeof(double)), 0);
}

TEST(SpaceTest, DefaultSpaceIsTheShippedFile) {
  const std::string path = std::string(SCW_SOURCE_DIR) + "/params/spaces/default.yaml";
  ASSERT_TRUE(std::filesystem::exists(path));
  const std::string text = params::ReadTextFile(path);
  // The built-in space is the file (embedded at build time), and the file is in the form
  // `scw space print` writes.
  EXPECT_EQ(ParameterSpace::Default().ToYaml(), text) << "re-run cmake to re-embed " << path;
  EXPECT_EQ(ParameterSpace::FromFile(path).ToYaml(), text)
      << "normalise with: scw space print --space " << path;
  const auto space = ParameterSpace::Default();
  EXPECT_EQ(space.name(), "default");
  ASSERT_EQ(space.size(), 30);
  EXPECT_EQ(space.entries().front().Label(), "ESC.beta_threshold_activate");
  EXPECT_EQ(space.entries().front().transform, Transform::kScaleArray);
  EXPECT_EQ(space.entries().back().Label(), "SlipControl.TC.rear.slip_threshold_hold_increase");
  EXPECT_EQ(space.entries().back().of, "SlipControl.TC.rear.slip_threshold_increase_hold");
}

TEST(SpaceTest, FileFormOmitsDefaultTransformAndQuotesIndexedKeys) {
  const ParameterSpace s("s\x01", {{"ESC.threshold_velocities", 1, 20.0, 40.0,
                                    params::Scale::kLinear, Transform::kDirect, "", -1},
                                   {"ESC.kp_beta", -1, 1.0, 4.0, params::Scale::kLog,
                                    Transform::kOffset, "ESC.threshold_velocities", 0}});
  const std::string yaml =
      "name: \"s\\x01\"\n"
      "parameters:\n"
      "  - {key: \"ESC.threshold_velocities[1]\", lo: 20.0, hi: 40.0, scale: linear}\n"
      "  - {key: ESC.kp_beta, transform: offset, of: \"ESC.threshold_velocities[0]\", lo: 1.0, "
      "hi: 4.0, scale: log}\n";
  EXPECT_EQ(s.ToYaml(), yaml);
  const auto back = ParameterSpace::FromYamlText(yaml, "s.yaml");
  EXPECT_EQ(back.name(), "s\x01");
  EXPECT_EQ(back.ToYaml(), yaml);
  EXPECT_EQ(back.entries()[1].of_index, 0);
}

TEST(SpaceTest, EveryCornerOfTheCubeDecodesToAValidSet) {
  const auto space = ParameterSpace::Default();
  const StabilityParams base;
  // The corners (all 0, all 1) and a deterministic sweep of mixed points.
  for (int k = 0; k < 64; ++k) {
    std::vector<double> u(static_cast<std::size_t>(space.size()));
    for (std::size_t i = 0; i < u.size(); ++i)
      u[i] = k == 0 ? 0.0 : k == 1 ? 1.0 : static_cast<double>((k * 7 + i * 13) % 11) / 10.0;
    Problems pr;
    space.Decode(u, base, &pr);
    EXPECT_TRUE(pr.empty()) << k << ": "
                            << (pr.empty() ? "" : pr.items()[0].path + " " + pr.items()[0].message);
  }
}

TEST(SpaceTest, EncodeDecodeReproducesTheShippedSet) {
  const StabilityParams base;
  // The shipped β pair has an inverted hysteresis above 25 m/s (deactivation 0.035 vs activation
  // 0.0174): 2.01 × the activation minimum, outside the default ratio range [0.3, 1].
  const auto mismatches = ParameterSpace::Default().BaseMismatches(base);
  ASSERT_EQ(mismatches.size(), 1u);
  EXPECT_EQ(mismatches[0].label, "ESC.beta_threshold_deactivate");
  EXPECT_NEAR(mismatches[0].x_base, 0.035 / 0.0174, 1e-12);
  // Grown to include it, the space reproduces the shipped set bit for bit.
  std::vector<std::string> notes;
  const auto space = ParameterSpace::Default().WithBase(base, BaseOutsideSpace::kGrow, &notes);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("ESC.beta_threshold_deactivate"), std::string::npos) << notes[0];
  EXPECT_TRUE(space.BaseMismatches(base).empty());
  Problems pr;
  const auto back = space.Decode(space.Encode(base), base, &pr);
  EXPECT_TRUE(pr.empty());
  ExpectBitIdentical(back, base);
}

TEST(SpaceTest, EvaluationZeroDecodesToTheBaseBitForBitForAwkwardBases) {
  // Values whose transform round trip is not exact in floating point (a ratio x = v / ref decoded
  // as x · ref, log-scaled gains, offsets of non-representable decimals), and values outside the
  // default ranges (grown).
  std::vector<StabilityParams> bases(4);
  bases[1].ESC.kd_psi_dot = 0.6;
  bases[1].ESC.kp_psi_dot = 7.123456789;
  bases[1].ESC.beta_error_threshold_deactivate = 0.0123456789;
  bases[1].ESC.psi_dot_error_threshold_deactivate = 0.0301;
  bases[1].SlipControl.TC.rear.slip_threshold_reduce_hold = 8.3;
  bases[1].SlipControl.ABS.front.slip_threshold_safe = -7.7;
  bases[2].ESC.kp_psi_dot = 55.5;                                    // above the range [1, 40]
  bases[2].ESC.kp_beta = 2.2;                                        // below the range [3, 100]
  bases[2].countersteer_system.steering_factor = 1.73;               // above [0.3, 1.5]
  bases[2].SlipControl.TC.rear.slip_threshold_hold_increase = 30.1;  // offset 18.1 > 15
  bases[3].ESC.beta_threshold_activate = {0.0333333333, 0.0211111111};
  bases[3].ESC.beta_threshold_deactivate = 0.0299999999;
  bases[3].countersteer_system.enable_sideslip = 0.0011;  // below the log range [0.002, 0.05]
  for (std::size_t k = 0; k < bases.size(); ++k) {
    SCOPED_TRACE("base " + std::to_string(k));
    ASSERT_TRUE(params::Validate(bases[k]).empty());
    const auto space = ParameterSpace::Default().WithBase(bases[k], BaseOutsideSpace::kGrow);
    const auto u0 = space.Encode(bases[k]);
    for (double u : u0) EXPECT_TRUE(u >= 0.0 && u <= 1.0);
    Problems pr;
    ExpectBitIdentical(space.Decode(u0, bases[k], &pr), bases[k]);
    EXPECT_TRUE(pr.empty());
  }
}

TEST(SpaceTest, BaseOutsideARangeIsRefusedNamingTheKey) {
  StabilityParams base;
  base.ESC.kp_psi_dot = 55.5;
  try {
    ParameterSpace::Default().WithBase(base, BaseOutsideSpace::kRefuse);
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("ESC.kp_psi_dot: the base value 55.5 lies outside the range [1, 40]"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("ESC.beta_threshold_deactivate"), std::string::npos) << what;
    EXPECT_NE(what.find("widen the range to [0.3, 2.02]"), std::string::npos) << what;
  }
  // A base inside every range is accepted unchanged by kRefuse (0.017 = 0.977 × 0.0174, the
  // smallest β breakpoint: the shipped β schedule extrapolates to 0 below 90 m/s, so the ratio
  // refers to the smallest breakpoint).
  base = StabilityParams{};
  base.ESC.beta_threshold_deactivate = 0.017;
  const auto space = ParameterSpace::Default().WithBase(base, BaseOutsideSpace::kRefuse);
  EXPECT_EQ(space.ToYaml(), ParameterSpace::Default().ToYaml());
}

TEST(SpaceTest, BaseNoRangeCanRepresentIsRefusedEvenWhenGrowing) {
  // A ratio of a zero reference, and a log-scaled argument of 0.
  StabilityParams base;
  base.ESC.psi_dot_error_threshold_activate = {0.0, 0.0};
  base.ESC.ki_beta = 0.0;
  ASSERT_TRUE(params::Validate(base).empty());
  try {
    ParameterSpace::Default().WithBase(base, BaseOutsideSpace::kGrow);
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("ESC.psi_dot_error_threshold_deactivate"), std::string::npos) << what;
    EXPECT_NE(what.find("ESC.ki_beta"), std::string::npos) << what;
    EXPECT_NE(what.find("log scale needs a positive argument"), std::string::npos) << what;
  }
}

TEST(SpaceTest, KeysOutsideTheSpaceKeepTheBaseValuesBitForBit) {
  StabilityParams base;
  base.tS = 0.0123456789;
  base.ESC.max_brake_pressure = 80.123456789;
  base.tire_stiffness_front = 123456.789;
  base.SlipControl.ABS.front.reduce_step = 0.0381234567;
  base.SlipControl.TC.slip_filter_pole = 0.81234567;
  base.brake_bias_shift.values = {-0.1011111, -0.0475555, 0.0};
  const auto space = ParameterSpace::Default().WithBase(base, BaseOutsideSpace::kGrow);
  std::set<std::string> tuned_keys;
  for (const auto& e : space.entries()) tuned_keys.insert(e.key);
  for (double level : {0.0, 0.23, 0.5, 0.77, 1.0}) {
    const std::vector<double> u(static_cast<std::size_t>(space.size()), level);
    const auto p = space.Decode(u, base, nullptr);
    ForEachPair(p, base, [&](const std::string& key, const std::string& a, const std::string& b) {
      if (!tuned_keys.count(key)) {
        EXPECT_EQ(a, b) << key << " at u = " << level;
      }
    });
  }
}

TEST(SpaceTest, TunedValuesAreRoundedToTheirResolution) {
  const auto space = ParameterSpace::Default().WithBase(StabilityParams{}, BaseOutsideSpace::kGrow);
  const StabilityParams base;
  std::map<std::string, double> resolution;
  params::ForEachField(base, [&](const std::string& key, const auto&, const params::Meta& m) {
    resolution[key] = m.resolution;
  });
  int changed = 0;
  for (int k = 0; k < 40; ++k) {
    std::vector<double> u(static_cast<std::size_t>(space.size()));
    for (std::size_t i = 0; i < u.size(); ++i)
      u[i] = static_cast<double>((k * 17 + i * 29) % 97) / 96.0;
    const auto p = space.Decode(u, base, nullptr);
    auto check = [&](const std::string& key, double v, double b) {
      if (v == b) return;
      ++changed;
      const double r = resolution.at(key);
      ASSERT_GT(r, 0.0) << key;
      EXPECT_EQ(v, params::RoundToResolution(v, r)) << key << " = " << v;
      EXPECT_GE(std::abs(v - b), r * (1 - 1e-9)) << key << ": a change below one step";
      EXPECT_LE(params::FormatNumber(v).size(), 9u) << key << " = " << params::FormatNumber(v);
    };
    params::ForEachField(p, [&](const std::string& key, const auto& value, const params::Meta&) {
      using T = std::decay_t<decltype(value)>;
      if constexpr (std::is_same_v<T, double>) {
        double b = 0;
        params::ForEachField(base, [&](const std::string& k2, const auto& v2, const params::Meta&) {
          if constexpr (std::is_same_v<std::decay_t<decltype(v2)>, double>)
            if (k2 == key) b = v2;
        });
        check(key, value, b);
      }
    });
  }
  EXPECT_GT(changed, 100);
}

TEST(SpaceTest, AValueWithinOneStepOfTheBaseIsTheBase) {
  // kd_psi_dot: base 0.6, resolution 0.001, log scale on [0.05, 3].
  const ParameterSpace s(
      "t", {{"ESC.kd_psi_dot", -1, 0.05, 3.0, params::Scale::kLog, Transform::kDirect, "", -1}});
  const StabilityParams base;
  auto at = [&](double x) {
    const double u = std::log(x / 0.05) / std::log(3.0 / 0.05);
    return s.Decode({u}, base, nullptr).ESC.kd_psi_dot;
  };
  EXPECT_EQ(at(0.6000000000000002), 0.6);
  EXPECT_EQ(at(0.6004), 0.6);
  EXPECT_EQ(at(0.5991), 0.6);
  EXPECT_EQ(at(0.6011), 0.601);
  EXPECT_EQ(at(0.6016), 0.602);
  EXPECT_EQ(at(0.71234), 0.712);
  EXPECT_EQ(params::FormatDouble(at(0.71234)), "0.712");
}

TEST(SpaceTest, RoundingKeepsTheOrderingsOfOffsetsAndRatios) {
  // A base off the 0.1 % grid: rounding the dependent thresholds to the grid must not cross their
  // references (ABS: hold_increase <= increase_hold <= reduce_hold <= hold_reduce <= safe < 0).
  StabilityParams base;
  base.SlipControl.ABS.front.slip_threshold_hold_reduce = -10.03;
  base.SlipControl.ABS.front.slip_threshold_safe = -7.01;
  const auto space = ParameterSpace::Default().WithBase(base, BaseOutsideSpace::kGrow);
  for (int k = 0; k < 200; ++k) {
    std::vector<double> u = space.Encode(base);
    for (std::size_t i = 0; i < u.size(); ++i)
      if ((k + i) % 3 == 0) u[i] = static_cast<double>((k * 31 + i * 7) % 101) / 100.0;
    Problems pr;
    space.Decode(u, base, &pr);
    EXPECT_TRUE(pr.empty()) << k << ": "
                            << (pr.empty() ? "" : pr.items()[0].path + " " + pr.items()[0].message);
  }
}

TEST(SpaceTest, LogScaleAndTransforms) {
  std::vector<SpaceEntry> e = {
      {"ESC.kp_psi_dot", -1, 1.0, 100.0, params::Scale::kLog, Transform::kDirect, "", -1},
      {"ESC.threshold_velocities", 1, 40.0, 80.0, params::Scale::kLinear, Transform::kDirect, "",
       -1},
      {"ESC.beta_threshold_deactivate", -1, 0.5, 1.0, params::Scale::kLinear, Transform::kRatio,
       "ESC.beta_threshold_activate", -1}};
  const ParameterSpace s("t", e);
  const auto p = s.Decode({0.5, 1.0, 0.0}, StabilityParams{}, nullptr);
  EXPECT_EQ(p.ESC.kp_psi_dot, 10.0);
  EXPECT_EQ(p.ESC.threshold_velocities[1], 80.0);
  // The ratio refers to the smallest activation threshold the car interpolates up to 90 m/s:
  // with the breakpoints at 25 and 80 m/s that is 0.0142 at 90 m/s; 0.5 × 0.0142 = 0.0071 is
  // rounded to the resolution 0.001 rad, to 0.008 because 0.007 would leave the range [0.5, 1].
  EXPECT_EQ(p.ESC.beta_threshold_deactivate, 0.008);
}

// A pinned entry keeps its base value whatever u says; where its reference moved so far that the
// base value would break the ordering, it takes the nearest value that keeps it.
TEST(SpaceTest, APinnedEntryKeepsItsBaseValueAndItsOrdering) {
  const StabilityParams base;
  const double hr = base.SlipControl.ABS.rear.slip_threshold_hold_reduce;
  const double rh = base.SlipControl.ABS.rear.slip_threshold_reduce_hold;
  const ParameterSpace s("t", {{"SlipControl.ABS.rear.slip_threshold_hold_reduce", -1, -20.0, -4.0,
                                params::Scale::kLinear, Transform::kDirect, "", -1},
                               {"SlipControl.ABS.rear.slip_threshold_reduce_hold", -1, -8.0, 0.0,
                                params::Scale::kLinear, Transform::kOffset,
                                "SlipControl.ABS.rear.slip_threshold_hold_reduce", -1}});
  const ParameterSpace pinned = s.WithPinned({1});
  int feasible = 0;
  EXPECT_FALSE(s.entries()[1].pinned);
  EXPECT_TRUE(pinned.entries()[1].pinned);
  for (double u0 : {0.0, 0.25, 0.5, 0.75, 1.0})
    for (double u1 : {0.0, 0.5, 1.0}) {
      Problems pr;
      const StabilityParams p = pinned.Decode({u0, u1}, base, &pr);
      if (!pr.empty()) continue;  // an ordering with keys outside this small space
      ++feasible;
      const double new_hr = p.SlipControl.ABS.rear.slip_threshold_hold_reduce;
      const double got = p.SlipControl.ABS.rear.slip_threshold_reduce_hold;
      if (rh - new_hr >= -8.0 && rh - new_hr <= 0.0)
        EXPECT_EQ(got, rh) << u0 << " " << u1;  // the base value, bit for bit
      else
        EXPECT_NEAR(got, new_hr + std::clamp(rh - new_hr, -8.0, 0.0), 0.1) << u0;
      EXPECT_LE(got - new_hr, 1e-12);  // the ordering holds
      EXPECT_GE(got - new_hr, -8.0 - 1e-12);
    }
  EXPECT_GE(feasible, 5);
  // With the reference at its base, the pinned entry is the base whatever its u.
  EXPECT_EQ(pinned.Decode({pinned.Encode(base)[0], 0.0}, base, nullptr)
                .SlipControl.ABS.rear.slip_threshold_reduce_hold,
            rh);
  (void)hr;
}

TEST(SpaceTest, RatiosOfAScheduleReferToTheSmallestValueTheCarInterpolates) {
  const StabilityParams shipped;
  // ψ̇ error: 0.0401 at 25 m/s, 0.0349 at 50 m/s, extended linearly to 0.02658 at 90 m/s.
  EXPECT_NEAR(params::ScheduledMinimum(shipped, "ESC.psi_dot_error_threshold_activate"), 0.02658,
              1e-12);
  // β reaches 0 before 90 m/s: no positive minimum, the ratio falls back to the smallest element.
  EXPECT_TRUE(std::isnan(params::ScheduledMinimum(shipped, "ESC.beta_threshold_activate")));
  EXPECT_TRUE(std::isnan(params::ScheduledMinimum(shipped, "ESC.kp_psi_dot")));
  // The deactivation threshold at the top of its ratio range stays below the activation
  // threshold at every speed: no inverted hysteresis, which the smallest breakpoint allowed.
  const ParameterSpace s(
      "t", {{"ESC.psi_dot_error_threshold_deactivate", -1, 0.3, 0.98, params::Scale::kLinear,
             Transform::kRatio, "ESC.psi_dot_error_threshold_activate", -1}});
  const auto p = s.Decode({1.0}, shipped, nullptr);
  EXPECT_LT(p.ESC.psi_dot_error_threshold_deactivate, 0.02658);
  for (const auto& w : params::LintStability(p))
    EXPECT_NE(w.path, "ESC.psi_dot_error_threshold_deactivate") << w.message;
}

TEST(SpaceTest, BadSpacesAreRejectedWithPathAndRule) {
  struct Case {
    const char* text;
    const char* expect;
  } cases[] = {
      {"parameters:\n  - {key: ESC.nope, lo: 0.0, hi: 1.0}\n", "not a double"},
      {"parameters:\n  - {key: ESC.kp_psi_dot, lo: 5.0, hi: 1.0}\n", "lo must be below hi"},
      {"parameters:\n  - {key: ESC.kp_psi_dot, lo: 0.0, hi: 1.0, scale: log}\n", "lo > 0"},
      {"parameters:\n  - {key: ESC.kp_psi_dot, lo: -5.0, hi: 1.0}\n", "within the schema bounds"},
      {"parameters:\n  - {key: ESC.threshold_velocities, lo: 1.0, hi: 2.0}\n", "element index"},
      {"parameters:\n  - {key: ESC.kp_psi_dot, lo: 1.0}\n",
       "parameters[0].hi: required key is missing (line 2)"},
      {"parameters:\n  - {key: ESC.kp_beta, transform: ratio, lo: 0.1, hi: 1.0}\n", ".of"},
      {"parameters:\n  - {key: ESC.kp_beta, lo: a, hi: 1.0}\n",
       "parameters[0].lo: expected a number (double), got the string a (line 2)"},
      {"parameters:\n  - {key: ESC.kp_beta, lo: .inf, hi: 1.0}\n", "not a finite number"},
      {"parameters: []\n", "parameters: needs at least 1 entry, has 0"},
      {"name: x\nparams: 1\n", "params: unknown key"},
      {"name: x\nparamters: 1\n", "paramters: unknown key (did you mean parameters?)"},
      {"parameters:\n  - {key: ESC.kp_beta, lo: 1.0, hi: 2.0, scale: lg}\n",
       "parameters[0].scale: 'lg' is not one of linear|log (line 2)"},
      {"parameters:\n  - {key: ESC.kp_beta, lo: 1.0, hi: 2.0, transform: shift}\n",
       "parameters[0].transform: 'shift' is not one of direct|offset|ratio|scale_array"},
      {"parameters:\n  - {key: ESC.kp_beta, lo: 1.0, hi: 2.0, tranform: ratio}\n",
       "parameters[0].tranform: unknown key (did you mean transform?) (line 2)"},
      {"parameters:\n  - {key: ESC.kp_beta, lo: 1.0, hi: 2.0}\n  - [ESC.kp_psi_dot]\n",
       "parameters[1]: expected a map {key, transform, of, lo, hi, scale}"},
      {"parameters:\n  - {key: \"ESC.threshold_velocities[a]\", lo: 1.0, hi: 2.0}\n",
       "parameters[0].key: bad element index in 'ESC.threshold_velocities[a]'"},
      {"parameters:\n  - {key: ESC.kp_beta, lo: 1.0, hi: 2.0, hi: 3.0}\n",
       "parameters[0].hi: given 2 times"},
      {"parameters:\n  - {key: \"ESC.threshold_velocities[9]\", transform: offset, of: "
       "ESC.kp_beta, lo: 0.0, hi: 8.0}\n",
       "parameters[0].key: element index out of range"},
      {"parameters:\n  - {key: ESC.kp_beta, lo: 1.0, hi: 2.0}\n  - {key: ESC.kp_beta, lo: 1.0, "
       "hi: 2.0}\n",
       "tuned twice"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.text);
    try {
      ParameterSpace::FromYamlText(c.text, "space.yaml");
      ADD_FAILURE() << "accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(c.expect), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("space.yaml"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace scw::tuning
