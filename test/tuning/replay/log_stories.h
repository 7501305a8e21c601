// Controller-log rows built from small physical stories (tests of `scw replay` and its benchmark):
// wheel speeds follow from the car's motion through the controller's own kinematics (tyre
// velocities, dynamic radius), so a "rolling" wheel has zero slip and a locking or spinning wheel
// has exactly the slip the story gives it.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "controller/stability/stability_controller.h"
#include "controller/stability/vehicle_model.h"
#include "tuning/replay/controller_log.h"

namespace scw::tuning::testing {

using controller::StabilityInput;

/// Motion of the car at one instant (body frame at the CoG, SI).
struct Motion {
  double v_x = 30.0;
  double v_y = 0.0;
  double yaw_rate = 0.0;
  double a_x = 0.0;
  double a_y = 0.0;
  double steering = 0.0;
};

/// Wheel speeds [rad/s] of the motion with longitudinal slips `slip` (fractions, > 0 spinning).
inline PerWheel<double> WheelSpeeds(const params::StabilityParams& p, const Motion& m,
                                    const PerWheel<double>& slip = {0.0, 0.0, 0.0, 0.0}) {
  const auto g = controller::ChassisGeometry::From(p);
  const auto tv = controller::TyreVelocities(m.v_x, m.v_y, m.yaw_rate, m.steering, g);
  const auto& sc = p.tires.front_left.radius.velocity_scaling;
  const double rf =
      controller::DynamicTyreRadius(p.tires.front_left.radius.radius_20mps, m.v_x, sc);
  const double rr = controller::DynamicTyreRadius(p.tires.rear_left.radius.radius_20mps, m.v_x, sc);
  PerWheel<double> w{};
  for (std::size_t i = 0; i < 4; ++i)
    w[i] = std::max(0.0, tv[i].longitudinal * (1.0 + slip[i]) / (IsFront(i) ? rf : rr));
  return w;
}

/// A log row of the car in `m`, driving with a light throttle in 4th gear, brakes off.
inline StabilityInput Row(const params::StabilityParams& p, double t, const Motion& m) {
  StabilityInput in;
  in.t = t;
  in.v_x = m.v_x;
  in.v_y = m.v_y;
  in.yaw_rate = m.yaw_rate;
  in.a_x = m.a_x;
  in.a_y = m.a_y;
  in.steering_measured = m.steering;
  in.steering_request = m.steering;
  in.brake_request_bar = {0.0, 0.0, 0.0, 0.0};
  in.brake_measured_bar = {0.0, 0.0, 0.0, 0.0};
  in.throttle_request = 0.3;
  in.gear_request = 4;
  in.gear = 4;
  in.engine_speed = 30.0 * m.v_x;
  in.wheel_speed = WheelSpeeds(p, m);
  in.long_fx = 800.0;
  return in;
}

/// Linear ramp 0 → 1 over [t0, t1].
inline double Ramp(double t, double t0, double t1) {
  return std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
}

/// Left-hand corner at 30 m/s with the ESC target a_y,req = 9 m/s² (κ = 0.01 1/m, ψ̇_ref = 0.3
/// rad/s, β_ref ≈ −0.008 rad). Slides: rows where the rear steps out by `slide(t)` (0..1 of the
/// full slide: β −0.12 rad, ψ̇ 0.8 rad/s).
template <class SlideFn>
std::vector<StabilityInput> CornerStory(const params::StabilityParams& p, double duration,
                                        SlideFn slide) {
  std::vector<StabilityInput> rows;
  const double v = 30.0;
  for (int k = 0; k * p.tS < duration; ++k) {
    const double t = k * p.tS;
    const double turn = Ramp(t, 0.3, 0.6);  // turn-in after a short straight
    const double s = slide(t);
    Motion m;
    const double beta = turn * (-0.0084 + s * (-0.12 + 0.0084));
    const double yaw_rate = turn * (0.3 + s * 0.5);
    m.v_x = v * std::cos(beta);
    m.v_y = v * std::sin(beta);
    m.yaw_rate = yaw_rate;
    m.a_y = turn * 9.0;
    m.steering = turn * 0.05;
    StabilityInput in = Row(p, t, m);
    in.ay_request = turn * 9.0;
    in.long_fx = 0.0;
    in.throttle_request = 0.2;
    rows.push_back(in);
  }
  return rows;
}

/// The oversteer episode: the rear steps out at 1.0 s, is fully sliding from 1.15 s to 1.45 s,
/// back in line at 1.8 s.
inline std::vector<StabilityInput> OversteerStory(const params::StabilityParams& p) {
  return CornerStory(p, 2.5,
                     [](double t) { return Ramp(t, 1.0, 1.15) * (1.0 - Ramp(t, 1.45, 1.8)); });
}

/// Hard braking from 40 m/s: from 0.5 s the brakes are applied (50/35 bar, long_fx −15 kN,
/// a_x = −12 m/s²); the front wheels lock within 0.2 s while the car keeps its speed.
inline std::vector<StabilityInput> LockupStory(const params::StabilityParams& p) {
  std::vector<StabilityInput> rows;
  for (int k = 0; k * p.tS < 1.2; ++k) {
    const double t = k * p.tS;
    const double tb = std::max(0.0, t - 0.5);  // time since the brakes came on
    Motion m;
    m.v_x = 40.0 - 12.0 * tb;
    StabilityInput in = Row(p, t, m);
    if (t >= 0.5) {
      m.a_x = -12.0;
      in = Row(p, t, m);
      in.brake_request_bar = {50.0, 50.0, 35.0, 35.0};
      in.brake_measured_bar = {50.0, 50.0, 35.0, 35.0};
      in.throttle_request = 0.0;
      in.long_fx = -15000.0;
      const double lock = -std::min(1.0, tb / 0.2);  // front slip → −100 %
      in.wheel_speed = WheelSpeeds(p, m, {lock, lock, -0.03, -0.03});
    }
    rows.push_back(in);
  }
  return rows;
}

/// Full throttle at 20 m/s from 0.5 s: long_fx = +4 kN and the rear wheels spin up to +30 % slip
/// within 0.1 s, held to the end (1.2 s).
inline std::vector<StabilityInput> RearSpinStory(const params::StabilityParams& p) {
  std::vector<StabilityInput> rows;
  for (int k = 0; k * p.tS < 1.2; ++k) {
    const double t = k * p.tS;
    Motion m;
    m.v_x = 20.0;
    StabilityInput in = Row(p, t, m);
    if (t >= 0.5) {
      const double spin = 0.3 * Ramp(t, 0.5, 0.6);
      in.throttle_request = 0.9;
      in.long_fx = 4000.0;
      in.wheel_speed = WheelSpeeds(p, m, {0.0, 0.0, spin, spin});
    }
    rows.push_back(in);
  }
  return rows;
}

/// Deterministic synthetic lap signal, row k (period tS): a 10 s cycle of cornering with weaving
/// steering, an oversteer slide, a braking lock-up, a wheel spin on acceleration and a straight;
/// with gaps in optional signals, a few rows without the essential yaw rate, gear changes, brake
/// temperatures and (in every other cycle) external vertical loads.
inline StabilityInput SyntheticRow(const params::StabilityParams& p, long k) {
  const double t = static_cast<double>(k) * p.tS;
  const long cycle = k / 1000;
  const double tc = static_cast<double>(k % 1000) * p.tS;  // time in the cycle [s]
  Motion m;
  m.v_x = 35.0 + 10.0 * std::sin(0.21 * t);
  m.steering = 0.04 * std::sin(1.3 * t) + 0.01 * std::sin(4.1 * t);
  m.yaw_rate = m.v_x * m.steering / 2.971;
  m.a_y = m.v_x * m.yaw_rate;
  m.a_x = 2.0 * std::cos(0.21 * t);
  PerWheel<double> slip{0.0, 0.0, 0.0, 0.0};
  double brake = 0.0, throttle = 0.4 + 0.2 * std::sin(0.7 * t), long_fx = 1500.0;
  if (tc >= 3.0 && tc < 4.5) {  // oversteer slide
    const double s = Ramp(tc, 3.0, 3.2) * (1.0 - Ramp(tc, 4.0, 4.5));
    const double beta = -0.12 * s;
    m.v_y = m.v_x * std::tan(beta);
    m.yaw_rate += 0.5 * s;
  } else if (tc >= 4.5 && tc < 6.0) {  // braking, fronts locking
    const double tb = tc - 4.5;
    brake = 45.0 * Ramp(tb, 0.0, 0.1);
    throttle = 0.0;
    long_fx = -14000.0;
    m.a_x = -11.0;
    const double lock = -0.6 * std::min(1.0, tb / 0.3) * (0.6 + 0.4 * std::sin(9.0 * tb));
    slip = {lock, lock * 0.9, -0.04, -0.04};
  } else if (tc >= 6.0 && tc < 8.0) {  // acceleration with rear wheel spin
    throttle = 0.95;
    long_fx = 4500.0;
    const double spin = 0.3 * Ramp(tc, 6.0, 6.2) * (1.0 - Ramp(tc, 7.5, 8.0));
    slip = {0.0, 0.0, spin, spin * 1.05};
  }
  StabilityInput in = Row(p, t, m);
  in.wheel_speed = WheelSpeeds(p, m, slip);
  in.brake_request_bar = {brake, brake, 0.7 * brake, 0.7 * brake};
  in.brake_measured_bar = in.brake_request_bar;
  in.throttle_request = throttle;
  in.long_fx = long_fx;
  in.ay_request = (k % 50 < 40) ? m.a_y : controller::kNotAvailable;
  in.gear = in.gear_request = 3 + static_cast<int>(cycle % 3);
  in.brake_temperature_degc = {300.0 + 50.0 * std::sin(0.1 * t), 310.0, 250.0, 260.0};
  if (k % 113 == 7) in.a_x = controller::kNotAvailable;
  if (k % 977 == 500) in.yaw_rate = controller::kNotAvailable;  // invalid row: pass-through
  if (cycle % 2 == 1)
    in.fz_external = {1800.0 + 10.0 * m.a_y, 1800.0 - 10.0 * m.a_y, 2200.0, 2200.0};
  return in;
}

/// Writes `rows` with ControllerLogWriter.
inline void WriteLog(const std::string& path, const std::vector<StabilityInput>& rows) {
  replay::ControllerLogWriter w(path);
  for (const auto& r : rows) w.Write(r);
  w.Commit();
}

/// A fresh empty folder under the system temp folder, removed by the destructor.
class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() / (name + "." + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string File(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline std::string ReadFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

/// A numeric CSV file (replay output) read back exactly (std::from_chars).
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;

  std::size_t Col(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw std::runtime_error("no column " + name);
    return static_cast<std::size_t>(it - header.begin());
  }
  double At(std::size_t row, const std::string& name) const { return rows.at(row).at(Col(name)); }
};

inline CsvTable ReadCsv(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot open " + path);
  CsvTable table;
  std::string line;
  auto split = [](const std::string& l) {
    std::vector<std::string> cells;
    std::stringstream ss(l);
    std::string c;
    while (std::getline(ss, c, ',')) cells.push_back(c);
    return cells;
  };
  std::getline(f, line);
  table.header = split(line);
  while (std::getline(f, line)) {
    std::vector<double> row;
    for (const auto& c : split(line)) {
      double v = 0.0;
      if (c == "nan") {
        v = std::nan("");
      } else {
        const auto r = std::from_chars(c.data(), c.data() + c.size(), v);
        if (r.ec != std::errc() || r.ptr != c.data() + c.size())
          throw std::runtime_error("bad number " + c + " in " + path);
      }
      row.push_back(v);
    }
    table.rows.push_back(std::move(row));
  }
  return table;
}

/// Same double bit for bit (all NaNs alike).
inline bool SameBits(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::memcmp(&a, &b, sizeof a) == 0;
}

}  // namespace scw::tuning::testing
