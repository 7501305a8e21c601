#include "tuning/metrics.h"

#include <algorithm>
#include <cmath>
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

}  // namespace scw::tuning
