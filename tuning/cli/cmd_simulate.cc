// scw simulate — one closed-loop run of a scenario with a trace and a summary.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "params/io/atomic_file.h"
#include "params/io/csv.h"
#include "params/io/load.h"
#include "params/io/sha256.h"
#include "params/io/test_fault.h"
#include "params/io/write.h"
#include "tuning/cli/command.h"
#include "tuning/cli/options.h"
#include "tuning/cli/progress.h"
#include "tuning/cli/revision.h"  // generated: SCW_GIT_REVISION
#include "tuning/replay/controller_log.h"
#include "tuning/replay/log_setup.h"
#include "tuning/sim/closed_loop.h"
#include "tuning/sim/plant_choice.h"
#include "tuning/sim/run_summary.h"
#include "tuning/sim/scenario.h"

namespace scw::cli {
namespace {

struct SimulateOptions {
  std::string scenario, stability, trace, summary, controller_log;
  std::vector<std::string> overrides;
  bool print = false;
  std::string progress = "auto";
};

/// "926×" for fast runs, "0.84×" for slow ones.
std::string RealTimeFactor(double simulated_s, double wall_s) {
  char buf[32];
  const double f = wall_s > 0.0 ? simulated_s / wall_s : 0.0;
  std::snprintf(buf, sizeof buf, f >= 10.0 ? "%.0f×" : "%.2g×", f);
  return buf;
}

constexpr const char* kTraceMetaSuffix = ".meta.yaml";

/// `TRACE.meta.yaml`: what the trace alone does not say (plot titles, provenance): the scenario,
/// its overrides, the parameter files, the program that wrote it and how the run ended. Beside the
/// trace, so the trace itself stays one CSV table.
std::string TraceMeta(const SimulateOptions& o, const params::ScenarioParams& spec,
                      const std::string& track_name, const std::string& summary_yaml) {
  namespace fs = std::filesystem;
  auto quoted = [](const std::string& text) {
    std::string q = "\"";
    for (const char c : text) {
      if (c == '"' || c == '\\') q += '\\';
      q += c;
    }
    return q + "\"";
  };
  auto file_or = [&](const std::string& path, const char* none) {
    return path.empty() ? std::string(none) : quoted(fs::absolute(path).string());
  };
  std::string text = "# scw simulate: what the trace " + fs::path(o.trace).filename().string() +
                     " records (experiments/plot_trace.py reads it)\n";
  text += "scenario: " + quoted(spec.name) + "\n";
  text += "scenario_file: " + file_or(o.scenario, "built-in") + "\n";
  text += "overrides: [";
  for (std::size_t i = 0; i < o.overrides.size(); ++i)
    text += (i ? ", " : "") + quoted(o.overrides[i]);
  text += "]\n";
  text += "stability: " + file_or(spec.stability, "built-in (the car's shipped set)") + "\n";
  if (!spec.stability.empty()) {
    std::string sha;
    try {
      sha = io::Sha256Hex(params::ReadTextFile(spec.stability));
    } catch (const std::exception&) {
    }
    if (!sha.empty()) text += "stability_sha256: " + sha + "\n";
  }
  text +=
      "vehicle: " + (spec.vehicle.empty() ? std::string("built-in") : quoted(spec.vehicle)) + "\n";
  text += "track: " + (spec.track.empty() ? std::string("built-in") : quoted(spec.track)) + "\n";
  text += "track_name: " + quoted(track_name) + "\n";
  text += "motion_controller: " + quoted(spec.motion.controller) + "\n";
  text += "gg_scale: " + params::FormatNumber(spec.gg_scale) + "\n";
  text += "laps: " + std::to_string(spec.laps) + "\n";
  text += std::string("scw: \"") + SCW_VERSION + " (git revision " + SCW_GIT_REVISION + ")\"\n";
  text += "# how the run ended (as --summary)\n";
  std::istringstream lines(summary_yaml);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("scenario:", 0) != 0) text += line + "\n";
  return text;
}

int RunSimulate(const SimulateOptions& o) {
  namespace fs = std::filesystem;
  RefuseRepeatedKeys("scw simulate", "--set", o.overrides);
  RefuseSharedOutputs(
      "scw simulate",
      {{"--trace", o.trace},
       {"--trace (its " + std::string(kTraceMetaSuffix) + ")",
        o.trace.empty() ? std::string() : o.trace + std::string(kTraceMetaSuffix)},
       {"--summary", o.summary},
       {"--controller-log", o.controller_log},
       {"--controller-log (its .setup.yaml)",
        o.controller_log.empty() ? std::string()
                                 : tuning::replay::SetupPathFor(o.controller_log)}});
  params::ScenarioParams spec = o.scenario.empty() ? tuning::DefaultScenario(o.overrides)
                                                   : tuning::LoadScenario(o.scenario, o.overrides);
  const std::string base =
      o.scenario.empty() ? std::string() : fs::path(o.scenario).parent_path().string();
  if (!o.stability.empty()) spec.stability = fs::absolute(o.stability).string();
  if (o.print) {
    std::cout << params::ToPlainYaml(spec);
    return kExitOk;
  }
  ProgressLine progress(o.progress);
  progress.Update({"prepare", 0, 1, "scenario (racing line, velocity profile)", "", -1.0});
  const auto t0 = std::chrono::steady_clock::now();
  const tuning::ResolvedScenario sc =
      tuning::Resolve(spec, base, o.scenario.empty() ? "built-in" : o.scenario);
  const auto t1 = std::chrono::steady_clock::now();
  for (const std::string& n : tuning::PlantNotes(spec.plant.model, sc.plant_vehicle))
    std::cerr << "note: plant.model=" << spec.plant.model << ": " << n << '\n';
  std::unique_ptr<io::CsvWriter> trace;
  if (!o.trace.empty()) trace = std::make_unique<io::CsvWriter>(o.trace, tuning::TraceHeader());
  std::unique_ptr<tuning::replay::ControllerLogWriter> log;
  if (!o.controller_log.empty())
    log = std::make_unique<tuning::replay::ControllerLogWriter>(o.controller_log);
  tuning::RunOptions ro;
  ro.trace = trace.get();
  controller::StabilityInput log_row;  // written with the loads the controller used
  if (log) {
    ro.on_controller_input = [&](const controller::StabilityInput& in) { log_row = in; };
    ro.on_controller_output = [&](const controller::StabilityOutput& out) {
      log->Write(log_row, out);
    };
  }
  {
    // Tests interrupt the run here, at a defined step (output_targets_test).
    auto inner = std::move(ro.on_controller_input);
    long steps = 0;
    ro.on_controller_input = [inner, steps](const controller::StabilityInput& in) mutable {
      if (inner) inner(in);
      io::TestFaultPoint("simulate-step", ++steps);
    };
  }
  if (progress.enabled()) {
    // By simulated time; the laps at the reference pace are the expected total.
    auto inner = std::move(ro.on_controller_input);
    const double lap_s = sc.ideal_lap_time;
    const int laps = spec.laps;
    double next_t = 0.0;
    ro.on_controller_input = [&progress, inner, lap_s, laps,
                              next_t](const controller::StabilityInput& in) mutable {
      if (inner) inner(in);
      if (in.t < next_t) return;
      next_t = in.t + 0.5;
      const int lap = std::min(laps, 1 + static_cast<int>(in.t / std::max(lap_s, 1e-3)));
      progress.Update({"simulate", in.t, lap_s * laps, "s simulated",
                       "lap " + std::to_string(lap) + "/" + std::to_string(laps), -1.0});
    };
  }
  const tuning::RunMetrics m = tuning::RunClosedLoop(sc, sc.stability, ro);
  // The console and the trace's meta file name the track: "scenario default" alone does not say
  // that --set track=monza drove Monza.
  const std::string track_name = sc.track->name();
  const auto t2 = std::chrono::steady_clock::now();
  progress.Finish();
  if (trace) {
    trace->Commit();
    if (o.trace != "-")
      io::WriteFileAtomic(o.trace + std::string(kTraceMetaSuffix),
                          TraceMeta(o, spec, track_name, tuning::RunSummaryYaml(spec.name, m)));
  }
  if (log &&
      tuning::replay::CommitWithSetup(*log, tuning::replay::ClosedLoopSetup(sc, sc.stability))
          .empty())
    std::cerr << "note: no setup file for a controller log written to " << o.controller_log
              << " (scw replay needs --vehicle FILE to reproduce the run's vehicle constants)\n";
  if (!o.summary.empty()) io::WriteFileAtomic(o.summary, tuning::RunSummaryYaml(spec.name, m));
  std::cout << tuning::FormatRunSummary(spec.name + " on " + track_name, m);
  const double sim_s = std::chrono::duration<double>(t2 - t1).count();
  char line[768];
  // What "ideal lap" means here (scw track line prints another one: a table's full limits).
  std::snprintf(line, sizeof line,
                "reference: ideal lap %.2f s, the speed profile the car is asked to drive (the "
                "vehicle's own g-g-v\n  envelope x GG %s x limit_fraction %s%s; at the envelope's "
                "full limits %.2f s; scw track line's\n  \"ideal lap time\" uses a representative "
                "table at its full limits); prepared in %.2f s\nrun: %.2f s simulated in %.2f s "
                "(%s real time)\n",
                sc.ideal_lap_time, params::FormatNumber(spec.gg_scale).c_str(),
                params::FormatNumber(spec.limit_fraction).c_str(),
                tuning::PmpcWithinProvidedLimits(spec)
                    ? (" x the PMPC's target_fraction " +
                       params::FormatNumber(spec.motion.pmpc.target_fraction))
                          .c_str()
                    : "",
                sc.limit_lap_time, std::chrono::duration<double>(t1 - t0).count(), m.time, sim_s,
                RealTimeFactor(m.time, sim_s).c_str());
  std::cerr << line;
  return m.aborted() ? kExitFailed : kExitOk;
}

void AddSimulate(CLI::App& app) {
  auto o = std::make_shared<SimulateOptions>();
  auto* cmd = app.add_subcommand(
      "simulate",
      "Run one closed-loop scenario (built-in default: Yas Marina North, EAV24-class "
      "car, pure pursuit, the car's stability parameters, 3 laps)");
  cmd->add_option("--scenario", o->scenario, "Scenario file (params/scenarios/*.yaml)");
  cmd->add_option("--set", o->overrides, "Override a scenario key, e.g. --set gg_scale=1.3")
      ->take_all();
  cmd->add_option("--stability", o->stability,
                  "Stability params file (car's ROS 2 layout); overrides the scenario's");
  cmd->add_option("--trace", o->trace,
                  "Write the trace CSV (one column per signal, docs/scenarios.md), and next to it "
                  "TRACE.meta.yaml: the scenario, overrides and parameter files of the run");
  cmd->add_option("--summary", o->summary, "Write the run summary (YAML)");
  cmd->add_option("--controller-log", o->controller_log,
                  "Write the stability controller's inputs in the replay log format, and next to "
                  "it CSV.setup.yaml with the vehicle constants and subsystem switches it used "
                  "(docs/replay.md); scw replay reproduces the run's controller outputs");
  cmd->add_flag("--print-scenario", o->print,
                "Print the scenario (with the overrides applied) as YAML and exit");
  AddProgressOption(cmd, &o->progress);
  cmd->callback([o] { SetExitCode(RunSimulate(*o)); });
}

const CommandRegistrar kRegistrar(20, &AddSimulate);

}  // namespace
}  // namespace scw::cli
