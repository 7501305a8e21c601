#include "tuning/sim/run_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "params/io/write.h"

namespace scw::tuning {
namespace {
std::string Fixed(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", digits, x);
  return buf;
}
}  // namespace

std::string FormatRunSummary(const std::string& name, const RunMetrics& m) {
  std::string out = "scenario " + name + ": " + RunStatusName(m.status);
  if (m.aborted())
    out += " at t = " + Fixed(m.time, 2) + " s, lap " + std::to_string(m.end_lap + 1) +
           ", s = " + Fixed(m.end_s, 1) + " m";
  out += "\n";
  for (std::size_t i = 0; i < m.lap_times.size(); ++i)
    out += "  lap " + std::to_string(i + 1) + ": " + Fixed(m.lap_times[i], 3) + " s\n";
  if (!m.lap_times.empty()) out += "  mean lap: " + Fixed(m.MeanLapTime(), 3) + " s\n";
  out += "  max |beta|: " + Fixed(m.max_abs_sideslip * 180.0 / M_PI, 2) +
         " deg   max |lateral error|: " + Fixed(m.max_abs_lateral_error, 2) +
         " m   max speed: " + Fixed(m.max_speed, 1) + " m/s\n";
  out += "  max |slip| front/rear: " + Fixed(m.max_slip_front, 1) + " / " +
         Fixed(m.max_slip_rear, 1) + " %\n";
  out += "  interventions (count / time): ESC " + std::to_string(m.esc_count) + " / " +
         Fixed(m.esc_time, 2) + " s, CS " + std::to_string(m.cs_count) + " / " +
         Fixed(m.cs_time, 2) + " s, ABS " + std::to_string(m.abs_count) + " / " +
         Fixed(m.abs_time, 2) + " s, TC " + std::to_string(m.tc_count) + " / " +
         Fixed(m.tc_time, 2) + " s\n";
  out += "  ESC brake energy: " + Fixed(m.esc_brake_energy / 1000.0, 2) +
         " kJ   ABS pressure released: " + Fixed(m.abs_pressure_released, 1) +
         " bar*s   TC throttle cut: " + Fixed(m.tc_throttle_cut, 3) + " s\n";
  return out;
}

std::string RunSummaryYaml(const std::string& name, const RunMetrics& m) {
  using params::FormatDouble;
  std::string out = "scenario: " + params::QuoteString(name) + "\n";
  out += std::string("status: ") + RunStatusName(m.status) + "\n";
  out += "lap_times_s: " +
         (m.lap_times.empty() ? std::string("[]") : params::FormatDoubleList(m.lap_times)) + "\n";
  auto kv = [&](const char* k, double v) { out += std::string(k) + ": " + FormatDouble(v) + "\n"; };
  auto ki = [&](const char* k, int v) { out += std::string(k) + ": " + std::to_string(v) + "\n"; };
  if (!m.lap_times.empty()) kv("mean_lap_time_s", m.MeanLapTime());
  kv("time_s", m.time);
  kv("distance_m", m.distance);
  kv("end_s_m", m.end_s);
  ki("end_lap", m.end_lap);
  kv("max_abs_sideslip_deg", m.max_abs_sideslip * 180.0 / M_PI);
  kv("max_abs_lateral_error_m", m.max_abs_lateral_error);
  kv("max_abs_heading_error_deg", m.max_abs_heading_error * 180.0 / M_PI);
  kv("max_slip_front_pct", m.max_slip_front);
  kv("max_slip_rear_pct", m.max_slip_rear);
  kv("sideslip_excess_deg_s", m.sideslip_excess_integral);
  kv("max_speed_mps", m.max_speed);
  ki("esc_count", m.esc_count);
  kv("esc_time_s", m.esc_time);
  ki("cs_count", m.cs_count);
  kv("cs_time_s", m.cs_time);
  ki("abs_count", m.abs_count);
  kv("abs_time_s", m.abs_time);
  ki("tc_count", m.tc_count);
  kv("tc_time_s", m.tc_time);
  kv("esc_brake_energy_J", m.esc_brake_energy);
  kv("abs_pressure_released_bar_s", m.abs_pressure_released);
  kv("tc_throttle_cut_s", m.tc_throttle_cut);
  return out;
}

}  // namespace scw::tuning
