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

controller::planning::RacingLine LoadRacingLine(const std::string& path, const plant::Track& track,
                                                double output_step) {
  const io::CsvTable t = io::ReadCsvTable(path, {}, {"x_m", "y_m", "s_opt", "n_opt"});
  const bool xy = t.Column("x_m") && t.Column("y_m");
  const bool sn = t.Column("s_opt") && t.Column("n_opt");
  if (!xy && !sn)
    throw ConfigError(path, "line 1",
                      "not a raceline: expected columns x_m,y_m (racetrack-database) or "
                      "s_opt,n_opt (TUMRT global racing line)");
  const std::size_t rows = t.lines.size();
  if (rows < 8)
    throw ConfigError(path, "", "too few rows for a closed raceline: " + std::to_string(rows));
  controller::planning::RacelinePoints points;
  points.cartesian = xy;
  points.a = *t.Column(xy ? "x_m" : "s_opt");
  points.b = *t.Column(xy ? "y_m" : "n_opt");
  points.rows = t.lines;
  return controller::planning::RacingLineThrough(track, points, path, output_step);
}

controller::planning::GgvTable LoadGgvCsv(const std::string& path, double exponent) {
  const io::CsvTable t =
      io::ReadCsvTable(path, {"v_mps", "ay_max_mps2", "ax_drive_max_mps2", "ax_brake_max_mps2"});
  controller::planning::GgvTable g;
  g.speed = *t.Column("v_mps");
  g.ay_max = *t.Column("ay_max_mps2");
  g.ax_drive_max = *t.Column("ax_drive_max_mps2");
  g.ax_brake_max = *t.Column("ax_brake_max_mps2");
  g.SetExponent(exponent);
  g.Validate(path);
  return g;
}

}  // namespace scw::tuning
