// What travels between the ranks of an MPI run arrives bit for bit: parameter sets through the
// schema visitor (tuning/sim/parallel/wire.h), run metrics as exact text (EncodeRunMetrics).
// Without a launcher the backend stays off (one rank, no remote task).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

#include "params/io/write.h"
#include "params/schema/stability_params.h"
#include "tuning/sim/metrics.h"
#include "tuning/sim/parallel/mpi_backend.h"
#include "tuning/sim/parallel/parallel_for.h"
#include "tuning/sim/parallel/wire.h"

namespace scw::tuning {
namespace {

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

params::StabilityParams OddSet() {
  params::StabilityParams p;
  p.ESC.kp_psi_dot = 0.1 + 0.2;  // not the double nearest 0.3
  p.ESC.ki_psi_dot = std::nextafter(1.0, 2.0);
  p.ESC.kd_psi_dot = std::numeric_limits<double>::denorm_min();
  p.ESC.threshold_velocities = {25.000000000000004, 50.0 + 1.0 / 3.0};
  p.ESC.enabled = false;
  p.SlipControl.ABS.operation_mode = 2;
  p.countersteer_system.steering_factor = -0.0;
  return p;
}

TEST(WireTest, ParameterSetsRoundTripBitForBit) {
  const params::StabilityParams sent = OddSet();
  WireWriter w;
  w.Params(sent);
  w.String("tail");
  params::StabilityParams got;  // defaults, overwritten field by field
  WireReader r(w.bytes());
  r.Params(&got);
  EXPECT_EQ(r.String(), "tail");
  EXPECT_TRUE(r.AtEnd());
  EXPECT_TRUE(params::DifferingKeys(sent, got).empty());
  EXPECT_TRUE(SameBits(got.ESC.kp_psi_dot, sent.ESC.kp_psi_dot));
  EXPECT_TRUE(SameBits(got.ESC.kd_psi_dot, sent.ESC.kd_psi_dot));
  EXPECT_TRUE(SameBits(got.countersteer_system.steering_factor, -0.0));
  EXPECT_EQ(got.ESC.threshold_velocities, sent.ESC.threshold_velocities);
  EXPECT_FALSE(got.ESC.enabled);
  EXPECT_EQ(got.SlipControl.ABS.operation_mode, 2);
  EXPECT_EQ(params::ToRosYaml(got, params::kStabilityNodeKey),
            params::ToRosYaml(sent, params::kStabilityNodeKey));
}

TEST(WireTest, TruncatedOrMalformedBytesThrow) {
  WireWriter w;
  w.Params(OddSet());
  const std::string bytes = w.bytes();
  params::StabilityParams got;
  WireReader cut(std::string_view(bytes).substr(0, bytes.size() - 3));
  EXPECT_THROW(cut.Params(&got), std::runtime_error);
  WireWriter lie;
  lie.Int(1000);  // a string length beyond the message
  lie.String("x");
  WireReader r(lie.bytes());
  EXPECT_THROW(r.String(), std::runtime_error);
}

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

TEST(MpiBackendTest, WithoutALauncherEverythingStaysInThisProcess) {
  // ctest starts this test without mpirun: MPI is never initialised.
  EXPECT_FALSE(mpi::Launched());
  EXPECT_EQ(mpi::Ranks(), 1);
  EXPECT_EQ(mpi::Rank(), 0);
  EXPECT_EQ(mpi::MaybeRemote(
                "evaluate", [] { return std::string(); }, 2),
            nullptr);
  const unsigned hw = std::thread::hardware_concurrency();
  EXPECT_EQ(ResolveThreads(0), hw == 0 ? 1 : static_cast<int>(hw));
}

}  // namespace
}  // namespace scw::tuning
