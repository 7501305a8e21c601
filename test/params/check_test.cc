#include <gtest/gtest.h>

#include <string>

#include "params/io/ros2_check.h"
#include "params/io/write.h"
#include "params/schema/stability_params.h"

namespace scw::params {
namespace {

CheckReport Check(const std::string& text, bool complete = true) {
  CheckOptions co;
  co.node_key = kStabilityNodeKey;
  co.expect_complete = complete;
  return CheckRosParamsText(text, DeclaredParams<StabilityParams>(), co);
}

std::string Overrides(const std::string& body) {
  return "/core/control/StabilityController:\n  ros__parameters:\n" + body;
}

bool Has(const CheckReport& r, bool error, const std::string& text) {
  for (const auto& f : r.findings)
    if (f.error == error && (f.key + ": " + f.message).find(text) != std::string::npos) return true;
  return false;
}

TEST(CheckTest, DefaultExportIsClean) {
  const auto r = Check(ToRosYaml(StabilityParams{}, kStabilityNodeKey));
  EXPECT_TRUE(r.findings.empty()) << r.Format("x");
}

TEST(CheckTest, RclTypingRules) {
  EXPECT_TRUE(Has(Check(Overrides("    ESC:\n      kp_psi_dot: 8\n"), false), true,
                  "declared as double but written as integer"));
  EXPECT_TRUE(Has(Check(Overrides("    ESC:\n      threshold_velocities: [25, 50.0]\n"), false),
                  true, "Sequence should be of same type"));
  EXPECT_TRUE(Has(Check(Overrides("    ESC:\n      threshold_velocities: []\n"), false), true,
                  "empty array"));
  EXPECT_TRUE(Has(Check(Overrides("    ESC:\n      enabled: \"true\"\n"), false), true,
                  "declared as bool but written as string"));
  // 010 is an (octal) integer literal for rcl: type-correct for an integer parameter.
  EXPECT_TRUE(
      Check(Overrides("    SlipControl:\n      ABS:\n        operation_mode: 010\n"), false).ok());
  EXPECT_TRUE(Has(Check(Overrides("    ESC:\n      kp_psi_dot:\n"), false), true, "no value"));
  EXPECT_TRUE(
      Has(Check(Overrides("    ESC:\n      kp_psi_dot: .inf\n"), false), true, "not finite"));
  // True/False/yes are booleans for rcl.
  EXPECT_TRUE(Check(Overrides("    ESC:\n      enabled: True\n"), false).ok());
}

TEST(CheckTest, StructureRules) {
  EXPECT_TRUE(Has(Check("/**:\n  ros__parameters:\n    tS: 0.01\n"), true, "wildcard"));
  EXPECT_TRUE(Has(Check(Overrides("    a: &x 1.0\n    b: *x\n"), false), true, "aliasing"));
  EXPECT_TRUE(
      Has(Check("/core/control/StabilityController:\n  tS: 0.01\n"), true, "ros__parameters"));
  EXPECT_TRUE(Has(Check(Overrides("    ESC: [1.0, 2.0\n"), false), true, "YAML syntax error"));
}

TEST(CheckTest, WarningsForDuplicatesUnknownAndMissing) {
  const auto r =
      Check(Overrides("    ESC:\n      kp_psi_dot: 8.0\n      kp_psi_dot: 9.0\n      kpp: 1.0\n"));
  EXPECT_TRUE(r.ok()) << r.Format("x");
  EXPECT_TRUE(
      Has(r, false, "ESC.kp_psi_dot: given 2 times; the ROS 2 parser keeps the last (9.0)"));
  EXPECT_TRUE(Has(r, false, "ESC.kpp: not declared by the node"));
  EXPECT_TRUE(Has(r, false, "ESC.kd_psi_dot: not set"));
  EXPECT_TRUE(
      Has(Check(Overrides("    vehicle:\n      dimension:\n        cog_height: 0.3\n"), false),
          false, "workspace key"));
}

}  // namespace
}  // namespace scw::params
