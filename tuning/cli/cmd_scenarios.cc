// scw scenarios init — a starter scenario set for a track of the user's own
// (tuning/sim/starter_set.h: which events go to which corners, and why).
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>

#include "params/io/atomic_file.h"
#include "params/io/load.h"
#include "params/io/write.h"
#include "params/schema/field.h"
#include "params/schema/vehicle_params.h"
#include "tuning/cli/command.h"
#include "tuning/cli/options.h"
#include "tuning/sim/scenario_set.h"
#include "tuning/sim/starter_set.h"
#include "tuning/sim/track_csv.h"

namespace scw::cli {
namespace {

namespace fs = std::filesystem;

struct ScenariosOptions {
  std::string track, vehicle, out, name;
  int training_corners = 2;
  int held_out_corners = 1;
  bool force = false;
};

bool IsFile(const std::string& ref) { return fs::path(ref).has_extension(); }

/// `file` as the set file at `out` names it: relative to the set's folder (a scenario set resolves
/// its scenarios' files there), absolute where no relative path exists.
std::string RefFromSet(const std::string& file, const std::string& out) {
  const fs::path target = fs::weakly_canonical(fs::absolute(file));
  const fs::path dir = out == "-" ? fs::current_path() : fs::absolute(out).parent_path();
  const fs::path rel = target.lexically_relative(fs::weakly_canonical(dir));
  return rel.empty() ? target.string() : rel.generic_string();
}

int Init(const ScenariosOptions& o) {
  if (o.out != "-" && !o.force && fs::exists(o.out))
    throw ConfigError("scw scenarios init", "-o",
                      o.out +
                          " exists; a set is meant to be edited, so it is not replaced: "
                          "choose another name or add --force");
  // Read the files first: bad input is reported before anything is written.
  const plant::Track track = tuning::LoadTrackFile(o.track);
  if (!o.vehicle.empty()) params::LoadPlainFile<params::VehicleParams>(o.vehicle);

  tuning::StarterSetOptions so;
  so.name = !o.name.empty() ? o.name : fs::path(o.track).stem().string() + "_starter";
  so.track_ref = IsFile(o.track) ? RefFromSet(o.track, o.out) : o.track;
  so.vehicle_ref = o.vehicle.empty() ? "" : RefFromSet(o.vehicle, o.out);
  so.training_corners = o.training_corners;
  so.held_out_corners = o.held_out_corners;
  const tuning::StarterSet starter = tuning::MakeStarterSet(track, so);
  const std::string text = tuning::StarterSetYaml(starter, track);

  // The file must load as scw tune loads it, with every scenario's overrides, from where it is
  // written (its track and vehicle named relative to its folder).
  const std::string as_file = o.out == "-" ? "starter_set.yaml" : o.out;
  const tuning::ScenarioSet set = tuning::ScenarioSet::FromYamlText(text, as_file);
  for (const auto* list : {&set.training, &set.held_out})
    for (const tuning::ScenarioEntry& e : *list) tuning::LoadEntry(e, set.base_dir);

  io::WriteFileAtomic(o.out, text);
  std::ostream& info = o.out == "-" ? std::cerr : std::cout;
  info << "track:     " << track.name() << " (" << std::fixed << std::setprecision(1)
       << track.length() << " m, " << starter.corners.size() << " corners; scw track info --track "
       << o.track << " lists them)\n";
  if (!starter.minor.empty()) {
    info << "left out:  corners";
    for (int c : starter.minor) info << " " << c;
    info << " (short or kink)\n";
  }
  info << "event           training    held out   chosen by\n";
  auto corners = [](const std::vector<int>& cs) {
    std::string s;
    for (int c : cs) s += (s.empty() ? "c" : ",c") + std::to_string(c);
    return s.empty() ? std::string("-") : s;
  };
  for (const tuning::StarterEventPlaces& p : starter.places) {
    info << std::left << std::setw(16) << p.event << std::setw(12) << corners(p.training)
         << std::setw(11) << corners(p.held_out) << p.rule;
    for (const auto& n : p.note) info << "; " << n;
    info << '\n' << std::right;
  }
  info << "wrote " << (o.out == "-" ? std::string("the set to stdout") : o.out) << ": "
       << set.training.size() << " training and " << set.held_out.size()
       << " held-out scenarios (clean laps at GG 1.1, 1.2; held out 1.15)\n"
       << "next:  scw tune --scenarios " << (o.out == "-" ? std::string("SET") : o.out)
       << " --check-set\n";
  return kExitOk;
}

void AddScenarios(CLI::App& app) {
  auto* cmd = app.add_subcommand("scenarios", "Write scenario sets for scw tune");
  cmd->require_subcommand(1, 1);
  auto o = std::make_shared<ScenariosOptions>();

  auto* init = cmd->add_subcommand(
      "init",
      "Write a starter scenario set for a track: clean laps, and power-on, late-braking and "
      "rear-grip-loss events at the track's corners (numbered as scw track info numbers them), "
      "with held-out scenarios at other corners; the set is loaded before it is written");
  init->add_option(
          "--track", o->track,
          "Track: a *.csv centre line (racetrack-database or Track3D, docs/track-files.md), "
          "a *.yaml piecewise definition or a built-in name (yas_north, monza)")
      ->required();
  init->add_option("--vehicle", o->vehicle,
                   "Vehicle file every scenario uses (params/vehicles/*.yaml; default: the "
                   "built-in EAV24-class car)");
  init->add_option("-o,--output", o->out,
                   "The set file to write (- for stdout); its scenarios name the track and "
                   "vehicle relative to its folder")
      ->required();
  init->add_option("--name", o->name, "Name of the set (default: the track file's name_starter)");
  WholeNumberIn(init->add_option("--training-corners", o->training_corners,
                                 "Corners per critical event in the training scenarios"),
                1, 20)
      ->capture_default_str();
  WholeNumberIn(init->add_option("--held-out-corners", o->held_out_corners,
                                 "Other corners per critical event in the held-out scenarios"),
                0, 20)
      ->capture_default_str();
  init->add_flag("--force", o->force, "Replace an existing output file");
  init->footer(
      "Which corners: power-on at the slowest corners, late braking after the longest straights,\n"
      "rear grip loss at the fastest corners; short and kink corners only when nothing else is\n"
      "left (docs/tutorial-own-track.md).");
  init->callback([o] { SetExitCode(Init(*o)); });
}

const CommandRegistrar kRegistrar(27, &AddScenarios);

}  // namespace
}  // namespace scw::cli
