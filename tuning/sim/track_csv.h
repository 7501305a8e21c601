// The CSV readers of the track and its planning inputs (plain text, no YAML; file I/O lives here,
// not in the plant or the planner), read through the one table reader io::ReadCsvTable
// (params/io/csv.h): the track's centre line in the two public formats of ../shared/data/tracks
// (README there), a given raceline and a g-g-v table.
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

#include <string>
#include <vector>

#include "controller/planning/ggv.h"
#include "controller/planning/racing_line.h"
#include "plant/track/track.h"

namespace scw::tuning {

/// Loads a closed centre line with widths in either public format.
plant::Track LoadTrackCsv(const std::string& path, const plant::TrackBuildOptions& options = {});

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
