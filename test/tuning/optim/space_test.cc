#include "tuning/optim/space.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "params/io/write.h"
#include "params/io/yaml_doc.h"

namespace scw::tuning {
namespace {

using params::StabilityParams;

TEST(SpaceTest, DefaultSpaceFileEqualsBuiltIn) {
  const std::string path = std::string(SCW_SOURCE_DIR) + "/params/spaces/default.yaml";
  ASSERT_TRUE(std::filesystem::exists(path));
  const auto file = ParameterSpace::FromFile(path);
  EXPECT_EQ(file.ToYaml(), ParameterSpace::Default().ToYaml())
      << "regenerate with: scw tune --print-space > params/spaces/default.yaml";
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
  const auto space = ParameterSpace::Default();
  const StabilityParams base;
  const auto u = space.Encode(base);
  Problems pr;
  const auto back = space.Decode(u, base, &pr);
  EXPECT_TRUE(pr.empty());
  EXPECT_NEAR(back.ESC.kp_psi_dot, base.ESC.kp_psi_dot, 1e-9);
  EXPECT_NEAR(back.ESC.beta_threshold_activate[1], base.ESC.beta_threshold_activate[1], 1e-12);
  EXPECT_NEAR(back.SlipControl.ABS.rear.slip_threshold_hold_increase,
              base.SlipControl.ABS.rear.slip_threshold_hold_increase, 1e-9);
  EXPECT_NEAR(back.SlipControl.TC.rear.slip_threshold_safe,
              base.SlipControl.TC.rear.slip_threshold_safe, 1e-9);
  // Deactivation thresholds are fractions of the activation minimum; the shipped β pair has an
  // inverted hysteresis above 25 m/s (0.035 vs 0.0174), which the ratio bound 1.0 cannot express.
  EXPECT_LE(back.ESC.beta_threshold_deactivate, base.ESC.beta_threshold_deactivate);
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
  EXPECT_NEAR(p.ESC.kp_psi_dot, 10.0, 1e-12);
  EXPECT_EQ(p.ESC.threshold_velocities[1], 80.0);
  EXPECT_NEAR(p.ESC.beta_threshold_deactivate, 0.5 * 0.0174, 1e-15);
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
      {"parameters:\n  - {key: ESC.kp_psi_dot, lo: 1.0}\n", "parameters[0].hi"},
      {"parameters:\n  - {key: ESC.kp_beta, transform: ratio, lo: 0.1, hi: 1.0}\n", ".of"},
      {"parameters:\n  - {key: ESC.kp_beta, lo: a, hi: 1.0}\n", "finite number"},
      {"parameters: []\n", "non-empty list"},
      {"name: x\nparams: 1\n", "unknown key"},
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
