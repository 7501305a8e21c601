// The readers of the track files and their planning inputs (file I/O lives here, not in the plant
// or the planner): a scenario's track (built-in, CSV centre line or YAML definition) with its given
// raceline, read once at the top of the preparation (LoadScenarioTrack); the CSV tables go through
// the one table reader (params/io/csv.h): the track's centre line in the two public formats of
// ../shared/data/tracks (README there), a given raceline and a g-g-v table.
//
//   racetrack-database:  `# x_m,y_m,w_tr_right_m,w_tr_left_m` (both widths positive)
//   TUMRT Track3D:       `s_m,x_m,y_m,z_m,theta_rad,…,w_tr_right_m,w_tr_left_m,…`
//                        (w_tr_right_m negative; the first point repeated at the end)
// The format is recognised by the header line (a leading '#' is allowed): the columns are found
// by name, in any order, extra columns are ignored. Widths are taken by magnitude, so both sign
// conventions load. An optional `friction_scale` column sets μ(s). 3D columns (z, pitch, bank) are
// ignored: the plant is planar.
//
// Errors: scw::ConfigError naming the file, the line (1-based, as an editor shows it) and the
// column of every bad cell (non-numeric, NaN/inf, missing), a missing column, too few rows, or a
// loop that does not close.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "controller/planning/ggv.h"
#include "controller/planning/racing_line.h"
#include "controller/planning/reference_cache.h"
#include "plant/track/track.h"

namespace scw::tuning {

/// Loads a closed centre line with widths in either public format.
plant::Track LoadTrackCsv(const std::string& path, const plant::TrackBuildOptions& options = {});

/// The track and the given raceline's points a scenario names, read once at the top of its
/// preparation; the line through the points is planned on the track by PrepareReference.
struct ScenarioTrack {
  std::shared_ptr<const plant::Track> track;
  std::optional<controller::planning::RacelinePoints> given_line;  ///< none without a line file
  std::string line_file;  ///< the given line's file (named in its errors)
};

/// The scenario's files: `track_file` "" = Yas Marina North, a name without extension = a built-in
/// track (plant/track/builtin_tracks.h; a directory before it is ignored), *.csv = a centre line
/// (LoadTrackCsv), *.yaml / *.yml = a piecewise definition (params/schema/track_params.h). The kind
/// is decided by the name before the file is read; the file is read once and its reader builds
/// the track, shared through `cache` under the name and the file's text (a built-in under its
/// name). A non-empty `line_file` is then read as ReadRacelinePoints. Errors in this order: the
/// track's name, the track file, the line file (ConfigError naming file, line, column); a point
/// of the line off the track is PrepareReference's error, naming the line file.
ScenarioTrack LoadScenarioTrack(const std::string& track_file, const std::string& line_file,
                                controller::planning::ReferenceCache& cache);

/// A track named as in a scenario's `track` key, read as LoadScenarioTrack reads it (the same
/// rule for the kind, the same readers and errors), without a line; for `scw track`.
plant::Track LoadTrackFile(const std::string& track_file);

/// A raceline file's points: columns `x_m,y_m` (racetrack-database racelines) or `s_opt,n_opt`
/// (TUMRT global racing lines), header-detected, at least 8 rows. Throws ConfigError naming file,
/// line and column on bad input.
controller::planning::RacelinePoints ReadRacelinePoints(const std::string& path);

/// Loads a raceline file relative to `track`: columns `x_m,y_m` (racetrack-database racelines) or
/// `s_opt,n_opt` (TUMRT global racing lines), header-detected, at least 8 rows; the line through
/// them is controller::planning::RacingLineThrough's. Throws ConfigError naming file, line and
/// column on bad input.
controller::planning::RacingLine LoadRacingLine(const std::string& path, const plant::Track& track,
                                                double output_step = 1.0);

/// Reads a g-g-v table CSV with columns v_mps, ay_max_mps2, ax_drive_max_mps2, ax_brake_max_mps2
/// (header line required); `exponent` sets p. Throws ConfigError naming file, line and column.
controller::planning::GgvTable LoadGgvCsv(const std::string& path, double exponent);

}  // namespace scw::tuning
