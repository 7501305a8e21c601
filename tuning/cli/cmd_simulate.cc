// scw simulate — one closed-loop run of a scenario with a trace and a summary.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>

#include "params/io/load.h"
#include "params/io/write.h"
#include "tuning/cli/command.h"
#include "tuning/closed_loop.h"
#include "tuning/csv_writer.h"
#include "tuning/replay/controller_log.h"
#include "tuning/report.h"
#include "tuning/scenario.h"

namespace scw::cli {
namespace {

struct SimulateOptions {
  std::string scenario, stability, trace, summary, controller_log;
  std::vector<std::string> overrides;
  bool print = false;
};

int RunSimulate(const SimulateOptions& o) {
  namespace fs = std::filesystem;
  params::ScenarioParams spec = o.scenario.empty() ? tuning::DefaultScenario(o.overrides)
                                                   : tuning::LoadScenario(o.scenario, o.overrides);
  const std::string base =
      o.scenario.empty() ? std::string() : fs::path(o.scenario).parent_path().string();
  if (!o.stability.empty()) spec.stability = fs::absolute(o.stability).string();
  if (o.print) {
    std::cout << params::ToPlainYaml(spec);
    return kExitOk;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const tuning::ResolvedScenario sc =
      tuning::Resolve(spec, base, o.scenario.empty() ? "built-in" : o.scenario);
  const auto t1 = std::chrono::steady_clock::now();
  std::unique_ptr<tuning::CsvWriter> trace;
  if (!o.trace.empty()) trace = std::make_unique<tuning::CsvWriter>(o.trace, tuning::TraceHeader());
  std::unique_ptr<tuning::ControllerLogWriter> log;
  if (!o.controller_log.empty())
    log = std::make_unique<tuning::ControllerLogWriter>(o.controller_log);
  tuning::RunOptions ro;
  ro.trace = trace.get();
  if (log) ro.on_controller_input = [&](const controller::StabilityInput& in) { log->Write(in); };
  const tuning::RunMetrics m = tuning::RunClosedLoop(sc, sc.stability, ro);
  const auto t2 = std::chrono::steady_clock::now();
  if (trace) trace->Commit();
  if (log) log->Commit();
  if (!o.summary.empty()) params::WriteFileAtomic(o.summary, tuning::RunSummaryYaml(spec.name, m));
  std::cout << tuning::FormatRunSummary(spec.name, m);
  const double sim_s = std::chrono::duration<double>(t2 - t1).count();
  std::cerr << "reference: ideal lap " << sc.ideal_lap_time << " s at GG " << spec.gg_scale
            << " x limit fraction " << spec.limit_fraction
            << " (at the plant's full limits: " << sc.limit_lap_time << " s)"
            << " (prepared in " << std::chrono::duration<double>(t1 - t0).count()
            << " s); run: " << m.time << " s simulated in " << sim_s << " s ("
            << (sim_s > 0 ? m.time / sim_s : 0.0) << "x real time)\n";
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
  cmd->add_option("--trace", o->trace, "Write the trace CSV (one column per signal)");
  cmd->add_option("--summary", o->summary, "Write the run summary (YAML)");
  cmd->add_option("--controller-log", o->controller_log,
                  "Write the stability controller's inputs in the replay log format "
                  "(docs/replay.md); scw replay reproduces the run's controller outputs");
  cmd->add_flag("--print-scenario", o->print,
                "Print the scenario (with the overrides applied) as YAML and exit");
  cmd->callback([o] { SetExitCode(RunSimulate(*o)); });
}

const CommandRegistrar kRegistrar(20, &AddSimulate);

}  // namespace
}  // namespace scw::cli
