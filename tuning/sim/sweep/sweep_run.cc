#include "tuning/sim/sweep/sweep_run.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "params/io/csv.h"
#include "params/schema/field.h"
#include "tuning/sim/closed_loop.h"
#include "tuning/sim/parallel/mpi_backend.h"
#include "tuning/sim/parallel/parallel_for.h"
#include "tuning/sim/parallel/wire.h"
#include "tuning/sim/prep_cache.h"
#include "tuning/sim/scenario.h"
#include "tuning/sim/sweep/sweep_processes.h"
#include "tuning/sim/sweep/sweep_write.h"

namespace scw::tuning {
namespace {

namespace fs = std::filesystem;

// Resolutions on demand, each at most once; Get and Scenario may run in parallel (a thread that
// needs a resolution in flight waits for it).
class Resolutions {
 public:
  explicit Resolutions(const SweepPlan& plan)
      : plan_(plan),
        cache_(&PrepCache::Process()),
        done_(plan.resolutions.size()),
        once_(plan.resolutions.size()) {}
  const ResolvedScenario& Get(int k) {
    const auto at = static_cast<std::size_t>(k);
    std::call_once(once_[at], [&] {
      done_[at] = std::make_unique<ResolvedScenario>(
          Resolve(plan_.resolutions[at], plan_.base_dir, plan_.source, &cache_));
    });
    return *done_[at];
  }
  /// The scenario of run i: its group's resolution with the run's own spec.
  ResolvedScenario Scenario(int i) {
    const PlannedRun& run = plan_.runs[static_cast<std::size_t>(i)];
    ResolvedScenario sc = Get(run.resolution);
    sc.spec = run.spec;
    return sc;
  }

 private:
  const SweepPlan& plan_;
  controller::planning::ReferenceCache cache_;  ///< shared by the resolutions
  std::vector<std::unique_ptr<ResolvedScenario>> done_;
  std::vector<std::once_flag> once_;
};

// --- Run results between processes: the run's metrics as exact text (EncodeRunMetrics), then
// the reference's ideal lap time the same way.
std::string EncodeRun(const RunMetrics& m, double ideal_lap_time) {
  char buf[64];
  std::snprintf(buf, sizeof buf, " %a", ideal_lap_time);
  return EncodeRunMetrics(m) + buf;
}

bool DecodeRun(const char* text, RunMetrics* m, double* ideal_lap_time) {
  const char* p = DecodeRunMetrics(text, m);
  if (p == nullptr) return false;
  char* end = nullptr;
  *ideal_lap_time = std::strtod(p, &end);
  if (end == p) return false;
  p = end;
  while (*p == ' ') ++p;
  return *p == '\0' || *p == '\n';
}

std::string RunLabel(const SweepPlan& plan, int i) {
  const GridPoint& point = plan.runs[static_cast<std::size_t>(i)].point;
  const std::vector<SweepAxis>& axes = plan.axes();
  std::string s = "run " + std::to_string(i + 1) + " (config " +
                  plan.configs[static_cast<std::size_t>(point.config)].name;
  for (std::size_t a = 0; a < axes.size(); ++a)
    s += ", " + axes[a].key + "=" + axes[a].values[static_cast<std::size_t>(point.value[a])];
  return s + ")";
}

// --- MPI ranks (tuning/sim/parallel/mpi_backend.h): the definition goes to every rank, which
// builds the same plan and resolves what its runs need; a batch is a list of run indices. A run's
// answer is "ok" + EncodeRun, or "C " / "R " + the message of a ConfigError / another error.
std::string EncodeDefinition(const SweepDefinition& d) {
  WireWriter w;
  const auto strings = [&w](const std::vector<std::string>& v) {
    w.Int(static_cast<std::int64_t>(v.size()));
    for (const auto& x : v) w.String(x);
  };
  w.String(d.scenario_file);
  strings(d.base_overrides);
  w.String(d.stability_file);
  w.Int(static_cast<std::int64_t>(d.axes.size()));
  for (const auto& a : d.axes) {
    w.String(a.key);
    strings(a.values);
  }
  w.Int(static_cast<std::int64_t>(d.configs.size()));
  for (const auto& c : d.configs) {
    w.String(c.name);
    strings(c.overrides);
  }
  w.Bool(d.stop_at_first_abort);
  return w.Take();
}

SweepDefinition DecodeDefinition(std::string_view bytes) {
  WireReader r(bytes);
  const auto strings = [&r] {
    std::vector<std::string> v(static_cast<std::size_t>(r.Int()));
    for (auto& x : v) x = r.String();
    return v;
  };
  SweepDefinition d;
  d.scenario_file = r.String();
  d.base_overrides = strings();
  d.stability_file = r.String();
  d.axes.resize(static_cast<std::size_t>(r.Int()));
  for (auto& a : d.axes) {
    a.key = r.String();
    a.values = strings();
  }
  d.configs.resize(static_cast<std::size_t>(r.Int()));
  for (auto& c : d.configs) {
    c.name = r.String();
    c.overrides = strings();
  }
  d.stop_at_first_abort = r.Bool();
  return d;
}

std::string RunAnswer(Resolutions* resolutions, int i) {
  try {
    const ResolvedScenario sc = resolutions->Scenario(i);
    return "ok" + EncodeRun(RunClosedLoop(sc, sc.stability), sc.ideal_lap_time);
  } catch (const ConfigError& e) {
    return std::string("C ") + e.what();
  } catch (const std::exception& e) {
    return std::string("R ") + e.what();
  }
}

// Fills run i from its answer; a failed run throws as with worker processes.
void ApplyAnswer(const SweepPlan& plan, SweepResult* r, int i, std::string_view answer) {
  const std::string a(answer);
  SweepRun& run = r->runs[static_cast<std::size_t>(i)];
  if (a.rfind("ok", 0) == 0) {
    if (!DecodeRun(a.c_str() + 2, &run.metrics, &run.ideal_lap_time))
      throw std::runtime_error("an MPI rank sent unreadable results for " + RunLabel(plan, i));
    run.computed = true;
    return;
  }
  const std::string message = RunLabel(plan, i) + ": " + (a.size() > 2 ? a.substr(2) : a);
  if (a.rfind("C ", 0) == 0) throw ConfigError("scw sweep", "", message);
  throw std::runtime_error(message);
}

class SweepWorkerTask final : public mpi::WorkerTask {
 public:
  explicit SweepWorkerTask(std::string_view setup)
      : plan_(ExpandSweep(DecodeDefinition(setup))), resolutions_(plan_) {}

