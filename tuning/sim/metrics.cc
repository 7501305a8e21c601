#include "tuning/sim/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>

namespace scw::tuning {

const char* RunStatusName(RunStatus s) {
  switch (s) {
    case RunStatus::kCompleted:
      return "completed";
    case RunStatus::kSideslip:
      return "sideslip";
    case RunStatus::kLateralError:
      return "lateral_error";
    case RunStatus::kWheelLock:
      return "wheel_lock";
    case RunStatus::kWheelSpin:
      return "wheel_spin";
    case RunStatus::kOffTrack:
      return "off_track";
    case RunStatus::kNonFinite:
      return "non_finite";
    case RunStatus::kTimeout:
      return "timeout";
    case RunStatus::kInvalidParams:
      return "invalid_params";
  }
  return "?";
}

double RunMetrics::MeanLapTime() const {
  if (lap_times.empty()) return std::nan("");
  return std::accumulate(lap_times.begin(), lap_times.end(), 0.0) /
         static_cast<double>(lap_times.size());
}

double RunMetrics::Progress() const {
  if (!(distance_planned > 0)) return status == RunStatus::kCompleted ? 1.0 : 0.0;
  const double p = distance / distance_planned;
  return std::isfinite(p) ? std::clamp(p, 0.0, 1.0) : 0.0;
}

std::string EncodeRunMetrics(const RunMetrics& m) {
  std::string out;
  char buf[64];
  const auto num = [&](double x) {
    std::snprintf(buf, sizeof buf, " %a", x);
    out += buf;
  };
  const auto integer = [&](long x) { out += " " + std::to_string(x); };
  integer(static_cast<long>(m.status));
  integer(static_cast<long>(m.lap_times.size()));
  for (double t : m.lap_times) num(t);
  integer(m.laps_planned);
  for (double x : {m.time, m.distance, m.distance_planned, m.end_s}) num(x);
  integer(m.end_lap);
  for (double x :
       {m.max_abs_sideslip, m.max_abs_lateral_error, m.max_abs_heading_error, m.max_slip_front,
        m.max_slip_rear, m.sideslip_excess_integral, m.esc_time, m.cs_time, m.abs_time, m.tc_time})
    num(x);
  for (int c : {m.esc_count, m.cs_count, m.abs_count, m.tc_count}) integer(c);
  for (double x : {m.esc_brake_energy, m.abs_pressure_released, m.tc_throttle_cut, m.max_speed})
    num(x);
  return out;
}

const char* DecodeRunMetrics(const char* text, RunMetrics* m) {
  const char* p = text;
  bool ok = true;
  const auto num = [&]() {
    char* end = nullptr;
    const double x = std::strtod(p, &end);
    if (end == p) ok = false;
    p = end;
    return x;
  };
  const auto integer = [&]() {
    char* end = nullptr;
    const long x = std::strtol(p, &end, 10);
    if (end == p) ok = false;
    p = end;
    return x;
  };
  const long status = integer();
  if (status < 0 || status > static_cast<long>(RunStatus::kInvalidParams)) return nullptr;
  m->status = static_cast<RunStatus>(status);
  const long laps = integer();
  if (laps < 0 || laps > 100000) return nullptr;
  m->lap_times.resize(static_cast<std::size_t>(laps));
  for (double& t : m->lap_times) t = num();
  m->laps_planned = static_cast<int>(integer());
  for (double* x : {&m->time, &m->distance, &m->distance_planned, &m->end_s}) *x = num();
  m->end_lap = static_cast<int>(integer());
  for (double* x : {&m->max_abs_sideslip, &m->max_abs_lateral_error, &m->max_abs_heading_error,
                    &m->max_slip_front, &m->max_slip_rear, &m->sideslip_excess_integral,
                    &m->esc_time, &m->cs_time, &m->abs_time, &m->tc_time})
    *x = num();
  for (int* c : {&m->esc_count, &m->cs_count, &m->abs_count, &m->tc_count})
    *c = static_cast<int>(integer());
  for (double* x :
       {&m->esc_brake_energy, &m->abs_pressure_released, &m->tc_throttle_cut, &m->max_speed})
    *x = num();
  return ok ? p : nullptr;
}

}  // namespace scw::tuning
