// Reference preparation: everything the motion controllers follow, planned once per scenario
// before any run (the tuner then runs many stability parameter sets on it).
//
//   line      the minimum-curvature racing line within the track's bounds, `line_margin` from the
//             edges (racing_line.h), or the centre line, or the line through given points
//             (RacingLineThrough; a raceline file's, read by the caller: tuning/sim/track_csv.h)
//   ggv       the plant's own combined g-g-v envelope of `vehicle` with the front brake bias
//             (envelope.h), unscaled
//   path      the forward–backward velocity profile on the line at the table × `limit_scale`
//             (velocity_profile.h: the paper's GG × the scenario's limit fraction), with every
//             late-braking event applied (late_braking.h)
//   ideal_lap_time  [s] of that profile (before late braking)
//   limit_lap_time  [s] of the profile on the same line at the table's full limits
// The corridor (corridor.h) is not part of it: it is capped by the run's abort threshold, which
// may differ between runs on one reference; the motion controller's factory builds it.
//
// Inputs: `track` (plant/track/track.h), `vehicle` the car the planner plans for (the scenario's
// grip applied, or the vehicle file's nominal grip with plan_with_nominal_grip), `options` below.
// Units SI. Deterministic: the same inputs give the same reference bit for bit, with or without a
// warm cache.
//
// Cached in `cache` (reference_cache.h, owned by the caller): the optimal line per track and
// margin, the g-g-v table per vehicle and brake bias, the full-limit lap per line and table. The
// velocity profile at limit_scale and late braking are recomputed each call (a few ms).
//
// Errors: scw::ConfigError from the racing line (e.g. a track narrower than twice the margin,
// source "racing line"; a given point off the track, source `given_source`) and the g-g-v table
// as they come; a late-braking event placed at a corner the track does not have names
// `options.source` and `events.late_braking.corner`.
//
// Why planning may include the plant: it plans on the track's geometry (plant/track) and on the
// plant's quasi-steady limits (plant/vehicle/quasi_steady.h), offline, at preparation time; it
// may use NLopt (the racing line) and a lock (the cache). The car's stability controller includes
// none of it (docs/architecture.md, "What each folder may include").
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "controller/planning/ggv.h"
#include "controller/planning/path.h"
#include "controller/planning/racing_line.h"
#include "controller/planning/reference_cache.h"
#include "params/schema/event_params.h"
#include "params/schema/vehicle_params.h"
#include "plant/track/track.h"

namespace scw::controller::planning {

enum class LineKind { kOptimal, kCentreLine, kGiven };

struct ReferenceOptions {
  LineKind line = LineKind::kOptimal;
  double line_margin = 2.0;  ///< kOptimal: distance kept from each edge [m]
  /// kGiven: the points of the line to follow (e.g. a raceline file's), must be set; the line is
  /// RacingLineThrough them on the track, and its errors name `given_source`.
  std::optional<RacelinePoints> given_line;
  std::string given_source;
  double limit_scale = 1.0;  ///< factor on every limit of the table (GG × limit_fraction) [-]
  double brake_bias_front = 0.58;    ///< the car's front share of brake pressure [-]
  params::LateBraking late_braking;  ///< brake points moved later (late_braking.h)
  std::string source;                ///< named in errors about late_braking (e.g. the scenario)
};

struct PreparedReference {
  std::shared_ptr<const plant::Track> line;  ///< the line the profile was planned on
  std::shared_ptr<const Path> path;          ///< the reference with its speed profile
  std::shared_ptr<const GgvTable> ggv;       ///< the plant's table, unscaled
  double ideal_lap_time = 0.0;               ///< [s] at limit_scale
  double limit_lap_time = 0.0;               ///< [s] at the full limits
};

/// Prepares the reference of `track` for `vehicle` (see the file comment).
PreparedReference PrepareReference(const plant::Track& track, const params::VehicleParams& vehicle,
                                   const ReferenceOptions& options, ReferenceCache& cache);

}  // namespace scw::controller::planning
