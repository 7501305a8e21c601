#include "tuning/sim/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <stdexcept>

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

namespace {

using params::OutputMeta;

/// Writes each member: integers in decimal, doubles as %a, the laps as count then values.
struct Encoder {
  std::string out;
  void Integer(long x) { out += " " + std::to_string(x); }
  void Output(const RunStatus& s, const OutputMeta&) { Integer(static_cast<long>(s)); }
  void Output(const int& x, const OutputMeta&) { Integer(x); }
  void Output(const double& x, const OutputMeta&) {
    char buf[64];
    std::snprintf(buf, sizeof buf, " %a", x);
    out += buf;
  }
  void Output(const std::vector<double>& xs, const OutputMeta& meta) {
    Integer(static_cast<long>(xs.size()));
    for (const double& x : xs) Output(x, meta);
  }
};

/// Reads what Encoder wrote; `ok` turns false at the first unreadable or out-of-range item.
struct Decoder {
  const char* p = nullptr;
  bool ok = true;
  long Integer() {
    char* end = nullptr;
    const long x = std::strtol(p, &end, 10);
    if (end == p) ok = false;
    p = end;
    return x;
  }
  void Output(RunStatus& s, const OutputMeta&) {
    const long x = Integer();
    if (x < 0 || x > static_cast<long>(RunStatus::kInvalidParams)) ok = false;
    if (ok) s = static_cast<RunStatus>(x);
  }
  void Output(int& x, const OutputMeta&) { x = static_cast<int>(Integer()); }
  void Output(double& x, const OutputMeta&) {
    char* end = nullptr;
    x = std::strtod(p, &end);
    if (end == p) ok = false;
    p = end;
  }
  void Output(std::vector<double>& xs, const OutputMeta& meta) {
    const long n = Integer();
    if (n < 0 || n > 100000) ok = false;
    if (!ok) return;
    xs.resize(static_cast<std::size_t>(n));
    for (double& x : xs) Output(x, meta);
  }
};

/// Finds one member by key and renders it.
struct Finder {
  std::string_view key;
  bool found = false;
  MetricValue value;
  void Output(const RunStatus&, const OutputMeta&) {}
  void Output(const std::vector<double>&, const OutputMeta&) {}
  void Output(const int& x, const OutputMeta& meta) {
    if (meta.key != key) return;
    found = true;
    value.is_integer = true;
    value.integer = x;
    value.real = x;
  }
  void Output(const double& x, const OutputMeta& meta) {
    if (meta.key != key) return;
    found = true;
    value.real = params::RenderedValue(x, meta);
  }
};

struct SummaryKeys {
  std::vector<std::string_view> keys;
  void Output(const RunStatus&, const OutputMeta&) {}
  void Output(const std::vector<double>&, const OutputMeta&) { keys.push_back(kMeanLapTimeKey); }
  template <class T>
  void Output(const T&, const OutputMeta& meta) {
    if (meta.summary) keys.push_back(meta.key);
  }
};

}  // namespace

MetricValue RenderedMetric(const RunMetrics& m, std::string_view key) {
  if (key == kMeanLapTimeKey) return {.real = m.MeanLapTime()};
  if (key == kProgressKey) return {.real = m.Progress()};
  Finder f;
  f.key = key;
  RunMetrics::Visit(m, f);
  if (!f.found) throw std::logic_error("RunMetrics has no number named " + std::string(key));
  return f.value;
}

std::vector<std::string_view> SummaryMetricKeys() {
  SummaryKeys k;
  const RunMetrics m;
  RunMetrics::Visit(m, k);
  return k.keys;
}

std::string EncodeRunMetrics(const RunMetrics& m) {
  Encoder e;
  RunMetrics::Visit(m, e);
  return e.out;
}

const char* DecodeRunMetrics(const char* text, RunMetrics* m) {
  Decoder d;
  d.p = text;
  RunMetrics::Visit(*m, d);
  return d.ok ? d.p : nullptr;
}

}  // namespace scw::tuning
