#include "tuning/sim/run_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "params/io/write.h"

namespace scw::tuning {
std::string FormatFixed(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", digits, x);
  return buf;
}

std::string FormatSigned(double x, int digits) {
  // A change that rounds to zero is written +0.000, never -0.000.
  if (std::abs(x) < 0.5 * std::pow(10.0, -digits)) x = 0.0;
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%+.*f", digits, x);
  return buf;
}

std::string FormatRunSummary(const std::string& name, const RunMetrics& m) {
  std::string out = "scenario " + name + ": " + RunStatusName(m.status);
  if (m.aborted())
    out += " at t = " + FormatFixed(m.time, 2) + " s, lap " + std::to_string(m.end_lap + 1) +
           ", s = " + FormatFixed(m.end_s, 1) + " m";
  out += "\n";
  for (std::size_t i = 0; i < m.lap_times.size(); ++i)
    out += "  lap " + std::to_string(i + 1) + ": " + FormatFixed(m.lap_times[i], 3) + " s\n";
  if (!m.lap_times.empty()) out += "  mean lap: " + FormatFixed(m.MeanLapTime(), 3) + " s\n";
  out += "  max |beta|: " + FormatFixed(RenderedMetric(m, "max_abs_sideslip_deg").real, 2) +
         " deg   max |lateral error|: " + FormatFixed(m.max_abs_lateral_error, 2) +
         " m   max speed: " + FormatFixed(m.max_speed, 1) + " m/s\n";
  out += "  max |slip| front/rear: " + FormatFixed(m.max_slip_front, 1) + " / " +
         FormatFixed(m.max_slip_rear, 1) + " %\n";
  out += "  interventions (count / time): ESC " + std::to_string(m.esc_count) + " / " +
         FormatFixed(m.esc_time, 2) + " s, CS " + std::to_string(m.cs_count) + " / " +
         FormatFixed(m.cs_time, 2) + " s, ABS " + std::to_string(m.abs_count) + " / " +
         FormatFixed(m.abs_time, 2) + " s, TC " + std::to_string(m.tc_count) + " / " +
         FormatFixed(m.tc_time, 2) + " s\n";
  out += "  ESC brake energy: " + FormatFixed(m.esc_brake_energy / 1000.0, 2) +
         " kJ   ABS pressure released: " + FormatFixed(m.abs_pressure_released, 1) +
         " bar*s   TC throttle cut: " + FormatFixed(m.tc_throttle_cut, 3) + " s\n";
  return out;
}

namespace {
/// One `key: value` line per summary member of RunMetrics::Visit.
struct YamlLines {
  const RunMetrics& m;
  std::string out;
  void Output(const RunStatus& s, const params::OutputMeta& meta) {
    out += std::string(meta.key) + ": " + RunStatusName(s) + "\n";
  }
  void Output(const std::vector<double>& laps, const params::OutputMeta& meta) {
    out += std::string(meta.key) + ": " +
           (laps.empty() ? std::string("[]") : params::FormatDoubleList(laps)) + "\n";
    if (!laps.empty())
      out += std::string(kMeanLapTimeKey) + ": " + params::FormatDouble(m.MeanLapTime()) + "\n";
  }
  void Output(const int& x, const params::OutputMeta& meta) {
    if (meta.summary) out += std::string(meta.key) + ": " + std::to_string(x) + "\n";
  }
  void Output(const double& x, const params::OutputMeta& meta) {
    if (meta.summary)
      out += std::string(meta.key) + ": " + params::FormatDouble(params::RenderedValue(x, meta)) +
             "\n";
  }
};
}  // namespace

std::string RunSummaryYaml(const std::string& name, const RunMetrics& m) {
  YamlLines lines{m, {}};
  lines.out = "scenario: " + params::QuoteString(name) + "\n";
  RunMetrics::Visit(m, lines);
  return lines.out;
}

}  // namespace scw::tuning
