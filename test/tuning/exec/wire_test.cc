// What travels between the processes of the execution layer arrives bit for bit: parameter sets
// through the schema visitor (tuning/exec/wire.h); run metrics as exact text: metrics_test.cc in
// test/tuning/sim. Without a launcher the MPI back end stays off (one rank, no remote task).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

#include "params/io/write.h"
#include "params/schema/stability_params.h"
#include "tuning/exec/mpi_backend.h"
#include "tuning/exec/parallel_for.h"
#include "tuning/exec/wire.h"

namespace scw::tuning::exec {
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
}  // namespace scw::tuning::exec
