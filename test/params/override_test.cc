#include "params/io/override.h"

#include <gtest/gtest.h>

#include "params/schema/stability_params.h"

namespace scw::params {
namespace {

TEST(OverrideTest, AppliesTypedValues) {
  StabilityParams p;
  ApplyOverrides(p, {"ESC.kp_psi_dot=12", "SlipControl.ABS.operation_mode=1", "ESC.enabled=false",
                     "ESC.threshold_velocities=[20.0, 60.0]"});
  EXPECT_EQ(p.ESC.kp_psi_dot, 12.0);
  EXPECT_EQ(p.SlipControl.ABS.operation_mode, 1);
  EXPECT_FALSE(p.ESC.enabled);
  EXPECT_EQ(p.ESC.threshold_velocities, (std::vector<double>{20.0, 60.0}));
}

TEST(OverrideTest, ReportsEveryBadOverride) {
  StabilityParams p;
  try {
    ApplyOverrides(p, {"ESC.kp_psi_dott=1", "ESC.kp_beta=fast", "noequals",
                       "SlipControl.ABS.operation_mode=1.5"});
    FAIL();
  } catch (const ConfigError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("ESC.kp_psi_dott: unknown key (did you mean ESC.kp_psi_dot?)"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("ESC.kp_beta: expected a number"), std::string::npos) << m;
    EXPECT_NE(m.find("noequals: an override must look like key=value"), std::string::npos) << m;
    EXPECT_NE(m.find("operation_mode: expected an integer"), std::string::npos) << m;
  }
}

TEST(OverrideTest, ValidatesTheResult) {
  StabilityParams p;
  EXPECT_THROW(ApplyOverrides(p, {"ESC.kp_psi_dot=-3"}), ConfigError);
}

}  // namespace
}  // namespace scw::params
