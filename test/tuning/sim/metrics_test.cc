// RunMetrics described once (issue 17 part 1): every member is listed in Visit exactly once with
// a unique key, the exact encoding between processes round-trips every member bit for bit, the
// renderings convert radians to degrees in one place, and the summaries use the schema's keys.
#include "tuning/sim/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <string>

#include "test/common/field_count.h"
#include "tuning/sim/run_summary.h"

namespace scw::tuning {
namespace {

/// Counts the Output calls and collects the keys.
struct Lister {
  int count = 0;
  std::set<std::string> keys;
  template <class T>
  void Output(const T&, const params::OutputMeta& meta) {
    ++count;
    keys.insert(std::string(meta.key));
  }
};

/// Gives every member a distinct, non-default value (doubles not exactly representable in
/// decimal, so that only an exact encoding round-trips them).
struct Filler {
  int k = 0;
  void Output(RunStatus& s, const params::OutputMeta&) { s = RunStatus::kWheelSpin; }
  void Output(int& x, const params::OutputMeta&) { x = 1000 + ++k; }
  void Output(double& x, const params::OutputMeta&) {
    ++k;
    x = k / 3.0 + 1e-9 * k;
  }
  void Output(std::vector<double>& xs, const params::OutputMeta&) {
    xs = {66.1 / 3.0, 65.9 / 7.0, 0.1};
  }
};

TEST(RunMetricsSchemaTest, VisitListsEveryMemberOnceWithAUniqueKey) {
  const RunMetrics m;
  Lister l;
  RunMetrics::Visit(m, l);
  // A member added to RunMetrics without a line in Visit makes these two differ.
  EXPECT_EQ(static_cast<std::size_t>(l.count), test::FieldCount<RunMetrics>());
  EXPECT_EQ(l.keys.size(), static_cast<std::size_t>(l.count)) << "keys must be unique";
  EXPECT_EQ(l.keys.count(std::string(kMeanLapTimeKey)), 0u);
  EXPECT_EQ(l.keys.count(std::string(kProgressKey)), 0u);
}

TEST(RunMetricsSchemaTest, ExactEncodingRoundTripsEveryMember) {
  RunMetrics m;
  Filler f;
  RunMetrics::Visit(m, f);
  const std::string text = EncodeRunMetrics(m);
  RunMetrics back;
  ASSERT_NE(DecodeRunMetrics(text.c_str(), &back), nullptr);
  EXPECT_EQ(EncodeRunMetrics(back), text);
  EXPECT_EQ(back.status, RunStatus::kWheelSpin);
  EXPECT_EQ(back.lap_times, m.lap_times);
  EXPECT_EQ(back.max_speed, m.max_speed);
  EXPECT_EQ(back.tc_count, m.tc_count);
  EXPECT_EQ(DecodeRunMetrics(" 3 -1", &back), nullptr);  // a negative number of laps
}

TEST(RunMetricsSchemaTest, RenderedValuesConvertRadiansToDegreesInOnePlace) {
  RunMetrics m;
  m.max_abs_sideslip = 0.1;
  m.max_abs_heading_error = -0.2;
  m.esc_count = 7;
  m.lap_times = {70.0, 72.0};
  EXPECT_EQ(RenderedMetric(m, "max_abs_sideslip_deg").real, 0.1 * 180.0 / M_PI);
  EXPECT_EQ(RenderedMetric(m, "max_abs_heading_error_deg").real, -0.2 * 180.0 / M_PI);
  const MetricValue c = RenderedMetric(m, "esc_count");
  EXPECT_TRUE(c.is_integer);
  EXPECT_EQ(c.integer, 7);
  EXPECT_EQ(RenderedMetric(m, kMeanLapTimeKey).real, 71.0);
  EXPECT_THROW(RenderedMetric(m, "max_abs_sideslip"), std::logic_error);
}

TEST(RunMetricsSchemaTest, YamlSummaryHasOneLinePerSummaryKey) {
  RunMetrics m;
  m.lap_times = {70.0};
  const std::string yaml = RunSummaryYaml("a", m);
  EXPECT_EQ(yaml.rfind("scenario: ", 0), 0u);
  for (std::string_view key : SummaryMetricKeys())
    EXPECT_NE(yaml.find("\n" + std::string(key) + ": "), std::string::npos) << key;
  EXPECT_EQ(yaml.find("laps_planned"), std::string::npos);  // bookkeeping, not in the summary
  EXPECT_NE(yaml.find("\nstatus: completed\n"), std::string::npos);
}

// What travels between processes (the execution layer, tuning/exec): the exact text of a run's
// metrics.
bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(WireTest, RunMetricsTextRoundTripsBitForBit) {
  RunMetrics m;
  m.status = RunStatus::kWheelLock;
  m.lap_times = {71.99600000000001, 1.0 / 3.0};
  m.laps_planned = 3;
  m.time = 143.99;
  m.distance = std::nextafter(5000.0, 0.0);
  m.distance_planned = 15000.0;
  m.end_s = -0.0;
  m.end_lap = 2;
  m.max_abs_sideslip = std::numeric_limits<double>::denorm_min();
  m.max_slip_front = 1e300;
  m.esc_count = 7;
  m.tc_count = -1;
  m.tc_throttle_cut = 0.1 + 0.2;
  m.max_speed = 83.33333333333333;
  const std::string text = EncodeRunMetrics(m);
  EXPECT_EQ(text.find('\n'), std::string::npos);
  RunMetrics got;
  const char* end = DecodeRunMetrics(text.c_str(), &got);
  ASSERT_NE(end, nullptr);
  EXPECT_EQ(*end, '\0');
  EXPECT_EQ(EncodeRunMetrics(got), text);
  EXPECT_EQ(got.status, m.status);
  EXPECT_EQ(got.lap_times, m.lap_times);
  EXPECT_TRUE(SameBits(got.end_s, -0.0));
  EXPECT_TRUE(SameBits(got.max_abs_sideslip, m.max_abs_sideslip));
  EXPECT_TRUE(SameBits(got.tc_throttle_cut, m.tc_throttle_cut));
  EXPECT_EQ(got.tc_count, -1);
  EXPECT_EQ(DecodeRunMetrics(" 99 0", &got), nullptr);   // no such status
  EXPECT_EQ(DecodeRunMetrics(" 0 1 x", &got), nullptr);  // not a number
}

}  // namespace
}  // namespace scw::tuning
