#include "tuning/maneuver/maneuver_report.h"

#include <cmath>
#include <vector>

#include "params/io/write.h"
#include "tuning/sim/run_summary.h"

namespace scw::tuning {
namespace {

constexpr double kRadToDegree = 180.0 / M_PI;

std::string Number(double x) { return std::isfinite(x) ? params::FormatDouble(x) : "null"; }

std::string Quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string Cell(double x) {
  if (!std::isfinite(x)) return "-";
  const double a = std::abs(x);
  return FormatFixed(x, a >= 100.0 ? 1 : (a >= 1.0 ? 2 : 3));
}

std::string Verdict(const ManeuverRun& r) {
  if (r.criteria.empty()) return "-";
  std::string failed;
  for (const auto& c : r.criteria)
    if (!c.passed()) failed += " " + c.key;
  return failed.empty() ? "pass" : "FAIL:" + failed;
}

std::string Series(const std::vector<double>& v, double scale, int every) {
  std::string out = "[";
  for (std::size_t k = 0; k < v.size(); k += static_cast<std::size_t>(every)) {
    if (k > 0) out += ",";
    out += Number(v[k] * scale);
  }
  return out + "]";
}

}  // namespace

std::string FormatManeuver(const ManeuverResult& r) {
  std::string out = r.name + ": " + r.standard + "\n";
  for (const auto& s : r.setup)
    out += "  " + s.key + ": " + Cell(s.value) + (s.doc.empty() ? "" : "  (" + s.doc + ")") + "\n";
  // Columns: the union of the runs' value keys, in first-seen order.
  std::vector<std::string> keys;
  for (const auto& run : r.runs)
    for (const auto& v : run.values) {
      bool seen = false;
      for (const auto& k : keys) seen = seen || k == v.key;
      if (!seen) keys.push_back(v.key);
    }
  out += "\n| run |";
  for (const auto& k : keys) out += " " + k + " |";
  out += " max |beta| [deg] | ESC/CS/ABS/TC | verdict |\n|---|";
  for (std::size_t i = 0; i < keys.size() + 3; ++i) out += "---|";
  out += "\n";
  for (const auto& run : r.runs) {
    out += "| " + run.label + " |";
    for (const auto& k : keys) {
      double x = NAN;
      for (const auto& v : run.values)
        if (v.key == k) x = v.value;
      out += " " + Cell(x) + " |";
    }
    const RunMetrics& m = run.metrics;
    out += " " + Cell(m.max_abs_sideslip * kRadToDegree) + " | " + std::to_string(m.esc_count) +
           "/" + std::to_string(m.cs_count) + "/" + std::to_string(m.abs_count) + "/" +
           std::to_string(m.tc_count) + " | " + Verdict(run) + " |\n";
  }
  const RunMetrics s = r.Summary();
  out += "\ncriteria: " + std::to_string(s.criteria_checked) + " checked, " +
         std::to_string(s.criteria_failed) + " failed";
  for (const auto& run : r.runs)
    for (const auto& c : run.criteria)
      if (!c.passed())
        out += "\n  " + run.label + ": " + c.key + " = " + Cell(c.value) +
               (c.upper ? " above " : " below ") + Cell(c.limit) + " (" + c.source + ")";
  if (s.aborted()) out += std::string("\nstatus: ") + RunStatusName(s.status);
  return out + "\n";
}

std::string ManeuverJson(const ManeuverResult& r, int signal_every) {
  const int every = std::max(1, signal_every);
  const RunMetrics sum = r.Summary();
  std::string out = "{\"maneuver\": " + Quoted(r.name) + ", \"standard\": " + Quoted(r.standard) +
                    ", \"series\": " + Quoted(r.series) + ",\n \"setup\": {";
  for (std::size_t i = 0; i < r.setup.size(); ++i)
    out += (i ? ", " : "") + Quoted(r.setup[i].key) + ": " + Number(r.setup[i].value);
  out += "},\n \"criteria_checked\": " + std::to_string(sum.criteria_checked) +
         ", \"criteria_failed\": " + std::to_string(sum.criteria_failed) + ",\n \"runs\": [";
  for (std::size_t j = 0; j < r.runs.size(); ++j) {
    const ManeuverRun& run = r.runs[j];
    out += std::string(j ? "," : "") + "\n  {\"label\": " + Quoted(run.label) +
           ", \"level\": " + Number(run.level) +
           ", \"status\": " + Quoted(RunStatusName(run.metrics.status)) + ",\n   \"values\": {";
    for (std::size_t i = 0; i < run.values.size(); ++i)
      out += (i ? ", " : "") + Quoted(run.values[i].key) + ": " + Number(run.values[i].value);
    out += "},\n   \"criteria\": [";
    for (std::size_t i = 0; i < run.criteria.size(); ++i) {
      const auto& c = run.criteria[i];
      out += std::string(i ? ", " : "") + "{\"key\": " + Quoted(c.key) +
             ", \"value\": " + Number(c.value) + ", \"limit\": " + Number(c.limit) +
             ", \"bound\": " + (c.upper ? "\"max\"" : "\"min\"") +
             ", \"source\": " + Quoted(c.source) +
             ", \"passed\": " + (c.passed() ? "true" : "false") + "}";
    }
    out += "],\n   \"metrics\": {";
    bool first = true;
    for (const auto key : SummaryMetricKeys()) {
      const MetricValue v = RenderedMetric(run.metrics, key);
      out += std::string(first ? "" : ", ") + Quoted(std::string(key)) + ": " +
             (v.is_integer ? std::to_string(v.integer) : Number(v.real));
      first = false;
    }
    const ManeuverSignals& s = run.signals;
    out += "},\n   \"signals\": {\"t_s\": " + Series(s.t, 1.0, every) +
           ",\n    \"steer_deg\": " + Series(s.steer, kRadToDegree, every) +
           ",\n    \"yaw_rate_degps\": " + Series(s.yaw_rate, kRadToDegree, every) +
           ",\n    \"ay_mps2\": " + Series(s.a_y, 1.0, every) +
           ",\n    \"beta_deg\": " + Series(s.beta, kRadToDegree, every) +
           ",\n    \"speed_mps\": " + Series(s.speed, 1.0, every) +
           ",\n    \"heading_deg\": " + Series(s.heading, kRadToDegree, every) +
           ",\n    \"x_m\": " + Series(s.x, 1.0, every) +
           ",\n    \"y_m\": " + Series(s.y, 1.0, every) + "}}";
  }
  return out + "]}\n";
}

}  // namespace scw::tuning
