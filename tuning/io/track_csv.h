// CSV readers for track data (plain text, no YAML; file I/O lives here, not in the plant): the two
// public centre-line formats of
// ../shared/data/tracks (README there) and a generic column reader for other tables.
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

/// Numeric columns of a CSV file with a header line.
struct CsvTable {
  std::vector<std::string> names;           ///< requested columns (required then optional found)
  std::vector<std::vector<double>> values;  ///< values[column][row]
  std::vector<int> lines;                   ///< source line of each row (1-based)

  /// Column by name, or nullptr.
  const std::vector<double>* Column(const std::string& name) const;
};

/// Reads `path`; `required` columns must exist, `optional` ones are read when present. Comment
/// lines (#) after the header and blank lines are skipped. Throws ConfigError listing every
/// problem (up to 20 cells).
CsvTable ReadCsvTable(const std::string& path, const std::vector<std::string>& required,
                      const std::vector<std::string>& optional = {});

/// Loads a closed centre line with widths in either public format.
plant::Track LoadTrackCsv(const std::string& path, const plant::TrackBuildOptions& options = {});

}  // namespace scw::tuning
