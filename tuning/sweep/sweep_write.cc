#include "tuning/sweep/sweep_write.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string_view>

#include "params/io/csv.h"

namespace scw::tuning::sweep {
namespace {

std::string SafeFilePart(const std::string& s) {
  std::string out = s;
  for (char& c : out)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '+' ||
          c == '-'))
      c = '_';
  return out;
}

const std::string& ConfigName(const SweepResult& r, const SweepRun& run) {
  return r.configs[static_cast<std::size_t>(run.point.config)].name;
}

const std::string& AxisValue(const SweepResult& r, const SweepRun& run, std::size_t axis) {
  return r.axes[axis].values[static_cast<std::size_t>(run.point.value[axis])];
}

std::string Fixed(double x, int digits) {
  if (std::isnan(x)) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << x;
  return s.str();
}

}  // namespace

bool SelectedForTrace(const SweepResult& r, const SweepRun& run,
                      const std::vector<TraceCondition>& conditions) {
  for (const auto& c : conditions) {
    const std::string& have =
        c.axis < 0 ? ConfigName(r, run) : AxisValue(r, run, static_cast<std::size_t>(c.axis));
    if (std::none_of(c.values.begin(), c.values.end(),
                     [&](const std::string& v) { return SameSweepValue(have, v); }))
      return false;
  }
  return true;
}

bool MatchesTraceConditions(const SweepResult& r, const SweepRun& run,
                            const std::vector<std::string>& at) {
  return SelectedForTrace(r, run, ParseTraceConditions(r.axes, at));
}

std::string TraceFileName(const SweepResult& r, const SweepRun& run) {
  std::string name = SafeFilePart(ConfigName(r, run));
  for (std::size_t i = 0; i < r.axes.size(); ++i)
    name += "__" + SafeFilePart(r.axes[i].key) + "-" + SafeFilePart(AxisValue(r, run, i));
  return name + ".csv";
}

void WriteSweepCsv(const std::string& path, const SweepResult& r) {
  int max_laps = 0;
  for (const auto& run : r.runs) max_laps = std::max(max_laps, run.spec.laps);
  std::vector<std::string> header = {"config"};
  for (const auto& a : r.axes) header.push_back(a.key);  // CsvWriter quotes (RFC 4180)
  for (const char* h : {"status", "progress", "laps_completed"}) header.emplace_back(h);
  for (int k = 1; k <= max_laps; ++k) header.push_back("lap_" + std::to_string(k) + "_s");
  // The RunMetrics columns (names, units and conversions: RunMetrics::Visit).
  static constexpr std::string_view kColumns[] = {kMeanLapTimeKey,
                                                  "max_abs_sideslip_deg",
                                                  "max_slip_front_pct",
                                                  "max_slip_rear_pct",
                                                  "max_abs_lateral_error_m",
                                                  "max_abs_heading_error_deg",
                                                  "max_speed_mps",
                                                  "esc_count",
                                                  "cs_count",
                                                  "abs_count",
                                                  "tc_count",
                                                  "esc_time_s",
                                                  "cs_time_s",
                                                  "abs_time_s",
                                                  "tc_time_s",
                                                  "esc_brake_energy_J",
                                                  "max_esc_margin",
                                                  "max_esc_beta_ratio",
                                                  "max_esc_beta_error_ratio",
                                                  "max_esc_yaw_rate_error_ratio",
                                                  "steer_hf_rms_deg",
                                                  "end_lap",
                                                  "end_s_m"};
  for (std::string_view c : kColumns) header.emplace_back(c);
  header.emplace_back("ideal_lap_time_s");
  io::CsvWriter w(path, header);
  for (const auto& run : r.runs) {
    if (!run.reported) continue;
    const RunMetrics& m = run.metrics;
    w.Add(ConfigName(r, run));
    for (std::size_t i = 0; i < r.axes.size(); ++i) w.Add(AxisValue(r, run, i));
    w.Add(std::string(RunStatusName(m.status)));
    w.Add(m.Progress());
    w.Add(static_cast<int>(m.lap_times.size()));
    for (int k = 0; k < max_laps; ++k)
      w.Add(k < static_cast<int>(m.lap_times.size()) ? m.lap_times[static_cast<std::size_t>(k)]
                                                     : std::nan(""));
    for (std::string_view c : kColumns) {
      const MetricValue v = RenderedMetric(m, c);
      if (v.is_integer)
        w.Add(static_cast<int>(v.integer));
      else
        w.Add(v.real);
    }
    w.Add(run.ideal_lap_time);
    w.EndRow();
  }
  w.Commit();
}

std::string SweepTable(const SweepResult& r) {
  std::size_t w_config = 0, w_status = 0;
  std::vector<std::size_t> w_axis(r.axes.size(), 0);
  for (const auto& run : r.runs) {
    if (!run.reported) continue;
    w_config = std::max(w_config, ConfigName(r, run).size());
    w_status = std::max(w_status, std::string(RunStatusName(run.metrics.status)).size());
    for (std::size_t i = 0; i < r.axes.size(); ++i)
      w_axis[i] = std::max(w_axis[i], AxisValue(r, run, i).size());
  }
  std::ostringstream out;
  for (const auto& run : r.runs) {
    if (!run.reported) continue;
    const auto& m = run.metrics;
    out << std::left << std::setw(static_cast<int>(w_config)) << ConfigName(r, run);
    for (std::size_t i = 0; i < r.axes.size(); ++i)
      out << "  " << r.axes[i].key << '=' << std::setw(static_cast<int>(w_axis[i]))
          << AxisValue(r, run, i);
    out << "  " << std::setw(static_cast<int>(w_status)) << RunStatusName(m.status) << "  mean lap "
        << std::right << std::setw(7) << Fixed(m.MeanLapTime(), 3) << " s  max|beta| "
        << std::setw(5) << Fixed(RenderedMetric(m, "max_abs_sideslip_deg").real, 2)
        << " deg  slip f/r " << std::setw(5) << Fixed(m.max_slip_front, 1) << '/' << std::setw(5)
        << Fixed(m.max_slip_rear, 1) << " %\n";
  }
  return out.str();
}

}  // namespace scw::tuning::sweep