  void StartBatch(std::string_view payload) override {
    WireReader r(payload);
    batch_.resize(static_cast<std::size_t>(r.Int()));
    for (int& i : batch_) i = static_cast<int>(r.Int());
  }

  std::string Run(int index) const override {
    if (index < 0 || static_cast<std::size_t>(index) >= batch_.size())
      throw std::runtime_error("job index out of range");
    const int i = batch_[static_cast<std::size_t>(index)];
    if (i < 0 || static_cast<std::size_t>(i) >= plan_.runs.size())
      throw std::runtime_error("run index out of range");
    return RunAnswer(&resolutions_, i);
  }

 private:
  SweepPlan plan_;
  mutable Resolutions resolutions_;
  std::vector<int> batch_;
};

// The result slots: every run of the plan, nothing computed yet.
SweepResult EmptyResult(const SweepPlan& plan) {
  SweepResult r;
  r.axes = plan.axes();
  r.configs = plan.configs;
  r.runs.resize(plan.runs.size());
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    r.runs[i].point = plan.runs[i].point;
    r.runs[i].spec = plan.runs[i].spec;
  }
  r.resolves = static_cast<int>(plan.resolutions.size());
  return r;
}

}  // namespace

std::vector<bool> ReportedRuns(const std::vector<int>& series, const std::vector<bool>& aborted,
                               bool stop_at_first_abort) {
  std::vector<bool> out(series.size(), true);
  if (!stop_at_first_abort) return out;
  std::map<int, bool> stopped;
  for (std::size_t i = 0; i < series.size(); ++i) {
    bool& s = stopped[series[i]];
    out[i] = !s;
    if (aborted[i]) s = true;
  }
  return out;
}

std::unique_ptr<mpi::WorkerTask> MakeSweepWorkerTask(std::string_view setup, int /*threads*/) {
  return std::make_unique<SweepWorkerTask>(setup);
}

