#include "tuning/sim/track_csv.h"

#include <cmath>
#include <filesystem>
#include <memory>
#include <utility>

#include "params/io/csv.h"
#include "params/io/load.h"
#include "params/io/yaml_doc.h"
#include "params/schema/field.h"
#include "params/schema/track_params.h"
#include "plant/track/builtin_tracks.h"
#include "plant/track/yas_north.h"

namespace scw::tuning {

using plant::Track;
using plant::TrackBuildOptions;
namespace {

std::string Where(int line, const std::string& column) {
  return "line " + std::to_string(line) + ", column " + column;
}

enum class TrackFileKind { kBuiltIn, kCsv, kYaml };

/// The kind of a scenario's track by its name alone, before anything is read: "" or a name
/// without extension is a built-in track.
TrackFileKind TrackKindOf(const std::string& file) {
  auto ends_with = [&](const std::string& suffix) {
    return file.size() >= suffix.size() &&
           file.compare(file.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (file.empty() || !std::filesystem::path(file).has_extension()) return TrackFileKind::kBuiltIn;
  if (ends_with(".csv")) return TrackFileKind::kCsv;
  if (ends_with(".yaml") || ends_with(".yml")) return TrackFileKind::kYaml;
  throw ConfigError(file, "track", "unknown track file type (expected .csv, .yaml or .yml)");
}

/// A track file of a known kind, read once: the text is the cache's key (with the name) and what
/// the kind's reader parses; the reader builds the track in the same step.
std::shared_ptr<const Track> ReadTrackFile(const std::string& path, TrackFileKind kind,
                                           TrackBuildOptions options,
                                           controller::planning::ReferenceCache* cache) {
  const std::string text = params::ReadTextFile(path);
  auto build = [&]() -> Track {
    if (kind == TrackFileKind::kCsv) {
      const io::CsvTable t = io::ParseCsvTable(
          text, path, {"x_m", "y_m", "w_tr_right_m", "w_tr_left_m"}, {"friction_scale"});
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
      options.source_lines = t.lines;  // problems name the file's lines
      return Track::FromPoints(*t.Column("x_m"), *t.Column("y_m"), wl, wr,
                               mu ? *mu : std::vector<double>{}, options,
                               std::filesystem::path(path).stem().string(), path);
    }
    return Track::FromDefinition(params::LoadPlainText<params::TrackParams>(text, path), path);
  };
  if (cache == nullptr) return std::make_shared<const Track>(build());
  return cache->Track("file:" + path + "\n" + text, build);
}

}  // namespace

Track LoadTrackCsv(const std::string& path, const TrackBuildOptions& options) {
  return *ReadTrackFile(path, TrackFileKind::kCsv, options, nullptr);
}

ScenarioTrack LoadScenarioTrack(const std::string& track_file, const std::string& line_file,
                                controller::planning::ReferenceCache& cache) {
  ScenarioTrack out;
  const TrackFileKind kind = TrackKindOf(track_file);
  if (kind == TrackFileKind::kBuiltIn) {
    // A scenario file's directory may have been put before the name.
    const std::string name = std::filesystem::path(track_file).filename().string();
    out.track = cache.Track("built-in:" + track_file, [&] {
      if (track_file.empty()) return plant::YasNorthTrack();
      if (auto track = plant::BuiltInTrack(name)) return *std::move(track);
      throw ConfigError(track_file, "track",
                        "unknown built-in track (known: " + plant::BuiltInTrackNames() +
                            "); a track file needs the extension .csv, .yaml or .yml");
    });
  } else {
    out.track = ReadTrackFile(track_file, kind, {}, &cache);
  }
  if (!line_file.empty()) {
    out.given_line = ReadRacelinePoints(line_file);
    out.line_file = line_file;
  }
  return out;
}

plant::Track LoadTrackFile(const std::string& track_file) {
  controller::planning::ReferenceCache cache;
  return *LoadScenarioTrack(track_file, "", cache).track;
}

controller::planning::RacelinePoints ReadRacelinePoints(const std::string& path) {
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
  return points;
}

controller::planning::RacingLine LoadRacingLine(const std::string& path, const plant::Track& track,
                                                double output_step) {
  return controller::planning::RacingLineThrough(track, ReadRacelinePoints(path), path,
                                                 output_step);
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
