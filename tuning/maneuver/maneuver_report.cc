#include "tuning/maneuver/maneuver_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
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
    if (static_cast<unsigned char>(c) < 0x20) {  // a file name may hold anything
      char u[8];
      std::snprintf(u, sizeof u, "\\u%04x", static_cast<unsigned>(c));
      out += u;
      continue;
    }
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string Cell(double x) {
  if (!std::isfinite(x)) return "-";
  const double a = std::abs(x);
  const int digits = a >= 100.0 ? 1 : (a >= 1.0 ? 2 : 3);
  // A value that rounds to zero is 0, not -0.000.
  if (a < 0.5 * std::pow(10.0, -digits)) x = 0.0;
  return FormatFixed(x, digits);
}

/// "on" when all four subsystems ran, "off" when none did, else "partial".
std::string StabilityControlText(const params::SubsystemSwitches& sw) {
  const int on = sw.esc + sw.cs + sw.abs + sw.tc;
  return on == 4 ? "on" : (on == 0 ? "off" : "partial");
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

std::string SubsystemsText(const params::SubsystemSwitches& sw) {
  std::string s;
  for (auto [on, name] : {std::pair{sw.esc, "ESC"}, {sw.cs, "CS"}, {sw.abs, "ABS"}, {sw.tc, "TC"}})
    if (on) s += (s.empty() ? "" : " ") + std::string(name);
  return s.empty() ? "none" : s;
}

std::vector<ManeuverLimit> ManeuverLimits(const ManeuverResult& r) {
  std::vector<ManeuverLimit> out;
  std::vector<std::vector<std::string>> runs;  // labels of the runs with each limit
  for (const auto& run : r.runs)
    for (const auto& c : run.criteria) {
      std::size_t i = 0;
      while (i < out.size() && !(out[i].key == c.key && out[i].limit == c.limit &&
                                 out[i].upper == c.upper && out[i].source == c.source))
        ++i;
      if (i == out.size()) {
        out.push_back({c.key, c.limit, c.upper, c.source, ""});
        runs.emplace_back();
      }
      if (runs[i].empty() || runs[i].back() != run.label) runs[i].push_back(run.label);
    }
  for (std::size_t i = 0; i < out.size(); ++i) {
    const auto& l = runs[i];
    out[i].runs = l.size() == r.runs.size() ? "every run"
                  : l.size() == 1           ? "run " + l.front()
                                            : "runs " + l.front() + " to " + l.back();
  }
  return out;
}

std::vector<std::string> ManeuverNotes(const ManeuverResult& r, const ManeuverConditions& c) {
  std::vector<std::string> notes;
  const RunMetrics s = r.Summary();
  const auto& sw = c.subsystems;
  const bool any_on = sw.esc || sw.cs || sw.abs || sw.tc;
  const long acted = (sw.esc ? s.esc_count : 0) + (sw.cs ? s.cs_count : 0) +
                     (sw.abs ? s.abs_count : 0) + (sw.tc ? s.tc_count : 0);
  // The subsystem each test is about (docs/maneuvers.md).
  const std::string& n = r.name;
  const bool acceleration = n == "split_mu_acceleration" || n == "mu_jump_acceleration";
  struct Target {
    bool on;
    int count;
    const char* name;
  };
  std::vector<Target> targets;
  if (n == "sine_with_dwell" || n == "step_steer" || n == "steady_state_circular" ||
      n == "braking_in_turn" || n == "power_off_in_turn" || n == "power_on_in_turn")
    targets.push_back({sw.esc, s.esc_count, "ESC"});
  if (n == "braking_in_turn" || n == "split_mu_braking")
    targets.push_back({sw.abs, s.abs_count, "ABS"});
  if (n == "power_on_in_turn" || acceleration) targets.push_back({sw.tc, s.tc_count, "TC"});
  if (any_on && acted == 0) {
    notes.push_back("no stability subsystem that ran (" + SubsystemsText(sw) +
                    ") acted in any run (ESC/CS/ABS/TC activations 0/0/0/0): at these "
                    "conditions this test does not exercise stability control, so its result is "
                    "the car's own response (compare --subsystems none)");
  } else {
    double esc_margin = 0.0;  // closest approach to ESC's activation condition (> 1: held)
    for (const auto& run : r.runs) esc_margin = std::max(esc_margin, run.metrics.max_esc_margin);
    for (const Target& t : targets)
      if (t.on && t.count == 0)
        notes.push_back(std::string(t.name) +
                        " ran but did not act in any run: at these conditions this test does not "
                        "exercise " +
                        t.name +
                        (std::string(t.name) == "ESC" && esc_margin > 0.0
                             ? " (its activation condition came to " + FormatFixed(esc_margin, 2) +
                                   " of holding at most, 1 = holds: max_esc_margin)"
                             : std::string()));
  }
  if (!acceleration) return notes;
  // Full throttle, no brake requested: a braking slip of a rear wheel is the brakes'. TC's rear
  // pressure is k·(1 − ε)·F of the requested drive force F (long_fx, here the engine's force at
  // full throttle) whatever the engine delivers; ε rises only by increase_step per step and TC
  // ends only deactivation_duration after the slip last exceeded its threshold; ABS acts only on a
  // braking request or with ESC (spec §3.4-§3.6). When the drive torque drops under it (a gear
  // shift interrupts it), the rear wheels are braked.
  for (const auto& run : r.runs) {
    const ManeuverSignals& sg = run.signals;
    double lowest = 0.0, at = 0.0;
    for (std::size_t k = 0; k < sg.t.size() && k < sg.max_slip_rear.size(); ++k)
      if (sg.t[k] >= 0.0 && sg.max_slip_rear[k] < lowest) {
        lowest = sg.max_slip_rear[k];
        at = sg.t[k];
      }
    if (lowest < -10.0 && sw.tc && run.metrics.tc_count > 0)
      notes.push_back(run.label + ": a rear wheel ran at " + FormatFixed(lowest, 1) +
                      " % slip (braking) at t = " + FormatFixed(at, 2) +
                      " s although this test requests no brake. This is the published TC (spec "
                      "§3.5), kept as published: its rear pressure comes from the requested drive "
                      "force (long_fx, here full throttle), not from what the engine delivers, "
                      "and is released only step by step, so it stays on while a gear shift "
                      "interrupts the drive torque; ABS acts only on a braking request or with "
                      "ESC. max_slip_rear_pct counts |slip| of either sign");
  }
  return notes;
}

std::string FormatManeuver(const ManeuverResult& r, const ManeuverConditions& conditions) {
  std::string out = r.name + ": " + r.standard + "\n";
  out += "vehicle: " + conditions.vehicle + "; stability: " + conditions.stability +
         "; subsystems: " + SubsystemsText(conditions.subsystems) + " (stability control " +
         StabilityControlText(conditions.subsystems) + ")\n";
  out += "setup:\n";
  for (const auto& s : r.setup)
    out += "  " + s.key + ": " + Cell(s.value) + (s.doc.empty() ? "" : "  (" + s.doc + ")") + "\n";
  const std::vector<ManeuverLimit> limits = ManeuverLimits(r);
  if (!limits.empty()) {
    out += "pass limits:\n";
    for (const auto& l : limits)
      out += "  " + l.key + (l.upper ? " <= " : " >= ") + params::FormatDouble(l.limit) + "  (" +
             l.source + "; " + l.runs + ")\n";
  }
  // Columns: the union of the runs' value keys, in first-seen order, with what each is.
  std::vector<std::string> keys;
  std::string legend;
  for (const auto& run : r.runs)
    for (const auto& v : run.values) {
      bool seen = false;
      for (const auto& k : keys) seen = seen || k == v.key;
      if (seen) continue;
      keys.push_back(v.key);
      if (!v.doc.empty()) legend += "  " + v.key + ": " + v.doc + "\n";
    }
  if (!legend.empty()) out += "columns:\n" + legend;
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
  for (const auto& n : ManeuverNotes(r, conditions)) out += "\nnote: " + n;
  return out + "\n";
}

std::string ManeuverJson(const ManeuverResult& r, int signal_every,
                         const ManeuverConditions& conditions) {
  const int every = std::max(1, signal_every);
  const RunMetrics sum = r.Summary();
  std::string out = "{\"maneuver\": " + Quoted(r.name) + ", \"standard\": " + Quoted(r.standard) +
                    ", \"series\": " + Quoted(r.series) + ",\n \"setup\": {";
  for (std::size_t i = 0; i < r.setup.size(); ++i)
    out += (i ? ", " : "") + Quoted(r.setup[i].key) + ": " + Number(r.setup[i].value);
  out += "},\n \"conditions\": {\"vehicle\": " + Quoted(conditions.vehicle) +
         ", \"stability\": " + Quoted(conditions.stability) +
         ", \"subsystems\": " + Quoted(SubsystemsText(conditions.subsystems)) +
         ", \"stability_control\": " + Quoted(StabilityControlText(conditions.subsystems)) +
         "},\n \"limits\": [";
  const std::vector<ManeuverLimit> limits = ManeuverLimits(r);
  for (std::size_t i = 0; i < limits.size(); ++i) {
    const auto& l = limits[i];
    out += std::string(i ? ", " : "") + "{\"key\": " + Quoted(l.key) +
           ", \"limit\": " + Number(l.limit) + ", \"bound\": " + (l.upper ? "\"max\"" : "\"min\"") +
           ", \"source\": " + Quoted(l.source) + ", \"runs\": " + Quoted(l.runs) + "}";
  }
  out += "],\n \"notes\": [";
  const std::vector<std::string> notes = ManeuverNotes(r, conditions);
  for (std::size_t i = 0; i < notes.size(); ++i) out += (i ? ", " : "") + Quoted(notes[i]);
  out += "],\n \"criteria_checked\": " + std::to_string(sum.criteria_checked) +
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
           ",\n    \"y_m\": " + Series(s.y, 1.0, every) +
           ",\n    \"slip_rear_pct\": " + Series(s.max_slip_rear, 1.0, every) + "}}";
  }
  return out + "]}\n";
}

}  // namespace scw::tuning
