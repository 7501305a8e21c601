// What scw tune exports (issue 15): the tuner never changes what it did not tune. The search space
// decodes, the tuner runs and the files are rendered exactly as `scw tune` does (tuning/cli/
// cmd_tune.cc), with a synthetic objective instead of the closed loop; the end-to-end run of the
// program itself is in tune_cli_test.cc.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "params/io/load.h"
#include "params/io/ros2_check.h"
#include "params/io/write.h"
#include "params/io/yaml_doc.h"
#include "tuning/optim/comparison.h"
#include "tuning/optim/space.h"
#include "tuning/optim/tuner.h"

namespace scw::tuning {
namespace {

using params::StabilityParams;

StabilityParams ShippedFile(std::set<std::string>* present) {
  params::LoadReport rep;
  auto p = params::LoadRosFile<StabilityParams>(
      std::string(SCW_SOURCE_DIR) + "/params/stability/default.yaml", params::kStabilityNodeKey,
      &rep);
  *present = rep.present;
  return p;
}

TuneProvenance Provenance(const std::set<std::string>& changed) {
  TuneProvenance p;
  p.tool_version = "0.1.0";
  p.git_revision = "0123456789ab";
  p.run_folder = "scw-runs/tune-20260504-102107";
  p.date_utc = "2026-05-04T10:21:07Z";
  p.base = "params/stability/default.yaml";
  p.algorithm = "crs2+sbplx";
  p.seed = 1;
  p.evaluations = 1;
  p.stop_reason = "max_evals";
  p.space = "built-in default";
  p.dimensions = 30;
  p.grown = {"ESC.beta_threshold_deactivate: ..."};
  p.training_scenarios = 4;
  p.training_before = 412.25;
  p.training_after = 401.5;
  p.held_out_scenarios = 5;
  p.held_out_before = 530.125;
  p.held_out_after = 529.0;
  p.changed.assign(changed.begin(), changed.end());
  return p;
}

params::CheckReport Check(const std::string& text, bool complete) {
  params::CheckOptions co;
  co.node_key = params::kStabilityNodeKey;
  co.expect_complete = complete;
  return params::CheckRosParamsText(text, params::DeclaredParams<StabilityParams>(), co);
}

// Dotted keys an overrides file sets.
std::set<std::string> KeysOf(const std::string& text) {
  Problems pr;
  const params::YamlNode parsed = params::ParseYaml(text, "overrides.yaml");
  const auto doc = params::Flatten(parsed, params::Layout::kRos2, params::kStabilityNodeKey, &pr);
  EXPECT_TRUE(pr.empty());
  std::set<std::string> keys;
  for (const auto& e : doc.entries) keys.insert(e.key);
  return keys;
}

// A synthetic cost with its minimum away from the base, so that a longer run changes keys.
Evaluation Synthetic(const std::vector<double>& u) {
  double c = 0;
  for (std::size_t i = 0; i < u.size(); ++i) c += (u[i] - 0.3) * (u[i] - 0.3);
  return {c, "ok", {}};
}

TEST(TuneExportTest, OneEvaluationTuneExportsExactlyTheBaseSet) {
  std::set<std::string> present;
  const StabilityParams base = ShippedFile(&present);
  std::vector<std::string> grown;
  const auto space = ParameterSpace::Default().WithBase(base, BaseOutsideSpace::kGrow, &grown);
  EXPECT_EQ(grown.size(), 1u);  // the shipped ESC.beta_threshold_deactivate (see space_test.cc)
  TunerOptions o;
  o.max_evals = 1;
  const auto r = Tune(space.Encode(base), Synthetic, o);
  ASSERT_EQ(r.evals, 1);
  Problems pr;
  const StabilityParams tuned = space.Decode(r.best_u, base, &pr);
  ASSERT_TRUE(pr.empty());
  const std::set<std::string> changed = params::DifferingKeys(tuned, base);
  EXPECT_TRUE(changed.empty()) << *changed.begin();

  const std::string full = params::ToRosYaml(tuned, params::kStabilityNodeKey, present,
                                             TunedFileHeader(Provenance(changed), false));
  const std::string over = params::ToRosOverrides(tuned, base, params::kStabilityNodeKey,
                                                  TunedFileHeader(Provenance(changed), true));
  // The full file is the base file's content; the overrides file sets no key.
  EXPECT_EQ(full.substr(full.find(params::kStabilityNodeKey)),
            params::ToRosYaml(base, params::kStabilityNodeKey, present));
  EXPECT_TRUE(KeysOf(over).empty()) << over;
  EXPECT_NE(over.find("ros__parameters: {}"), std::string::npos) << over;
  EXPECT_NE(over.find("changed keys: none"), std::string::npos) << over;
  EXPECT_TRUE(Check(full, true).ok()) << Check(full, true).Format("full");
  EXPECT_TRUE(Check(over, false).ok()) << Check(over, false).Format("overrides");
  // And the shipped file itself: the full export is that file, value for value.
  const std::string shipped =
      params::ReadTextFile(std::string(SCW_SOURCE_DIR) + "/params/stability/default.yaml");
  EXPECT_EQ(params::DifferingKeys(
                params::LoadRosText<StabilityParams>(full, "full", params::kStabilityNodeKey),
                params::LoadRosText<StabilityParams>(shipped, "shipped", params::kStabilityNodeKey))
                .size(),
            0u);
}

TEST(TuneExportTest, OverridesListOnlyRealChangesRoundedAndTheHeaderKeepsTheCheckerHappy) {
  std::set<std::string> present;
  const StabilityParams base = ShippedFile(&present);
  const auto space = ParameterSpace::Default().WithBase(base, BaseOutsideSpace::kGrow);
  TunerOptions o;
  o.algorithm = "sbplx";
  o.max_evals = 40;
  o.seed = 5;
  const auto r = Tune(space.Encode(base), Synthetic, o);
  Problems pr;
  const StabilityParams tuned = space.Decode(r.best_u, base, &pr);
  ASSERT_TRUE(pr.empty());
  const std::set<std::string> changed = params::DifferingKeys(tuned, base);
  ASSERT_FALSE(changed.empty());
  std::set<std::string> space_keys;
  for (const auto& e : space.entries()) space_keys.insert(e.key);
  for (const auto& k : changed) EXPECT_TRUE(space_keys.count(k)) << k << " changed, not tuned";

  const std::string header = TunedFileHeader(Provenance(changed), true);
  const std::string over = params::ToRosOverrides(tuned, base, params::kStabilityNodeKey, header);
  const std::string full = params::ToRosYaml(tuned, params::kStabilityNodeKey, present,
                                             TunedFileHeader(Provenance(changed), false));
  EXPECT_EQ(KeysOf(over), changed);
  // Values at their resolution: short decimal texts, no round-trip noise.
  const params::YamlNode parsed = params::ParseYaml(over, "o");
  const auto doc = params::Flatten(parsed, params::Layout::kRos2, params::kStabilityNodeKey, &pr);
  for (const auto& e : doc.entries) {
    const std::string text = params::Render(*e.node);
    EXPECT_LE(text.size(), 24u) << e.key << ": " << text;  // arrays: two short elements
    EXPECT_EQ(text.find("0000"), std::string::npos) << e.key << ": " << text;
    EXPECT_EQ(text.find("9999"), std::string::npos) << e.key << ": " << text;
  }
  // The provenance header, then the node key.
  for (const std::string& text : {over, full}) {
    EXPECT_EQ(
        text.rfind("# Tuned by scw tune 0.1.0 (git 0123456789ab) on 2026-05-04T10:21:07Z\n", 0), 0u)
        << text;
    for (const char* item :
         {"# run folder: scw-runs/tune-20260504-102107", "# base: params/stability/default.yaml",
          "# search: crs2+sbplx, seed 1, 1 evaluation (stop: max_evals)",
          "#   training (4 scenarios): 412.250 -> 401.500",
          "#   held-out (5 scenarios, not used for tuning): 530.125 -> 529.000",
          "range grown to include the base"})
      EXPECT_NE(text.find(item), std::string::npos) << item << "\n" << text;
    EXPECT_EQ(text.find("\n/core/control/StabilityController:\n  ros__parameters:"),
              text.find("\n/core/control/StabilityController:"));
  }
  EXPECT_NE(over.find("--params-file base.yaml --params-file stability_overrides.yaml"),
            std::string::npos);
  // Still a file the car's node loads: the project's ROS 2 checker passes both.
  EXPECT_TRUE(Check(full, true).ok()) << Check(full, true).Format("full");
  EXPECT_TRUE(Check(over, false).ok()) << Check(over, false).Format("overrides");
  EXPECT_EQ(Check(full, true).warnings(),
            Check(params::ToRosYaml(base, params::kStabilityNodeKey, present), true).warnings());
  // The full file reads back as the tuned set, bit for bit.
  EXPECT_TRUE(
      params::DifferingKeys(
          params::LoadRosText<StabilityParams>(full, "full", params::kStabilityNodeKey), tuned)
          .empty());
}

}  // namespace
}  // namespace scw::tuning