int RunSweepWorker(const SweepPlan& plan, int in_fd, int out_fd) {
  Resolutions resolutions(plan);
  FILE* in = fdopen(in_fd, "r");
  FILE* out = fdopen(out_fd, "w");
  if (in == nullptr || out == nullptr) return 1;
  char line[256];
  const int n = static_cast<int>(plan.runs.size());
  while (std::fgets(line, sizeof line, in) != nullptr) {
    int i = -1;
    if (std::sscanf(line, "run %d", &i) != 1 || i < 0 || i >= n) return 1;
    std::string answer;
    try {
      const ResolvedScenario sc = resolutions.Scenario(i);
      answer =
          "ok " + std::to_string(i) + EncodeRun(RunClosedLoop(sc, sc.stability), sc.ideal_lap_time);
    } catch (const ConfigError& e) {
      answer = "error " + std::to_string(i) + " C " + detail::OneLine(e.what());
    } catch (const std::exception& e) {
      answer = "error " + std::to_string(i) + " R " + detail::OneLine(e.what());
    }
    if (std::fputs((answer + "\n").c_str(), out) < 0 || std::fflush(out) != 0) return 1;
  }
  return 0;
}

SweepResult RunSweep(const SweepPlan& plan, const SweepExecution& exec,
                     const SweepTraceOptions& traces) {
  const SweepDefinition& d = plan.definition;
  const auto conditions = ParseTraceConditions(plan.axes(), traces.at);
  SweepResult r = EmptyResult(plan);
  const int n = static_cast<int>(plan.runs.size());
  const int threads = exec.threads;
  Resolutions resolutions(plan);

  // Progress (reporting only): runs computed so far of the runs that will be computed.
  std::mutex progress_mutex;
  SweepProgress progress{"run", 0, n};
  const auto report = [&](int more_done) {
    if (!exec.on_progress) return;
    const std::lock_guard<std::mutex> lock(progress_mutex);
    progress.done += more_done;
    exec.on_progress(progress);
  };
  report(0);

  // How a batch of runs is computed: threads of this process (resolutions first, in parallel),
  // or worker processes (each resolves what it needs).
  std::unique_ptr<detail::SweepProcessPool> pool;
  std::function<void(const std::vector<int>&)> run_batch;
  int workers = ResolveThreads(threads);
  std::shared_ptr<const mpi::RemoteTask> remote;
  if (exec.processes == 0)
    remote = mpi::MaybeRemote(
        "sweep", [&] { return EncodeDefinition(d); }, workers);
  if (remote) {
    // MPI: every rank (this one included, `threads` each) takes runs as it becomes free.
    workers = mpi::Ranks() * remote->threads();
    run_batch = [&](const std::vector<int>& batch) {
      WireWriter w;
      w.Int(static_cast<std::int64_t>(batch.size()));
      for (int i : batch) w.Int(i);
      remote->Run(
          w.Take(), static_cast<int>(batch.size()),
          [&](int k) {
            const int i = batch[static_cast<std::size_t>(k)];
            ApplyAnswer(plan, &r, i, RunAnswer(&resolutions, i));
            report(1);
          },
          [&](int k, std::string_view answer) {
            ApplyAnswer(plan, &r, batch[static_cast<std::size_t>(k)], answer);
            report(1);
          });
    };
  } else if (exec.processes > 0) {
    if (exec.worker_command.empty())
      throw std::invalid_argument("RunSweep: processes need a worker command");
    workers = std::min(exec.processes, std::max(n, 1));
    std::vector<std::string> argv = exec.worker_command;
    for (auto& a : SweepWorkerArguments(d)) argv.push_back(std::move(a));
    pool = std::make_unique<detail::SweepProcessPool>(argv, workers,
                                                      [&plan](int i) { return RunLabel(plan, i); });
    run_batch = [&](const std::vector<int>& batch) {
      pool->Run(batch, [&](int i, const char* payload) {
        SweepRun& run = r.runs[static_cast<std::size_t>(i)];
        if (!DecodeRun(payload, &run.metrics, &run.ideal_lap_time))
          throw std::runtime_error("sweep worker sent unreadable results for " + RunLabel(plan, i));
        run.computed = true;
        report(1);
      });
    };
  } else {
    run_batch = [&](const std::vector<int>& batch) {
      // The batch's resolutions first, in parallel (only those a run needs: a series stopped at
      // its first abort never resolves its later values).
      std::vector<int> groups;
      for (int i : batch) groups.push_back(plan.runs[static_cast<std::size_t>(i)].resolution);
      std::sort(groups.begin(), groups.end());
      groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
      ParallelFor(static_cast<int>(groups.size()), threads,
                  [&](int k) { (void)resolutions.Get(groups[static_cast<std::size_t>(k)]); });
      ParallelFor(static_cast<int>(batch.size()), threads, [&](int k) {
        const int i = batch[static_cast<std::size_t>(k)];
        const ResolvedScenario sc = resolutions.Scenario(i);
        SweepRun& run = r.runs[static_cast<std::size_t>(i)];
        run.metrics = RunClosedLoop(sc, sc.stability);
        run.ideal_lap_time = sc.ideal_lap_time;
        run.computed = true;
        report(1);
      });
    };
  }

  if (!d.stop_at_first_abort) {
    std::vector<int> all(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) all[static_cast<std::size_t>(i)] = i;
    run_batch(all);
  } else {
    // Waves: the next few runs of every series still going, in parallel; a series stops after
    // its first abort. Which runs get computed depends on the worker count, the reported ones
    // (every run up to the first abort) do not.
    int n_series = 0;
    for (const auto& run : plan.runs) n_series = std::max(n_series, run.point.series + 1);
    std::vector<std::vector<int>> members(static_cast<std::size_t>(n_series));
    for (int i = 0; i < n; ++i)
      members[static_cast<std::size_t>(plan.runs[static_cast<std::size_t>(i)].point.series)]
          .push_back(i);
    std::vector<std::size_t> next(members.size(), 0);
    std::vector<bool> stopped(members.size(), false);
    while (true) {
      std::vector<std::size_t> alive;
      for (std::size_t s = 0; s < members.size(); ++s)
        if (!stopped[s] && next[s] < members[s].size()) alive.push_back(s);
      if (alive.empty()) break;
      const std::size_t per = std::max<std::size_t>(
          1, (static_cast<std::size_t>(workers) + alive.size() - 1) / alive.size());
      std::vector<int> batch;
      for (std::size_t s : alive)
        for (std::size_t k = next[s]; k < std::min(next[s] + per, members[s].size()); ++k)
          batch.push_back(members[s][k]);
      run_batch(batch);
      for (std::size_t s : alive) {
        const std::size_t end = std::min(next[s] + per, members[s].size());
        for (; next[s] < end && !stopped[s]; ++next[s])
          if (r.runs[static_cast<std::size_t>(members[s][next[s]])].metrics.aborted())
            stopped[s] = true;
      }
      if (exec.on_progress) {
        // The runs still to come: those after each going series' last computed run.
        int total = progress.done;
        for (std::size_t s = 0; s < members.size(); ++s)
          if (!stopped[s])
            for (std::size_t k = next[s]; k < members[s].size(); ++k)
              total += !r.runs[static_cast<std::size_t>(members[s][k])].computed;
        progress.total = total;
        report(0);
      }
    }
  }
  if (pool) {
    pool->Finish();
    pool.reset();
  }

  std::vector<int> series(r.runs.size());
  std::vector<bool> aborted(r.runs.size());
  for (std::size_t i = 0; i < r.runs.size(); ++i) {
    series[i] = r.runs[i].point.series;
    // A run not computed comes after its series' first abort: never reported.
    aborted[i] = !r.runs[i].computed || r.runs[i].metrics.aborted();
  }
  const std::vector<bool> reported = ReportedRuns(series, aborted, d.stop_at_first_abort);
  for (std::size_t i = 0; i < r.runs.size(); ++i) r.runs[i].reported = reported[i];

  if (!traces.dir.empty()) {
    std::vector<int> selected;
    for (int i = 0; i < n; ++i) {
      const SweepRun& run = r.runs[static_cast<std::size_t>(i)];
      if (run.reported && SelectedForTrace(r, run, conditions)) selected.push_back(i);
    }
    // Resolutions of the traced runs first (serially: with worker processes none exist here).
    for (int i : selected) (void)resolutions.Get(plan.runs[static_cast<std::size_t>(i)].resolution);
    std::error_code ec;
    fs::create_directories(traces.dir, ec);
    if (ec)
      throw std::runtime_error("cannot create the trace folder " + traces.dir + ": " +
                               ec.message());
    {
      const std::lock_guard<std::mutex> lock(progress_mutex);
      progress = {"trace", 0, static_cast<int>(selected.size())};
    }
    report(0);
    ParallelFor(static_cast<int>(selected.size()), threads, [&](int k) {
      const int i = selected[static_cast<std::size_t>(k)];
      const ResolvedScenario sc = resolutions.Scenario(i);
      io::CsvWriter w(
          (fs::path(traces.dir) / TraceFileName(r, r.runs[static_cast<std::size_t>(i)])).string(),
          TraceHeader());
      RunOptions ro;
      ro.trace = &w;
      (void)RunClosedLoop(sc, sc.stability, ro);
      w.Commit();
      report(1);
    });
  }
  return r;
}

}  // namespace scw::tuning
