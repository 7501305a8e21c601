// Open-Car-Dynamics behind scw's plant interface (plant/ocd/ocd_vehicle.h) and the one parameter
// mapping (plant/ocd/ocd_parameters.h). Built only when OCD is found (SCW_WITH_OCD).
#include "plant/ocd/ocd_vehicle.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "params/schema/field.h"
#include "params/schema/vehicle_params.h"
#include "plant/ocd/ocd_parameters.h"
#include "plant/vehicle/maneuver.h"
#include "plant/vehicle/vehicle.h"

namespace scw::plant::ocd {
namespace {

const params::VehicleParams kCar{};

/// Steps `n` plant steps with constant actuator requests.
template <class P, class S>
void Hold(const P& p, const Actuators& u, int n, S* s) {
  for (int k = 0; k < n; ++k) p.Step(u, s);
}

std::vector<double> Bits(const State& s) {
  std::vector<double> v(s.x.data(), s.x.data() + s.x.size());
  for (double f : s.out.fz) v.push_back(f);
  for (double f : s.out.fy) v.push_back(f);
  return v;
}

TEST(OcdMapping, CoversEveryParameterOcdDeclares) {
  const OcdVehicle car(kCar);
  const OcdState s = car.MakeState();
  std::set<std::string> mapped;
  for (const OcdParameter& q : car.ocd_parameters()) mapped.insert(q.name);
  std::vector<std::string> missing;
  for (const std::string& name : car.OcdNames(s))
    if (!mapped.count(name) && name.rfind("initial_state.", 0) != 0) missing.push_back(name);
  EXPECT_TRUE(missing.empty()) << "OCD parameters the mapping leaves at OCD's defaults: "
                               << testing::PrintToString(missing);
  const std::vector<std::string> names = car.OcdNames(s);
  for (const std::string& name : mapped)
    EXPECT_TRUE(std::binary_search(names.begin(), names.end(), name))
        << name << " is mapped but OCD does not declare it";
}

TEST(OcdMapping, TheMappedValuesReachOcd) {
  params::VehicleParams p = kCar;
  p.grip.rear_mu_y = 0.8;
  p.grip.wheel_mu_x = {1.0, 0.5, 1.0, 1.0};
  const OcdVehicle car(p);
  const OcdState s = car.MakeState();
  const std::string vd = "vehicle_dynamics_double_track.";
  EXPECT_EQ(car.OcdValue(s, vd + "mass_vehicle_kg"), p.chassis.mass);
  EXPECT_EQ(car.OcdValue(s, vd + "moment_of_inertia_kgpm2.z"), p.chassis.yaw_inertia);
  EXPECT_EQ(car.OcdValue(s, vd + "cog.distance_from_front_axle_m"), p.chassis.cg_to_front_axle);
  EXPECT_EQ(car.OcdValue(s, vd + "z.tire_model.rear_left.PDY1"), p.tires.rear.pdy1);
  EXPECT_EQ(car.OcdValue(s, vd + "z.tire_model.front_left.FNOMIN"), p.tires.front.fnomin);
  // Grip factors on the friction scalings of each wheel (grip_scaling peak: LMU only).
  EXPECT_DOUBLE_EQ(car.OcdValue(s, vd + "z.tire_model.rear_right.LMUY"), 0.8 * p.tires.rear.lmuy);
  EXPECT_DOUBLE_EQ(car.OcdValue(s, vd + "z.tire_model.front_right.LMUX"), 0.5 * p.tires.front.lmux);
  EXPECT_EQ(car.OcdValue(s, vd + "z.tire_model.front_left.LMUX"), p.tires.front.lmux);
  EXPECT_EQ(car.OcdValue(s, vd + "z.tire_model.rear_right.LKY"), p.tires.rear.lky);
  EXPECT_EQ(car.OcdValue(s, "integration_step_size_s"), p.simulation.time_step);
  EXPECT_EQ(car.OcdValue(s, "drivetrain.LSD_preload"), p.differential.lsd_preload);
  EXPECT_DOUBLE_EQ(car.OcdValue(s, vd + "aerodynamics.c_l"),
                   -(p.aero.downforce_area_front + p.aero.downforce_area_rear));
}

TEST(OcdMapping, AntiRollBarsGiveTheVehicleFilesRollStiffnessSplit) {
  for (double share : {0.4, 0.5, 0.6, 0.7}) {
    params::VehicleParams p = kCar;
    p.chassis.roll_stiffness_share_front = share;
    double c[2] = {0, 0}, bar[2] = {0, 0};
    for (const OcdParameter& q : MapVehicle(p)) {
      const std::string susp = "vehicle_dynamics_double_track.suspension.";
      for (int a = 0; a < 2; ++a) {
        const std::string axle = a == 0 ? "front" : "rear";
        if (q.name == susp + "vehicle_spring_stiffness_Npm." + axle) c[a] = q.value[0];
        if (q.name == susp + "antirollbar_virtual_spring_stiffness_Npm." + axle)
          bar[a] = q.value[0];
      }
    }
    EXPECT_GE(std::min(bar[0], bar[1]), 0.0);
    EXPECT_EQ(std::min(bar[0], bar[1]), 0.0) << "the smallest pair: one bar is zero";
    const double kf = (c[0] + bar[0]) * p.chassis.track_front * p.chassis.track_front;
    const double kr = (c[1] + bar[1]) * p.chassis.track_rear * p.chassis.track_rear;
    EXPECT_NEAR(kf / (kf + kr), share, 1e-12);
  }
}

TEST(OcdMapping, ValuesOcdCannotRepresentAreNamed) {
  params::VehicleParams p = kCar;
  p.tires.rear.falloff = 2.0;
  p.tires.kinematics.relaxation_length_long = 0.4;
  p.differential.lsd_speed_scale = 2.0;
  const std::vector<Problem> problems = CheckRepresentable(p);
  std::vector<std::string> paths;
  for (const Problem& q : problems) paths.push_back(q.path);
  EXPECT_EQ(paths, (std::vector<std::string>{"tires.rear.falloff",
                                             "tires.kinematics.relaxation_length_long",
                                             "differential.lsd_speed_scale"}));
  try {
    const OcdVehicle car(p);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("tires.rear.falloff"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("plant.model=scw"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(CheckRepresentable(kCar).empty());
}

TEST(OcdMapping, WhatOcdReplacesIsSaid) {
  const std::vector<std::string> notes = Replaced(kCar);
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_NE(notes[0].find("load_transfer_time_constant"), std::string::npos);
  params::VehicleParams p = kCar;
  p.differential.type = "spool";
  EXPECT_EQ(Replaced(p).size(), 3u);
  EXPECT_NE(Replaced(p).back().find("spool"), std::string::npos);
}

/// The vehicle file's numbers by dotted path (arrays: path[i]).
std::map<std::string, double> VehicleNumbers(const params::VehicleParams& p) {
  std::map<std::string, double> out;
  params::ForEachField(p, [&](const std::string& path, const auto& value, const params::Meta&) {
    using T = std::remove_cvref_t<decltype(value)>;
    if constexpr (std::is_same_v<T, double>) {
      out[path] = value;
    } else if constexpr (std::is_same_v<T, PerWheel<double>>) {
      for (std::size_t i = 0; i < 4; ++i) out[path + "[" + std::to_string(i) + "]"] = value[i];
    }
  });
  return out;
}

TEST(OcdMapping, EveryValueTakenFromAVehicleKeyIsThatKeysValueInOcd) {
  const OcdVehicle car(kCar);
  const OcdState s = car.MakeState();
  const std::map<std::string, double> numbers = VehicleNumbers(kCar);
  int direct = 0;
  for (const OcdParameter& q : car.ocd_parameters()) {
    // What reaches OCD is what the mapping lists (scalars; arrays are OCD-only tables).
    if (q.value.size() == 1) {
      EXPECT_EQ(car.OcdValue(s, q.name), q.value[0]) << q.name;
    }
    if (q.ocd_only) {
      EXPECT_FALSE(q.why.empty()) << q.name << ": an OCD-only value needs its reason";
      continue;
    }
    const auto it = numbers.find(q.source);
    if (it == numbers.end()) continue;  // a formula: checked one by one below
    EXPECT_EQ(q.value.at(0), it->second) << q.name << " from " << q.source;
    ++direct;
  }
  EXPECT_GT(direct, 100) << "chassis, wheels, aero, differential and every MF5.2 coefficient";
  // The formulas.
  const auto value = [&](const std::string& name) {
    for (const OcdParameter& q : car.ocd_parameters())
      if (q.name == name) return q.value.at(0);
    ADD_FAILURE() << name << " not mapped";
    return 0.0;
  };
  const std::string ae = "vehicle_dynamics_double_track.aerodynamics.";
  const auto& a = kCar.aero;
  const auto& c = kCar.chassis;
  EXPECT_EQ(value(ae + "c_l"), -(a.downforce_area_front + a.downforce_area_rear));
  // The aero centre puts the front axle's share of the downforce where the vehicle file does.
  const double d = value(ae + "d_aero_center_cog_m");
  const double lr = c.wheelbase - c.cg_to_front_axle;
  EXPECT_NEAR((lr + d) / c.wheelbase,
              a.downforce_area_front / (a.downforce_area_front + a.downforce_area_rear), 1e-12);
  const auto& g = kCar.grip;
  const std::string t = "vehicle_dynamics_double_track.z.tire_model.";
  EXPECT_EQ(value(t + "front_left.LMUX"), kCar.tires.front.lmux * (g.mu * g.front_mu_x));
  EXPECT_EQ(value(t + "rear_right.LMUY"), kCar.tires.rear.lmuy * (g.mu * g.rear_mu_y));
}

// Every key of the vehicle file is accounted for on OCD: mapped onto an OCD parameter (named in a
// source of MapVehicle), kept by scw's own models that drive OCD through its inputs (engine,
// gearbox, brakes, steering, sensors), named as replaced by OCD's own structure (Replaced), or
// refused when it differs from OCD's fixed value (CheckRepresentable). None is dropped silently.
TEST(OcdMapping, EveryVehicleKeyIsMappedKeptReplacedOrRefused) {
  params::VehicleParams spool = kCar;
  spool.differential.type = "spool";
  std::string named;
  for (const params::VehicleParams& p : {kCar, spool}) {
    for (const OcdParameter& q : MapVehicle(p)) named += q.source + "\n";
    for (const std::string& n : Replaced(p)) named += n + "\n";
  }
  const auto named_key = [&](const std::string& path) {
    for (std::size_t at = named.find(path); at != std::string::npos;
         at = named.find(path, at + 1)) {
      const char next = at + path.size() < named.size() ? named[at + path.size()] : ' ';
      if (!(std::isalnum(static_cast<unsigned char>(next)) || next == '_')) return true;
    }
    return false;
  };
  params::VehicleParams probe = kCar;
  std::vector<std::string> silent;
  params::ForEachField(probe, [&](const std::string& path, auto& value, const params::Meta&) {
    for (const char* kept : {"name", "engine.", "gearbox.", "brakes.", "steering.", "sensors."})
      if (path.rfind(kept, 0) == 0) return;
    if (named_key(path)) return;
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(value)>, double>) {
      const double was = value;
      value = was + 0.125;
      bool refused = false;
      for (const Problem& q : CheckRepresentable(probe)) refused = refused || q.path == path;
      value = was;
      if (refused) return;
    }
    silent.push_back(path);
  });
  EXPECT_TRUE(silent.empty()) << "vehicle keys neither mapped, kept, replaced nor refused on OCD: "
                              << testing::PrintToString(silent);
}

TEST(OcdMapping, TheTableListsEveryNonTyreParameterOnce) {
  const std::string md = MappingTableMarkdown(kCar);
  EXPECT_NE(md.find("| `mass_vehicle_kg` | 720 | `chassis.mass` |"), std::string::npos) << md;
  EXPECT_NE(md.find("`z.tire_model.front_*.PDY1`"), std::string::npos);
  EXPECT_EQ(md.find("z.tire_model.front_right"), std::string::npos) << "tyres grouped per axle";
  // No cell over the docs' 300 characters.
  std::size_t start = 0;
  while (start < md.size()) {
    const std::size_t end = md.find('\n', start);
    const std::string line = md.substr(start, end - start);
    std::size_t a = 0;
    while ((a = line.find('|', a)) != std::string::npos) {
      const std::size_t b = line.find('|', a + 1);
      if (b == std::string::npos) break;
      EXPECT_LE(b - a - 1, 300u) << line;
      a = b;
    }
    start = end + 1;
  }
}

// docs/ocd-plant.md carries the table of the built-in car as `scw vehicle ocd` prints it.
TEST(OcdMapping, TheDocsTableIsTheGeneratedOne) {
  std::ifstream f(std::string(SCW_SOURCE_DIR) + "/docs/ocd-plant.md");
  ASSERT_TRUE(f.good()) << "docs/ocd-plant.md";
  std::stringstream text;
  text << f.rdbuf();
  EXPECT_NE(text.str().find(MappingTableMarkdown(kCar)), std::string::npos)
      << "docs/ocd-plant.md's mapping table is stale: replace it with the table of "
         "`scw vehicle ocd` (the lines up to the first blank line)";
}

TEST(OcdVehicle, CoastsStraightAndSettledAtAFlyingStart) {
  const OcdVehicle car(kCar);
  OcdState s = car.MakeState({0.0, 0.0, 0.0, 60.0});
  const double fz0 = s.out.fz[0] + s.out.fz[1] + s.out.fz[2] + s.out.fz[3];
  Hold(car, Actuators{}, 200, &s);
  ASSERT_EQ(s.status, kStatusOk);
  EXPECT_NEAR(s.x[kY], 0.0, 1e-9);
  EXPECT_NEAR(s.x[kYawRate], 0.0, 1e-9);
  EXPECT_LT(s.x[kVx], 60.0);
  EXPECT_GT(s.x[kVx], 55.0);
  // The body starts on its springs under the downforce: the loads after 0.2 s differ from the
  // settled start only by the drag's load transfer and the lower speed (no bounce of many kN).
  const double fz = s.out.fz[0] + s.out.fz[1] + s.out.fz[2] + s.out.fz[3];
  EXPECT_NEAR(fz, fz0, 0.05 * fz0);
}

TEST(OcdVehicle, SteadyCorneringIsCloseToScwsPlant) {
  const Vehicle scw(kCar);
  const OcdVehicle ocd(kCar);
  State a = scw.MakeState({0.0, 0.0, 0.0, 30.0});
  OcdState b = ocd.MakeState({0.0, 0.0, 0.0, 30.0});
  Actuators u;
  u.steer_req = 0.02;
  u.throttle = 0.25;
  for (int k = 0; k < 3000; ++k) {
    scw.Step(u, &a);
    ocd.Step(u, &b);
  }
  ASSERT_EQ(b.status, kStatusOk);
  EXPECT_GT(b.x[kYawRate], 0.0);
  EXPECT_NEAR(b.x[kYawRate], a.x[kYawRate], 0.15 * a.x[kYawRate]);
  EXPECT_NEAR(b.out.a_y, a.out.a_y, 0.15 * a.out.a_y);
  // Outer (right) wheels loaded more in a left turn.
  EXPECT_GT(b.out.fz[kFR], b.out.fz[kFL]);
  EXPECT_GT(b.out.fz[kRR], b.out.fz[kRL]);
}

TEST(OcdVehicle, BrakesDriveAndGearsActThroughScwsActuators) {
  const OcdVehicle car(kCar);
  OcdState s = car.MakeState({0.0, 0.0, 0.0, 20.0});
  Actuators drive;
  drive.throttle = 1.0;
  Hold(car, drive, 4000, &s);
  EXPECT_GT(s.x[kVx], 35.0);
  EXPECT_GT(s.gearbox.engaged, 1);
  EXPECT_GT(s.out.axle_torque, 0.0);
  const double v = s.x[kVx];
  Actuators brake;
  brake.brake_pressure_req = {40.0, 40.0, 30.0, 30.0};
  Hold(car, brake, 500, &s);
  EXPECT_LT(s.x[kVx], v - 5.0);
  // Torque = k_b p of scw's brake actuator's pressure (lagged towards the 40 bar request).
  EXPECT_EQ(s.out.brake_torque[kFL], kCar.brakes.torque_gain_front * s.brakes.pressure[kFL]);
  EXPECT_NEAR(s.brakes.pressure[kFL], 40.0, 1.0);
  const Measurement m = car.Measure(s);
  EXPECT_EQ(m.brake_pressure[kFL], s.brakes.pressure[kFL]);
  EXPECT_EQ(m.v_x, s.x[kVx]);
}

TEST(OcdVehicle, RoadFrictionAndWindAct) {
  const OcdVehicle car(kCar);
  Actuators u;
  u.steer_req = 0.05;
  u.throttle = 0.3;
  OcdState dry = car.MakeState({0.0, 0.0, 0.0, 30.0});
  OcdState wet = car.MakeState({0.0, 0.0, 0.0, 30.0});
  Environment env;
  env.mu = {0.5, 0.5, 0.5, 0.5};
  for (int k = 0; k < 1500; ++k) {
    car.Step(u, &dry);
    car.Step(u, env, &wet);
  }
  EXPECT_LT(std::abs(wet.out.a_y), 0.8 * std::abs(dry.out.a_y));
  EXPECT_EQ(wet.road_mu, env.mu);
  car.Step(u, &wet);  // back on the nominal road: the tyres' own friction again
  EXPECT_EQ(wet.road_mu, (PerWheel<double>{1.0, 1.0, 1.0, 1.0}));
  EXPECT_EQ(car.OcdValue(wet, "vehicle_dynamics_double_track.z.tire_model.front_left.LMUX"),
            kCar.tires.front.lmux);
  // A crosswind from the left (air moving to -y) pushes the car to the right.
  OcdState calm = car.MakeState({0.0, 0.0, 0.0, 40.0});
  OcdState windy = car.MakeState({0.0, 0.0, 0.0, 40.0});
  Environment gust;
  gust.wind_y = -20.0;
  for (int k = 0; k < 500; ++k) {
    car.Step(Actuators{}, &calm);
    car.Step(Actuators{}, gust, &windy);
  }
  EXPECT_LT(windy.x[kVy], calm.x[kVy] - 0.01);
  // The default environment is the nominal step.
  OcdState c = car.MakeState({0.0, 0.0, 0.0, 40.0}), d = car.MakeState({0.0, 0.0, 0.0, 40.0});
  for (int k = 0; k < 200; ++k) {
    car.Step(u, &c);
    car.Step(u, Environment{}, &d);
  }
  EXPECT_EQ(Bits(c), Bits(d));
}

TEST(OcdVehicle, RunsAreDeterministicAndIndependentAcrossThreads) {
  const OcdVehicle car(kCar);
  const auto run = [&car](std::vector<double>* out) {
    OcdState s = car.MakeState({0.0, 0.0, 0.0, 35.0});
    Actuators u;
    for (int k = 0; k < 2000; ++k) {
      u.steer_req = 0.04 * std::sin(0.003 * k);
      u.throttle = k < 1000 ? 0.5 : 0.0;
      u.brake_pressure_req = k < 1000 ? PerWheel<double>{} : PerWheel<double>{30, 30, 20, 20};
      car.Step(u, &s);
    }
    *out = Bits(s);
  };
  std::vector<double> serial, again, t1, t2;
  run(&serial);
  run(&again);
  std::thread a(run, &t1), b(run, &t2);
  a.join();
  b.join();
  EXPECT_EQ(std::memcmp(serial.data(), again.data(), serial.size() * sizeof(double)), 0);
  EXPECT_EQ(serial, t1);
  EXPECT_EQ(serial, t2);
}

TEST(OcdVehicle, TheReferenceManeuverRunsFromRest) {
  const OcdVehicle car(kCar);
  OcdState s = car.MakeState();
  const ManeuverSummary sum = RunReferenceManeuverOn(car, 20.0, &s);
  EXPECT_EQ(sum.status, kStatusOk);
  EXPECT_GT(sum.max_speed, 30.0);
  EXPECT_GT(sum.distance, 300.0);
}

// A non-finite request is handled by scw's actuators as on scw's plant (the steering holds its
// angle, a brake or throttle request counts as zero): the run goes on, finite.
TEST(OcdVehicle, ANonFiniteRequestIsHandledByScwsActuatorsAsOnScwsPlant) {
  const OcdVehicle car(kCar);
  const Vehicle scw(kCar);
  OcdState s = car.MakeState({0.0, 0.0, 0.0, 30.0});
  State r = scw.MakeState({0.0, 0.0, 0.0, 30.0});
  Actuators u;
  u.steer_req = 0.03;
  Hold(car, u, 100, &s);
  Hold(scw, u, 100, &r);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  u.steer_req = nan;
  u.throttle = nan;
  u.brake_pressure_req = {nan, nan, nan, nan};
  Hold(car, u, 100, &s);
  Hold(scw, u, 100, &r);
  EXPECT_EQ(s.status, kStatusOk);
  EXPECT_EQ(s.steering.angle, r.steering.angle);
  EXPECT_EQ(s.brakes.pressure, r.brakes.pressure);
  EXPECT_EQ(s.throttle, 0.0);
  for (double v : Bits(s)) EXPECT_TRUE(std::isfinite(v));
}

// A state that turns non-finite (here: a wind too strong to square in double) ends the run with
// kStatusNonFinite, the state frozen at its last finite value while the time goes on.
TEST(OcdVehicle, ANonFiniteStateEndsTheRunFrozenAtItsLastFiniteValue) {
  const OcdVehicle car(kCar);
  OcdState s = car.MakeState({0.0, 0.0, 0.0, 30.0});
  Hold(car, Actuators{}, 100, &s);
  ASSERT_EQ(s.status, kStatusOk);
  const std::vector<double> before = Bits(s);
  Environment storm;
  storm.wind_x = 1e200;
  car.Step(Actuators{}, storm, &s);
  EXPECT_NE(s.status & kStatusNonFinite, 0u);
  EXPECT_EQ(Bits(s), before);
  const double t = s.time;
  car.Step(Actuators{}, &s);
  EXPECT_EQ(Bits(s), before);
  EXPECT_NE(s.status & kStatusNonFinite, 0u);
  EXPECT_GT(s.time, t);
}

}  // namespace
}  // namespace scw::plant::ocd
