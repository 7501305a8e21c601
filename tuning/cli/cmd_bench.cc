// scw bench --plant|--pmpc|--evaluator [...] — wall-clock speed of the simulation parts.
// Each mode flag runs one workload; without a flag: the default closed loop.
#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "params/io/csv.h"
#include "params/io/load.h"
#include "params/io/write.h"
#include "params/schema/vehicle_params.h"
#include "plant/vehicle/maneuver.h"
#include "plant/vehicle/vehicle.h"
#include "tuning/cli/command.h"
#include "tuning/cli/options.h"
#include "tuning/exec/mpi_backend.h"
#include "tuning/optim/evaluator.h"
#include "tuning/optim/plant_step_check.h"
#include "tuning/sim/closed_loop.h"
#include "tuning/sim/plant_choice.h"
#include "tuning/sim/prep_cache.h"
#include "tuning/sim/scenario.h"

namespace scw::cli {
namespace {

struct BenchOptions {
  bool evaluator = false;
  bool pmpc = false;
  int evaluations = 4;
  std::string scenarios;    ///< --evaluator: scenario set file ("" = the built-in default set)
  std::string job_times;    ///< --evaluator: per-job wall times CSV
  double plant_step = 0.0;  ///< --evaluator: the scenarios' plant_step (0: the vehicles' own)
  std::string vehicle;
  std::string plant;  ///< --plant[=scw|ocd|both]: the plant alone ("": not asked for)
  double duration = 600.0;
  int repeat = 3;
};

// The machine line of every figure: the CPU model, the memory allocator in use (the MPC's
// speed depends on it; top-level CMakeLists, SCW_TCMALLOC): tcmalloc when its library is loaded
// (linked, or preloaded), else glibc's; and whether the build is profile-guided (SCW_PGO) and
// link-time optimised (SCW_LTO).
std::string CpuModel() {
  const std::string build = std::string(SCW_BUILD_PGO ? ", build PGO" : ", build without PGO") +
                            (SCW_BUILD_LTO ? "+LTO" : "");
  std::ifstream in("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  using TcVersion = const char* (*)(int*, int*, const char**);
  if (void* f = dlsym(RTLD_DEFAULT, "tc_version")) {
    int major = 0, minor = 0;
    const char* patch = "";
    return model + ", allocator " + reinterpret_cast<TcVersion>(f)(&major, &minor, &patch) + build;
  }
  return model + ", allocator glibc" + build;
}

// The plant alone, single thread: the reference manoeuvre (plant/vehicle/maneuver.h) from rest,
// best of `repeat` runs (the machine is shared; the best run is the least disturbed one). In a
// build with Open-Car-Dynamics the same manoeuvre also runs on it, the runs of the two plants
// alternating, and the ratio of their real-time factors is printed (docs/ocd-plant.md).
struct PlantTiming {
  double best = 1e300;  ///< [s] wall time of the fastest run
  plant::ManeuverSummary sum;
};

template <class Plant>
void TimeOnce(const Plant& v, double duration, PlantTiming* t) {
  auto s = v.MakeState();
  const auto t0 = std::chrono::steady_clock::now();
  t->sum = plant::RunReferenceManeuverOn(v, duration, &s);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  t->best = std::min(t->best, wall);
}

int BenchPlant(const BenchOptions& o) {
  const params::VehicleParams p = o.vehicle.empty()
                                      ? params::VehicleParams{}
                                      : params::LoadPlainFile<params::VehicleParams>(o.vehicle);
  const plant::Vehicle v(p);
#if SCW_WITH_OCD
  std::optional<plant::ocd::OcdVehicle> ocd;
  if (o.plant != "scw") ocd.emplace(p);
#else
  if (o.plant == "ocd") throw ConfigError("scw bench", "--plant=ocd", tuning::NoOcdMessage());
#endif
  PlantTiming scw, other;
  for (int r = 0; r < o.repeat; ++r) {
    if (o.plant != "ocd") TimeOnce(v, o.duration, &scw);
#if SCW_WITH_OCD
    if (ocd) TimeOnce(*ocd, o.duration, &other);
#endif
  }
  const auto report = [&](const char* model, const PlantTiming& t) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "plant '%s' (%s), reference manoeuvre, %.0f s simulated, %ld steps of %.3g ms, "
                  "1 thread, best of %d\n"
                  "cpu: %s\n"
                  "wall time: %.4f s, %.3f us/step (distance %.0f m, max |a_y| %.1f m/s^2)\n",
                  p.name.c_str(), model, t.sum.sim_time, t.sum.steps, 1e3 * v.time_step(), o.repeat,
                  CpuModel().c_str(), t.best, 1e6 * t.best / static_cast<double>(t.sum.steps),
                  t.sum.distance, t.sum.max_abs_ay);
    std::cout << buf << "real-time factor: " << static_cast<long>(t.sum.sim_time / t.best) << '\n';
    if (t.sum.status != plant::kStatusOk) {
      std::cerr << "error: the " << model << " plant run ended with status " << t.sum.status
                << '\n';
      return false;
    }
    return true;
  };
  bool ok = true;
  if (o.plant != "ocd") ok = report("scw", scw) && ok;
#if SCW_WITH_OCD
  if (ocd) ok = report("ocd: Open-Car-Dynamics", other) && ok;
  if (ocd && o.plant != "ocd") {
    const double rtf_scw = scw.sum.sim_time / scw.best, rtf_ocd = other.sum.sim_time / other.best;
    std::printf("real-time factor scw/ocd: %.1f (measured in this run, runs alternating)\n",
                rtf_scw / rtf_ocd);
  }
#else
  if (o.plant == "both")
    std::cout << "(this build has no Open-Car-Dynamics plant: scw's plant only; "
                 "docs/ocd-plant.md)\n";
#endif
  return ok ? kExitOk : kExitFailed;
}

// The default closed loop (plant + stability controller + pure pursuit + longitudinal controller)
// on the built-in scenario, 3 laps, one thread, best of `repeat` runs.
int BenchClosedLoop(const BenchOptions& o) {
  const tuning::ResolvedScenario sc = tuning::Resolve(tuning::DefaultScenario());
  double best = 1e300;
  tuning::RunMetrics m;
  for (int r = 0; r < o.repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    m = tuning::RunClosedLoop(sc, sc.stability);
    best = std::min(best,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "closed loop: built-in scenario (Yas Marina North, %d laps, %s), plant 1 kHz, "
                "controllers 100 Hz, 1 thread, best of %d\ncpu: %s\n"
                "wall time: %.4f s for %.1f s simulated (%.2f us per plant step)\n",
                sc.spec.laps, tuning::RunStatusName(m.status), o.repeat, CpuModel().c_str(), best,
                m.time, 1e6 * best / (m.time * 1000.0));
  std::cout << buf << "real-time factor: " << static_cast<long>(m.time / best) << '\n';
  return kExitOk;
}

// The point-mass MPC (motion.controller=pmpc) in the closed loop of the built-in scenario, one lap
// of Yas Marina North, one thread, best of `repeat` runs. The reference (racing line, velocity
// profile) is prepared once before the timing; a run's time includes building the controllers,
// every QP solve and the plant.
int BenchPmpc(const BenchOptions& o) {
  const tuning::ResolvedScenario sc =
      tuning::Resolve(tuning::DefaultScenario({"motion.controller=pmpc", "laps=1"}));
  double best = 1e300;
  tuning::RunMetrics m;
  for (int r = 0; r < o.repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    m = tuning::RunClosedLoop(sc, sc.stability);
    best = std::min(best,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  if (m.status != tuning::RunStatus::kCompleted) {
    std::cerr << "error: the PMPC lap ended with status " << tuning::RunStatusName(m.status)
              << '\n';
    return kExitFailed;
  }
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "pmpc closed loop: built-in scenario (Yas Marina North, 1 lap, %s, lap %.3f s), "
                "plant 1 kHz, QP every %.0f ms, 1 thread, best of %d\ncpu: %s\n"
                "wall time: %.4f s for %.1f s simulated\n",
                tuning::RunStatusName(m.status), m.lap_times.empty() ? 0.0 : m.lap_times[0],
                1e3 * sc.spec.motion.pmpc.solve_period, o.repeat, CpuModel().c_str(), best, m.time);
  std::cout << buf << "real-time factor: " << static_cast<long>(m.time / best) << '\n';
  return kExitOk;
}

// Per-job wall times of the tuning objective: each training scenario run once with the base set,
// one after another on this thread (the job lengths a scheduler across many workers must balance;
// experiments/scaling_model.py turns them into predicted speed-ups).
void WriteJobTimes(const tuning::BatchEvaluator& ev, const std::string& path) {
  io::CsvWriter csv(path, {"scenario", "kind", "status", "simulated_s", "wall_s"});
  std::vector<double> wall;
  tuning::RunOptions ro;  // as the evaluator runs them
  ro.sideslip_allowed_deg = ev.cost().sideslip_allowed_deg;
  for (const auto& sc : ev.scenarios()) {
    const auto t0 = std::chrono::steady_clock::now();
    const tuning::RunMetrics m = tuning::RunClosedLoop(sc, sc.stability, ro);
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    csv.Add(sc.spec.name);
    csv.Add(sc.spec.kind);
    csv.Add(std::string(tuning::RunStatusName(m.status)));
    csv.Add(m.time);
    csv.Add(wall.back());
    csv.EndRow();
  }
  csv.Commit();
  std::vector<double> sorted = wall;
  std::sort(sorted.begin(), sorted.end());
  double total = 0;
  for (double w : wall) total += w;
  auto q = [&](double f) { return sorted[static_cast<std::size_t>(f * (sorted.size() - 1))]; };
  std::printf(
      "job times (%zu jobs, 1 thread): total %.3f s, mean %.4f s, min %.4f, median %.4f, "
      "p90 %.4f, max %.4f s -> %s\n",
      wall.size(), total, total / static_cast<double>(wall.size()), sorted.front(), q(0.5), q(0.9),
      sorted.back(), path.c_str());
}

// Evaluations per second of the tuning objective (the training scenarios of the default set, or
// of --scenarios) with 1 and 2 threads; under mpirun, with the run's ranks × 1 thread each (run
// it with -np 1 and -np 2 for the speed-up across processes).
int BenchEvaluator(const BenchOptions& o) {
  auto set = o.scenarios.empty() ? tuning::ScenarioSet::Default()
                                 : tuning::ScenarioSet::FromFile(o.scenarios);
  if (o.plant_step > 0.0) set.training = tuning::WithPlantStep(set.training, o.plant_step);
  std::vector<params::StabilityParams> sets(static_cast<std::size_t>(o.evaluations));
  for (std::size_t i = 0; i < sets.size(); ++i)
    sets[i].ESC.kp_psi_dot = 6.0 + static_cast<double>(i);  // distinct sets
  const bool ranks = tuning::exec::mpi::Launched();
  const std::string step_note =
      o.plant_step > 0.0 ? " at plant step " + params::FormatDouble(o.plant_step) + " s" : "";
  double rate[2] = {0, 0};
  // One preparation cache for both evaluators, as a tune's evaluators share one: the second
  // evaluator's preparation time is then that of a warm cache.
  controller::planning::ReferenceCache cache(&tuning::PrepCache::Process());
  for (int threads : {1, 2}) {
    if (ranks && threads > 1) break;
    const auto t_prep = std::chrono::steady_clock::now();
    const auto ev = tuning::BatchEvaluator::FromEntries(set.training, set.base_dir, set.cost,
                                                        threads, {}, &cache);
    const double prep =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_prep).count();
    if (threads == 1 && !o.job_times.empty()) WriteJobTimes(ev, o.job_times);
    double best = 1e300;
    for (int r = 0; r < o.repeat; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      for (const auto& p : sets) ev.Evaluate(p);  // one set at a time, as the tuner asks
      best = std::min(best,
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    rate[threads - 1] = static_cast<double>(sets.size()) / best;
    const std::string workers =
        ranks ? std::to_string(tuning::exec::mpi::Ranks()) + " MPI rank(s) x 1 thread"
              : std::to_string(threads) + " thread(s)";
    std::printf(
        "evaluator: %zu scenarios per evaluation%s, %s: %.3f evaluations/s "
        "(%.1f runs/s; scenarios prepared in %.2f s)\n",
        set.training.size(), step_note.c_str(), workers.c_str(), rate[threads - 1],
        rate[threads - 1] * static_cast<double>(set.training.size()), prep);
  }
  std::printf("cpu: %s\n", CpuModel().c_str());
  if (ranks)
    std::printf("speed-up across ranks: compare with the same command under mpirun -np 1\n");
  else
    std::printf("speed-up 1 -> 2 threads: %.2fx\n", rate[1] / rate[0]);
  return kExitOk;
}

void AddBench(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "bench",
      "Measure speed (wall clock): the default closed loop on one core (no flag), the "
      "plant alone (--plant), the point-mass MPC's closed loop (--pmpc), or tuning evaluations "
      "per second (--evaluator)");
  auto o = std::make_shared<BenchOptions>();
  cmd->add_flag("--plant{both}", o->plant,
                "The plant alone driving its reference manoeuvre; prints 'real-time factor: N' "
                "per plant. --plant=scw: scw's plant; --plant=ocd: Open-Car-Dynamics "
                "(plant.model=ocd, in a build with it); --plant or --plant=both: both, their runs "
                "alternating, and the ratio of their real-time factors (scw's only where the "
                "build has no OCD)")
      ->check(CLI::IsMember({"scw", "ocd", "both"}));
  cmd->add_flag("--pmpc", o->pmpc,
                "The point-mass MPC (motion.controller=pmpc) driving one lap of the built-in "
                "scenario on one core; prints 'real-time factor: N'");
  cmd->add_flag("--evaluator", o->evaluator,
                "Tuning evaluations per second with 1 and 2 threads (training scenarios of the "
                "default set or of --scenarios); under mpirun -np N: with N ranks x 1 thread");
  WholeNumberIn(
      cmd->add_option("--evaluations", o->evaluations, "Evaluations per measurement (--evaluator)"),
      1, 1000);
  cmd->add_option("--scenarios", o->scenarios,
                  "Scenario set file for --evaluator (default: the built-in default set)");
  cmd->add_option("--job-times", o->job_times,
                  "With --evaluator: write each training scenario's wall time for one run (1 "
                  "thread) to this CSV (input of experiments/scaling_model.py)");
  NumberIn(cmd->add_option("--plant-step", o->plant_step,
                           "With --evaluator: run the scenarios at this plant step [s] (their "
                           "plant_step key, as scw tune's --search-plant-step; 0: the vehicles' "
                           "own step)"),
           0.0, 0.005);
  cmd->add_option("--vehicle", o->vehicle, "Vehicle file (default: built-in EAV24 set)");
  NumberIn(cmd->add_option("--duration", o->duration, "Simulated time per run [s]"), 1.0, 1e6);
  WholeNumberIn(cmd->add_option("--repeat", o->repeat, "Runs; the fastest is reported"), 1, 100);
  cmd->callback([o] {
    if (!o->plant.empty()) return SetExitCode(BenchPlant(*o));
    if (o->evaluator) return SetExitCode(BenchEvaluator(*o));
    if (o->pmpc) return SetExitCode(BenchPmpc(*o));
    SetExitCode(BenchClosedLoop(*o));
  });
}

const CommandRegistrar kRegistrar(90, &AddBench);

}  // namespace
}  // namespace scw::cli
