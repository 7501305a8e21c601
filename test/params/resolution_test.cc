// Resolutions of tunable parameters (Meta::resolution, params/schema/field.h): every field the
// tuner may move has one, and values on its grid print as short decimals.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <type_traits>

#include "params/io/write.h"
#include "params/schema/field.h"
#include "params/schema/stability_params.h"
#include "params/schema/tracking_params.h"

namespace scw::params {
namespace {

template <class P>
void ExpectEveryTunableFieldHasAResolution() {
  int tunable = 0;
  const P defaults{};
  ForEachField(defaults, [&](const std::string& key, const auto& value, const Meta& m) {
    using T = std::decay_t<decltype(value)>;
    if (m.scale == Scale::kFixed) return;
    ++tunable;
    EXPECT_TRUE((std::is_same_v<T, double> || std::is_same_v<T, std::vector<double>>)) << key;
    EXPECT_GT(m.resolution, 0.0) << key << " is tunable but has no resolution";
    // A step the bounds can hold, and a grid whose values print as short decimals.
    if (std::isfinite(m.lo) && std::isfinite(m.hi)) {
      EXPECT_LT(m.resolution, m.hi - m.lo) << key;
    }
    EXPECT_LE(FormatDouble(ResolutionGridValue(7, m.resolution)).size(), 8u) << key;
  });
  EXPECT_GT(tunable, 5);
}

TEST(ResolutionTest, EveryTunableStabilityFieldHasAResolution) {
  ExpectEveryTunableFieldHasAResolution<StabilityParams>();
}

TEST(ResolutionTest, EveryTunableTrackingFieldHasAResolution) {
  ExpectEveryTunableFieldHasAResolution<TrackingParams>();
}

TEST(ResolutionTest, SchemaExamples) {
  auto resolution = [](const std::string& key) {
    double r = -1;
    const StabilityParams defaults;
    ForEachField(defaults, [&](const std::string& k, const auto&, const Meta& m) {
      if (k == key) r = m.resolution;
    });
    return r;
  };
  EXPECT_EQ(resolution("ESC.beta_threshold_deactivate"), 0.001);                   // rad
  EXPECT_EQ(resolution("SlipControl.ABS.front.slip_threshold_hold_reduce"), 0.1);  // % slip
  EXPECT_EQ(resolution("ESC.kd_psi_dot"), 0.001);
  EXPECT_EQ(resolution("tS"), 0.0);  // fixed: never tuned
}

TEST(ResolutionTest, RoundingGivesTheShortestDecimal) {
  EXPECT_EQ(FormatDouble(RoundToResolution(0.6000000000000002, 0.001)), "0.6");
  EXPECT_EQ(FormatDouble(RoundToResolution(0.30000000000000004, 0.1)), "0.3");
  EXPECT_EQ(FormatDouble(RoundToResolution(0.0174 * 1.3, 0.001)), "0.023");
  EXPECT_EQ(FormatDouble(RoundToResolution(-10.2749, 0.1)), "-10.3");
  EXPECT_EQ(FormatDouble(RoundToResolution(-0.04, 0.1)), "0.0");  // no -0.0
  EXPECT_EQ(FormatDouble(RoundToResolution(2512.4, 10.0)), "2510.0");
  EXPECT_EQ(FormatDouble(RoundToResolution(0.123456, 0.05)), "0.1");
  EXPECT_EQ(FormatDouble(RoundToResolution(0.0000412, 0.000001)), "4.1e-05");
  EXPECT_EQ(RoundToResolution(0.123456, 0.0), 0.123456);  // no resolution: unchanged
  // Every multiple of 0.001 up to 100 prints with at most three decimals.
  for (int n = -100000; n <= 100000; n += 7) {
    const std::string t = FormatDouble(ResolutionGridValue(n, 0.001));
    const auto dot = t.find('.');
    ASSERT_NE(dot, std::string::npos) << t;
    if (t.find('e') == std::string::npos) {
      EXPECT_LE(t.size() - dot - 1, 3u) << n << ": " << t;
    }
  }
}

}  // namespace
}  // namespace scw::params
