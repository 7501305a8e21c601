#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "params/io/atomic_file.h"
#include "params/io/load.h"
#include "params/io/ros2_check.h"
#include "params/io/write.h"
#include "params/schema/stability_params.h"
#include "params/schema/tracking_params.h"
#include "test/params/test_util.h"

namespace scw::params {
namespace {

LoadOptions CarImport() {
  LoadOptions opt;
  opt.layout = Layout::kRos2;
  opt.node_key = kStabilityNodeKey;
  opt.lenient = true;
  return opt;
}

// Every (dotted key → literal text) of a ROS 2 params file, read with the rcl-rule tree.
std::map<std::string, std::string> Literals(const std::string& text) {
  Problems pr;
  const YamlNode root = ParseYaml(text, "x");
  const FlatDoc doc = Flatten(root, Layout::kRos2, kStabilityNodeKey, &pr);
  std::map<std::string, std::string> out;
  for (const auto& e : doc.entries) out[e.key] = Render(*e.node);
  return out;
}

TEST(ExportTest, FormatDoubleAlwaysReadsBackAsDouble) {
  EXPECT_EQ(FormatDouble(8.0), "8.0");
  EXPECT_EQ(FormatDouble(-2500.0), "-2500.0");
  EXPECT_EQ(FormatDouble(0.038), "0.038");
  EXPECT_EQ(FormatDouble(4e-05), "4e-05");
  EXPECT_EQ(FormatDouble(1e20), "1e+20");
  EXPECT_EQ(FormatDouble(-0.0), "-0.0");
  for (double x : {0.1, 1.0 / 3.0, 12.5e6, 1e-300, 2.0e15}) {
    const std::string s = FormatDouble(x);
    EXPECT_EQ(ClassifyScalar(s, false), ScalarType::kDouble) << s;
    double back = 0;
    ASSERT_TRUE(ParseDouble(s, &back));
    EXPECT_EQ(back, x);
  }
}

TEST(ExportTest, ReferenceFileRoundTrip) {
  const std::string ref =
      scw::test::SharedData("reference-configs/stability_controller_config.yml");
  if (ref.empty()) GTEST_SKIP() << "../shared/data not present";
  LoadReport rep;
  const auto imported = LoadFromFile<StabilityParams>(ref, CarImport(), &rep);
  EXPECT_EQ(imported.ESC.max_brake_pressure, 80.0);  // the node keeps the last duplicate

  const std::string exported = ToRosYaml(imported, kStabilityNodeKey, rep.present);
  const auto reloaded = LoadRosText<StabilityParams>(exported, "exported.yml", kStabilityNodeKey);
  EXPECT_TRUE(DifferingKeys(imported, reloaded).empty());

  // Same key set as the reference file (85 unique keys), same literal types for every key.
  const auto ref_lit = Literals(ReadTextFile(ref));
  const auto out_lit = Literals(exported);
  EXPECT_EQ(ref_lit.size(), 85u);
  std::set<std::string> ref_keys, out_keys;
  for (const auto& [k, v] : ref_lit) ref_keys.insert(k);
  for (const auto& [k, v] : out_lit) out_keys.insert(k);
  EXPECT_EQ(ref_keys, out_keys);
  for (const auto& [k, v] : ref_lit) {
    SCOPED_TRACE(k);
    const auto& w = out_lit.at(k);
    if (v.front() == '[') continue;
    bool b;
    if (ParseBool(v, &b)) {
      EXPECT_EQ(w, b ? "true" : "false");
      continue;
    }
    EXPECT_EQ(ClassifyScalar(v, false), ClassifyScalar(w, false)) << v << " vs " << w;
  }
  EXPECT_EQ(out_lit.at("SlipControl.ABS.operation_mode"), "0");
  EXPECT_EQ(out_lit.at("SlipControl.ABS.moving_average_fx_window_length"), "50");
  EXPECT_EQ(out_lit.at("ESC.kp_psi_dot"), "8.0");
  EXPECT_EQ(out_lit.at("ESC.threshold_velocities"), "[25.0, 50.0]");
  EXPECT_EQ(out_lit.at("brake_bias_shift.values"), "[-0.101, -0.0475, 0.0]");
  // Each key once: no duplicates in the export.
  EXPECT_EQ(exported.find("max_brake_pressure: 60.0"), std::string::npos);

  CheckOptions co;
  co.node_key = kStabilityNodeKey;
  const auto check = CheckRosParamsText(exported, DeclaredParams<StabilityParams>(), co);
  EXPECT_EQ(check.findings.size(), 0u) << check.Format("exported.yml");
}

TEST(ExportTest, OverridesOnlyHoldsExactlyTheChangedKeys) {
  StabilityParams base, tuned;
  tuned.ESC.kp_psi_dot = 9.5;
  tuned.ESC.beta_threshold_activate = {0.04, 0.02};
  tuned.tire_stiffness_rear = 180000.0;
  const std::string text = ToRosOverrides(tuned, base, kStabilityNodeKey);
  const auto lit = Literals(text);
  ASSERT_EQ(lit.size(), 3u) << text;
  EXPECT_EQ(lit.at("ESC.kp_psi_dot"), "9.5");
  EXPECT_EQ(lit.at("ESC.beta_threshold_activate"), "[0.04, 0.02]");
  EXPECT_EQ(lit.at("tire_stiffness_rear"), "180000.0");
  CheckOptions co;
  co.node_key = kStabilityNodeKey;
  co.expect_complete = false;
  EXPECT_TRUE(CheckRosParamsText(text, DeclaredParams<StabilityParams>(), co).ok());
  // Nothing changed: still a loadable file.
  EXPECT_TRUE(CheckRosParamsText(ToRosOverrides(base, base, kStabilityNodeKey),
                                 DeclaredParams<StabilityParams>(), co)
                  .ok());
}

TEST(ExportTest, NodeKeyIsConfigurable) {
  const std::string text = ToRosYaml(StabilityParams{}, "/car2/control/StabilityController");
  EXPECT_EQ(text.rfind("/car2/control/StabilityController:\n  ros__parameters:\n", 0), 0u);
  const auto p = LoadRosText<StabilityParams>(text, "x.yml", "/car2/control/StabilityController");
  EXPECT_EQ(p.tS, 0.01);
}

TEST(ExportTest, TrackingParamsRoundTrip) {
  TrackingParams t;
  t.velocity_p_gain = 2.5;
  const std::string text = ToRosYaml(t, kTrackingNodeKey);
  const auto back = LoadRosText<TrackingParams>(text, "tracking.yml", kTrackingNodeKey);
  EXPECT_EQ(back.velocity_p_gain, 2.5);
  EXPECT_EQ(Literals(text).size(), 0u);  // wrong node for Literals(): nothing found
  const std::string ref = scw::test::SharedData("reference-configs/tracking_controller_config.yml");
  if (ref.empty()) GTEST_SKIP() << "../shared/data not present";
  const auto car = LoadRosFile<TrackingParams>(ref, kTrackingNodeKey);
  EXPECT_EQ(car.curvature_lookahead_gain, 0.00004);
}

TEST(ExportTest, AtomicWriteLeavesNoPartialFile) {
  const auto dir = std::filesystem::temp_directory_path() / "scw_atomic_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "out.yml").string();
  io::WriteFileAtomic(path, "first\n");
  io::WriteFileAtomic(path, "second\n");
  EXPECT_EQ(ReadTextFile(path), "second\n");
  // A folder that does not exist: error names the path, nothing is left behind.
  const std::string bad = (dir / "missing" / "out.yml").string();
  try {
    io::WriteFileAtomic(bad, "x");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos);
  }
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 1);
  std::filesystem::remove_all(dir);
}

TEST(ExportTest, GeneratedDocsExist) {
  for (const char* kind :
       {"tracking", "scenario", "vehicle", "track", "cost", "scenario-set", "space"}) {
    const std::string path = scw::test::SourcePath(std::string("docs/parameters-") + kind + ".md");
    EXPECT_TRUE(std::filesystem::exists(path))
        << path << ": regenerate with scw params docs --kind " << kind << " -o " << path;
  }
}

TEST(ExportTest, DocsTableIsUpToDate) {
  // docs/parameters-stability.md is generated: `scw params docs -o docs/parameters-stability.md`.
  const std::string path = scw::test::SourcePath("docs/parameters-stability.md");
  ASSERT_TRUE(std::filesystem::exists(path));
  const std::string text = ReadTextFile(path);
  const StabilityParams defaults;
  ForEachField(defaults, [&](const std::string& key, const auto&, const Meta&) {
    EXPECT_NE(text.find("`" + key + "`"), std::string::npos)
        << key << " missing: regenerate with scw params docs -o docs/parameters-stability.md";
  });
}

}  // namespace
}  // namespace scw::params
