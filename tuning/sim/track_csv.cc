#include "tuning/sim/track_csv.h"

#include <cmath>
#include <filesystem>

#include "params/io/csv.h"
#include "params/schema/field.h"

namespace scw::tuning {

using plant::Track;
using plant::TrackBuildOptions;
namespace {

std::string Where(int line, const std::string& column) {
  return "line " + std::to_string(line) + ", column " + column;
}

}  // namespace

Track LoadTrackCsv(const std::string& path, const TrackBuildOptions& options) {
  const io::CsvTable t =
      io::ReadCsvTable(path, {"x_m", "y_m", "w_tr_right_m", "w_tr_left_m"}, {"friction_scale"});
  const std::size_t rows = t.lines.size();
  if (rows < 8)
    throw ConfigError(path, "",
                      "too few rows for a closed track: " + std::to_string(rows) +
                          " data row(s), need at least 8");
  std::vector<double> wl(*t.Column("w_tr_left_m")), wr(*t.Column("w_tr_right_m"));
  Problems pr;
  for (std::size_t i = 0; i < rows; ++i) {
    wl[i] = std::abs(wl[i]);
    wr[i] = std::abs(wr[i]);
    if (wl[i] == 0.0) pr.Add(Where(t.lines[i], "w_tr_left_m"), "width must be non-zero");
    if (wr[i] == 0.0) pr.Add(Where(t.lines[i], "w_tr_right_m"), "width must be non-zero");
  }
  if (!pr.empty()) throw ConfigError(path, pr.items());
  const std::vector<double>* mu = t.Column("friction_scale");
  const std::string name = std::filesystem::path(path).stem().string();
  try {
    return Track::FromPoints(*t.Column("x_m"), *t.Column("y_m"), wl, wr,
                             mu ? *mu : std::vector<double>{}, options, name, path);
  } catch (const ConfigError& e) {
    // Name the source line for per-point problems ("point K" → "line L").
    std::vector<Problem> out;
    for (const auto& p : e.problems()) {
      Problem q = p;
      if (p.path.rfind("point ", 0) == 0) {
        const std::size_t k = std::stoul(p.path.substr(6));
        if (k < rows) q.path = "line " + std::to_string(t.lines[k]);
      } else if (p.message.find("does not close") != std::string::npos) {
        q.path = "line " + std::to_string(t.lines.back()) + " (last row) vs line " +
                 std::to_string(t.lines.front()) + " (first row)";
      }
      out.push_back(q);
    }
    throw ConfigError(path, out);
  }
}

}  // namespace scw::tuning
