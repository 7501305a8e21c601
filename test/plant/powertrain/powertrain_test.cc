// Engine map, gearbox state machine (one row per edge), gear request vs engaged gear, LSD.
#include <gtest/gtest.h>

#include <cmath>

#include "params/schema/vehicle_params.h"
#include "plant/powertrain/differential.h"
#include "plant/powertrain/engine.h"
#include "plant/powertrain/gearbox.h"
#include "plant/vehicle/maneuver.h"
#include "plant/vehicle/vehicle.h"

namespace scw::plant {
namespace {

TEST(EngineMap, ReproducesBreakpointsAndInterpolates) {
  const params::EngineParams p;
  const EngineMap e(p);
  const std::size_t cols = p.map_throttle.size();
  for (std::size_t r = 0; r < p.map_speed_rpm.size(); ++r)
    for (std::size_t c = 0; c < cols; ++c) {
      const double w = RpmToRadPerSec(p.map_speed_rpm[r]);
      if (w > RpmToRadPerSec(p.rev_limit_rpm)) continue;
      EXPECT_NEAR(e.Torque(w, p.map_throttle[c]), p.map_torque[r * cols + c], 1e-9);
    }
  const double w = RpmToRadPerSec(0.5 * (p.map_speed_rpm[2] + p.map_speed_rpm[3]));
  EXPECT_NEAR(e.Torque(w, 1.0),
              0.5 * (p.map_torque[2 * cols + cols - 1] + p.map_torque[3 * cols + cols - 1]), 1e-9);
  // Clamped throttle and speed.
  EXPECT_EQ(e.Torque(RpmToRadPerSec(500), 2.0), e.Torque(RpmToRadPerSec(p.map_speed_rpm[0]), 1.0));
}

TEST(EngineMap, RevLimiterCutsPositiveTorqueOnly) {
  const params::EngineParams p;
  const EngineMap e(p);
  const double limit = RpmToRadPerSec(p.rev_limit_rpm);
  const double band = RpmToRadPerSec(p.rev_limiter_band_rpm);
  EXPECT_GT(e.Torque(limit, 1.0), 0.0);
  EXPECT_NEAR(e.Torque(limit + 0.5 * band, 1.0), 0.5 * e.Torque(limit, 1.0), 1e-9);
  EXPECT_EQ(e.Torque(limit + band, 1.0), 0.0);
  EXPECT_LT(e.Torque(limit + 2 * band, 0.0), 0.0);  // engine drag stays
}

struct GearboxRow {
  const char* edge;
  GearboxState from;
  double engine_rpm;
  GearboxState to;
};

TEST(Gearbox, TransitionTableOneRowPerEdge) {
  const params::GearboxParams gp;  // 6 gears, up 7300, down [4800 .. 5800], shift 0.1, min 0.3
  const GearboxConfig c(gp);
  const double dt = 0.001;
  using P = ShiftPhase;
  const GearboxRow rows[] = {
      {"engaged->shifting up", {2, 2, P::kEngaged, 0.5}, 7350, {2, 3, P::kShifting, 0.0}},
      {"engaged->shifting down", {3, 3, P::kEngaged, 0.5}, 4900, {3, 2, P::kShifting, 0.0}},
      {"engaged stays (in band)", {3, 3, P::kEngaged, 0.5}, 6000, {3, 3, P::kEngaged, 0.501}},
      {"engaged stays (min time in gear)",
       {2, 2, P::kEngaged, 0.1},
       7350,
       {2, 2, P::kEngaged, 0.101}},
      {"engaged stays (top gear)", {6, 6, P::kEngaged, 0.5}, 7400, {6, 6, P::kEngaged, 0.501}},
      {"engaged stays (first gear)", {1, 1, P::kEngaged, 0.5}, 1000, {1, 1, P::kEngaged, 0.501}},
      {"shifting->engaged", {2, 3, P::kShifting, 0.0995}, 5000, {3, 3, P::kEngaged, 0.0}},
      {"shifting stays", {2, 3, P::kShifting, 0.05}, 5000, {2, 3, P::kShifting, 0.051}},
  };
  for (const auto& r : rows) {
    const GearboxState n = Next(r.from, RpmToRadPerSec(r.engine_rpm), dt, c);
    EXPECT_EQ(n.engaged, r.to.engaged) << r.edge;
    EXPECT_EQ(n.requested, r.to.requested) << r.edge;
    EXPECT_EQ(n.phase, r.to.phase) << r.edge;
    EXPECT_NEAR(n.time_in_phase, r.to.time_in_phase, 1e-12) << r.edge;
  }
}

// The gear request changes when the shift is decided; the engaged gear follows after the torque
// interruption, during which the driveline transmits no torque.
TEST(Gearbox, RequestLeadsEngagedGearByTheShiftTime) {
  const params::VehicleParams p;
  const Vehicle v(p);
  State s = v.MakeState();
  double t_request = -1.0, t_engaged = -1.0;
  int shifts = 0;
  for (int k = 0; k < 20000 && shifts < 3; ++k) {
    Measurement m = v.Measure(s);
    Actuators u;
    u.throttle = SlipLimitedThrottle(m, p.wheels.radius_rear, 0.03);
    const int engaged_before = s.gearbox.engaged, request_before = s.gearbox.requested;
    v.Step(u, &s);
    m = v.Measure(s);
    if (m.gear_request != request_before) {
      t_request = m.time;
      EXPECT_EQ(m.gear, engaged_before) << "engaged gear must not change at the decision";
    }
    if (m.gear != m.gear_request) {
      EXPECT_EQ(s.out.axle_torque, 0.0) << "torque interruption";
    }
    if (m.gear != engaged_before) {
      t_engaged = m.time;
      EXPECT_NEAR(t_engaged - t_request, p.gearbox.shift_time, 1.5 * v.time_step());
      ++shifts;
    }
  }
  EXPECT_EQ(shifts, 3);
}

TEST(Differential, LsdMovesTorqueToTheSlowerWheel) {
  params::DifferentialParams dp;
  dp.type = "lsd";
  const DifferentialConfig c(dp);
  EXPECT_GT(LsdTorque(50.0, 40.0, 1000.0, c), 0.0);  // RL faster: RL loses torque
  EXPECT_LT(LsdTorque(40.0, 50.0, 1000.0, c), 0.0);
  EXPECT_EQ(LsdTorque(45.0, 45.0, 1000.0, c), 0.0);
  EXPECT_NEAR(LsdTorque(1e3, 0.0, 1000.0, c), dp.lsd_lock_drive * 1000.0, 1e-9);
  EXPECT_NEAR(LsdTorque(1e3, 0.0, -1000.0, c), std::max(dp.lsd_preload, dp.lsd_lock_coast * 1000.0),
              1e-9);
}

// Spool: rear wheels identical; LSD: they may differ in a corner under power, bounded by physics.
TEST(Differential, SpoolLocksAndLsdLetsTheRearWheelsDiffer) {
  for (const char* type : {"spool", "lsd"}) {
    params::VehicleParams p;
    p.differential.type = type;
    const Vehicle v(p);
    State s = v.MakeState({.speed = 15.0});
    Actuators u;
    u.steer_req = 0.1;
    u.throttle = 0.3;
    double max_diff = 0.0;
    for (int k = 0; k < 3000; ++k) {
      v.Step(u, &s);
      max_diff = std::max(max_diff, std::abs(s.x[kOmegaRL] - s.x[kOmegaRR]));
      ASSERT_EQ(s.status, kStatusOk);
    }
    if (std::string(type) == "spool")
      EXPECT_EQ(max_diff, 0.0);
    else
      EXPECT_GT(max_diff, 0.1);
  }
}

}  // namespace
}  // namespace scw::plant
