// scw track info|line — the track and its reference trajectory (racing line + velocity profile).
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "controller/planning/racing_line.h"
#include "controller/planning/velocity_profile.h"
#include "params/io/atomic_file.h"
#include "params/io/write.h"
#include "plant/track/builtin_tracks.h"
#include "plant/track/corners.h"
#include "tuning/cli/command.h"
#include "tuning/cli/options.h"
#include "tuning/sim/track_csv.h"

namespace scw::cli {
namespace {

struct TrackOptions {
  std::string track, ggv, raceline, out;
  double gg_scale = 1.0;
  double ggv_exponent = 2.0;
  double margin = 2.0;
  double v_max = 90.0;
};

std::string Fixed(double x, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << x;
  return s.str();
}

int Info(const TrackOptions& o) {
  const plant::Track t = tuning::LoadTrackFile(o.track);
  double wmin = 1e9, wmax = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double w = t.width_left()[i] + t.width_right()[i];
    wmin = std::min(wmin, w);
    wmax = std::max(wmax, w);
  }
  const bool built_in = o.track.empty() || plant::BuiltInTrack(o.track).has_value();
  std::cout << "track:   " << t.name() << (built_in ? " (built-in)" : "") << '\n'
            << "length:  " << std::fixed << std::setprecision(1) << t.length() << " m, "
            << (t.total_turning() > 0 ? "anticlockwise" : "clockwise") << ", " << t.size()
            << " nodes at " << std::setprecision(3) << t.step() << " m\n"
            << "width:   " << std::setprecision(1) << wmin << " - " << wmax << " m\n";
  const std::vector<plant::Corner> corners = plant::FindCorners(t);
  // A corner covers its nodes and the node spacing after the last one, so a corner of one node
  // is one spacing long, not zero; a corner over the start line ends at a smaller s than it
  // begins, and its length is measured forward across s = 0.
  std::cout << "corners: " << corners.size()
            << ", in driving order from the start line. A corner: nodes that curve one way with\n"
               "  a radius below 250 m, joined across straighter stretches under 20 m; it spans "
               "its nodes\n  plus one node spacing. Scenario events name corners by these "
               "numbers (events.*.corner = N:\n  the apex of corner N, plus s).\n"
               "   #  dir    from [m]   to [m]  length [m]  min R [m]  apex at [m]  note\n";
  int flagged = 0;
  for (const plant::Corner& c : corners) {
    const double length = plant::CornerLength(c, t);
    const double to = t.Wrap(c.s_to + t.step());
    std::string note;
    auto add = [&](const std::string& what) { note += (note.empty() ? "" : "; ") + what; };
    if (c.s_to < c.s_from) add("spans the start line");
    if (plant::IsShortCorner(c, t))
      add("short: only " + Fixed(length, 1) + " m below 250 m radius");
    if (plant::IsKink(c)) add("kink: min R above " + Fixed(plant::kKinkRadius, 0) + " m");
    flagged += note.find("short") != std::string::npos || note.find("kink") != std::string::npos;
    std::cout << std::setw(4) << c.number << "  " << (c.left ? "left " : "right") << std::setw(11)
              << std::setprecision(1) << c.s_from << std::setw(9) << to << std::setw(12) << length
              << std::setw(11) << c.min_radius << std::setw(13) << c.s_apex
              << (note.empty() ? "" : "  " + note) << '\n';
  }
  if (flagged > 0)
    std::cout << "note: " << flagged
              << " corner(s) marked short or kink are counted by the rule above although a\n"
                 "  driver may not call them corners; they keep their numbers, so the corner "
                 "numbers of\n  scenario files stay valid.\n";
  return kExitOk;
}

int Line(const TrackOptions& o) {
  const plant::Track t = tuning::LoadTrackFile(o.track);
  const controller::planning::GgvTable ggv = o.ggv.empty()
                                                 ? controller::planning::RepresentativeGgv()
                                                 : tuning::LoadGgvCsv(o.ggv, o.ggv_exponent);
  controller::planning::RacingLine rl = [&] {
    if (!o.raceline.empty()) return tuning::LoadRacingLine(o.raceline, t);
    controller::planning::RacingLineOptions ro;
    ro.margin = o.margin;
    return controller::planning::MinimumCurvatureLine(t, ro);
  }();
  if (o.raceline.empty())
    std::cerr << "racing line: minimum curvature, " << rl.offset.size() << " offsets, "
              << rl.evaluations << " evaluations, " << Fixed(rl.seconds, 2) << " s (" << rl.status
              << ")\n";
  controller::planning::VelocityProfileOptions vo;
  vo.gg_scale = o.gg_scale;
  vo.v_max = o.v_max;
  const controller::planning::ReferenceTrajectory r =
      controller::planning::ComputeVelocityProfile(rl.line, ggv, vo);
  std::ostringstream csv;
  csv << "s_m,x_m,y_m,psi_rad,kappa_radpm,v_mps,ax_mps2,ay_mps2,t_s\n";
  using params::FormatNumber;
  for (std::size_t i = 0; i < r.size(); ++i)
    csv << FormatNumber(r.s[i]) << ',' << FormatNumber(r.x[i]) << ',' << FormatNumber(r.y[i]) << ','
        << FormatNumber(r.psi[i]) << ',' << FormatNumber(r.kappa[i]) << ',' << FormatNumber(r.v[i])
        << ',' << FormatNumber(r.a_x[i]) << ',' << FormatNumber(r.a_y[i]) << ','
        << FormatNumber(r.t[i]) << '\n';
  try {
    io::WriteFileAtomic(o.out, csv.str());
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
    return kExitFailed;
  }
  double vmin = 1e9, vmax = 0.0;
  for (double v : r.v) {
    vmin = std::min(vmin, v);
    vmax = std::max(vmax, v);
  }
  // Two "ideal laps" exist: this one (a table's full limits) and scw simulate's reference (the
  // simulated car's own envelope x GG x limit_fraction). Say which this is.
  std::cout << std::fixed << std::setprecision(2) << "ideal lap time: " << r.lap_time << " s (GG "
            << params::FormatNumber(o.gg_scale) << ", line " << std::setprecision(1) << r.length
            << " m, v " << vmin << " - " << vmax << " m/s)\n"
            << "  = the velocity profile on this line at the full limits of "
            << (o.ggv.empty() ? "a representative AV-21/EAV g-g-v\n    table (--ggv for another)"
                              : "the g-g-v table\n    " + o.ggv)
            << " x GG " << params::FormatNumber(o.gg_scale) << ", up to "
            << params::FormatNumber(o.v_max)
            << " m/s. It is not the simulated car's: scw simulate\n    plans on the vehicle's "
               "own envelope x GG x limit_fraction (0.7 by default) and reports that\n    plan "
               "as its \"ideal lap\", a different number.\n"
            << "wrote " << o.out << '\n';
  return kExitOk;
}

void AddTrack(CLI::App& app) {
  auto* cmd = app.add_subcommand("track", "Inspect a track and compute its reference trajectory");
  cmd->require_subcommand(1, 1);
  auto o = std::make_shared<TrackOptions>();
  const char* track_help =
      "Track: a built-in name (yas_north, monza), a *.yaml piecewise definition or a *.csv centre "
      "line (racetrack-database or Track3D); default: the built-in Yas Marina North";

  auto* info = cmd->add_subcommand("info",
                                   "Length, width range and the corners with their "
                                   "minimum radius");
  info->add_option("--track", o->track, track_help);
  info->callback([o] { SetExitCode(Info(*o)); });

  auto* line = cmd->add_subcommand(
      "line",
      "Minimum-curvature racing line and forward-backward g-g-v velocity profile; writes a CSV "
      "(s_m,x_m,y_m,psi_rad,kappa_radpm,v_mps,ax_mps2,ay_mps2,t_s) and prints the ideal lap time");
  line->add_option("--track", o->track, track_help);
  // Kebab case like every other option; --gg_scale (the scenario key's spelling) still works.
  NumberIn(line->add_option("--gg-scale", o->gg_scale,
                            "Acceleration scaling GG (multiplies every limit; the scenario key "
                            "gg_scale)"),
           0.05, 5.0);
  NumberIn(AddHiddenAlias(line, "--gg_scale", o->gg_scale), 0.05, 5.0);
  line->add_option("--ggv", o->ggv,
                   "g-g-v table CSV: v_mps,ay_max_mps2,ax_drive_max_mps2,ax_brake_max_mps2 "
                   "(default: a representative AV-21/EAV table)");
  NumberIn(line->add_option("--ggv-exponent", o->ggv_exponent,
                            "Combination exponent p of --ggv (1 diamond, 2 ellipse)"),
           1.0, 10.0);
  line->add_option("--raceline", o->raceline,
                   "Use this raceline instead of optimising (x_m,y_m or s_opt,n_opt CSV)");
  NumberIn(line->add_option("--margin", o->margin, "Distance kept from each track edge [m]"), 0.0,
           20.0);
  NumberIn(line->add_option("--v-max", o->v_max, "Top speed [m/s]"), 5.0, 150.0);
  line->add_option("-o,--output", o->out, "Output CSV")->required();
  line->callback([o] { SetExitCode(Line(*o)); });
}

const CommandRegistrar kReg(30, &AddTrack);

}  // namespace
}  // namespace scw::cli
