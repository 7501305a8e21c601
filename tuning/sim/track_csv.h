// The track CSV reader (plain text, no YAML; file I/O lives here, not in the plant): the two
// public centre-line formats of ../shared/data/tracks (README there), read through the one table
// reader io::ReadCsvTable (params/io/csv.h).
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

#include "plant/track/track.h"

namespace scw::tuning {

/// Loads a closed centre line with widths in either public format.
plant::Track LoadTrackCsv(const std::string& path, const plant::TrackBuildOptions& options = {});

}  // namespace scw::tuning
