#include "tuning/sweep/sweep_run.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "params/io/csv.h"
#include "params/schema/field.h"
#include "tuning/exec/parallel_for.h"
#include "tuning/exec/wire.h"
#include "tuning/sim/closed_loop.h"
#include "tuning/sim/prep_cache.h"
#include "tuning/sim/scenario.h"
#include "tuning/sweep/sweep_write.h"

namespace scw::tuning::sweep {
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

// --- Remote workers (MPI ranks, worker processes: tuning/exec/executor.h): the definition goes to
// every worker, which builds the same plan and resolves what its runs need; a batch is a list of
// run indices. A run's answer is "ok" + EncodeRun, or "C " / "R " + the message of a ConfigError /
// another error.
std::string EncodeDefinition(const SweepDefinition& d) {
  exec::WireWriter w;
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
  exec::WireReader r(bytes);
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

// Fills run i from its answer; a failed run throws (ConfigError for "C") naming the run.
void ApplyAnswer(const SweepPlan& plan, SweepResult* r, int i, std::string_view answer) {
  const std::string a(answer);
  SweepRun& run = r->runs[static_cast<std::size_t>(i)];
  if (a.rfind("ok", 0) == 0) {
    if (!DecodeRun(a.c_str() + 2, &run.metrics, &run.ideal_lap_time))
      throw std::runtime_error("a sweep worker sent unreadable results for " + RunLabel(plan, i));
    run.computed = true;
    return;
  }
  const std::string message = RunLabel(plan, i) + ": " + (a.size() > 2 ? a.substr(2) : a);
  if (a.rfind("C ", 0) == 0) throw ConfigError("scw sweep", "", message);
  throw std::runtime_error(message);
}

class SweepWorkerTask final : public exec::WorkerTask {
 public:
  explicit SweepWorkerTask(std::string_view setup)
      : plan_(ExpandSweep(DecodeDefinition(setup))), resolutions_(plan_) {}

  void StartBatch(std::string_view payload) override {
    exec::WireReader r(payload);
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

// Reports progress (see SweepExecution::on_progress): one call at a time.
class Progress {
 public:
  explicit Progress(const SweepExecution& execution) : on_progress_(execution.on_progress) {}
  void Start(const std::string& phase, int total) {
    const std::lock_guard<std::mutex> lock(mutex_);
    progress_ = {phase, 0, total};
    if (on_progress_) on_progress_(progress_);
  }
  void Done(int more) {
    if (!on_progress_) return;
    const std::lock_guard<std::mutex> lock(mutex_);
    progress_.done += more;
    on_progress_(progress_);
  }
  /// A new total: the runs done so far plus `to_come`.
  void Remaining(int to_come) {
    if (!on_progress_) return;
    const std::lock_guard<std::mutex> lock(mutex_);
    progress_.total = progress_.done + to_come;
    on_progress_(progress_);
  }
  bool enabled() const { return static_cast<bool>(on_progress_); }

 private:
  const std::function<void(const SweepProgress&)>& on_progress_;
  std::mutex mutex_;
  SweepProgress progress_;
};

// Computes the runs `batch` (plan indices) into r's slots through the executor. On threads the
// batch's resolutions come first, in parallel (only those a run needs: a series stopped at its
// first abort never resolves its later values), and each run writes its slot directly; elsewhere
// a run's answer travels as exact text (RunAnswer, ApplyAnswer), also for this rank's own runs.
void ComputeRuns(const SweepPlan& plan, const exec::Executor& executor, Resolutions* resolutions,
                 Progress* progress, const std::vector<int>& batch, SweepResult* r) {
  const auto run_of = [&batch](int k) { return batch[static_cast<std::size_t>(k)]; };
  exec::Batch b;
  b.jobs = static_cast<int>(batch.size());
  b.label = [&](int k) { return RunLabel(plan, run_of(k)); };
  b.remote = [&](int k, std::string_view answer) {
    ApplyAnswer(plan, r, run_of(k), answer);
    progress->Done(1);
  };
  if (executor.backend() == exec::Backend::kThreads) {
    std::vector<int> groups;
    for (int i : batch) groups.push_back(plan.runs[static_cast<std::size_t>(i)].resolution);
    std::sort(groups.begin(), groups.end());
    groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
    exec::ParallelFor(static_cast<int>(groups.size()), executor.threads(),
                      [&](int k) { (void)resolutions->Get(groups[static_cast<std::size_t>(k)]); });
    b.local = [&](int k) {
      const ResolvedScenario sc = resolutions->Scenario(run_of(k));
      SweepRun& run = r->runs[static_cast<std::size_t>(run_of(k))];
      run.metrics = RunClosedLoop(sc, sc.stability);
      run.ideal_lap_time = sc.ideal_lap_time;
      run.computed = true;
      progress->Done(1);
    };
  } else {
    exec::WireWriter w;
    w.Int(static_cast<std::int64_t>(batch.size()));
    for (int i : batch) w.Int(i);
    b.payload = w.Take();
    b.local = [&](int k) { b.remote(k, RunAnswer(resolutions, run_of(k))); };
  }
  try {
    executor.Run(b);
  } catch (const exec::WorkerError& e) {
    throw std::runtime_error(std::string("sweep ") + e.what() + "; no table written");
  }
}

// Stopping at the first abort: waves of the next few runs of every series still going (together
// about `workers` runs); a series stops after its first abort. Which runs get computed depends on
// the worker count, the reported ones (every run up to the first abort) do not.
void RunInWaves(const SweepPlan& plan, int workers,
                const std::function<void(const std::vector<int>&)>& run, Progress* progress,
                SweepResult* r) {
  int n_series = 0;
  for (const auto& p : plan.runs) n_series = std::max(n_series, p.point.series + 1);
  std::vector<std::vector<int>> members(static_cast<std::size_t>(n_series));
  for (std::size_t i = 0; i < plan.runs.size(); ++i)
    members[static_cast<std::size_t>(plan.runs[i].point.series)].push_back(static_cast<int>(i));
  std::vector<std::size_t> next(members.size(), 0);
  std::vector<bool> stopped(members.size(), false);
  const auto computed = [r](int i) -> const SweepRun& {
    return r->runs[static_cast<std::size_t>(i)];
  };
  while (true) {
    std::vector<std::size_t> alive;
    for (std::size_t s = 0; s < members.size(); ++s)
      if (!stopped[s] && next[s] < members[s].size()) alive.push_back(s);
    if (alive.empty()) return;
    const std::size_t per = std::max<std::size_t>(
        1, (static_cast<std::size_t>(workers) + alive.size() - 1) / alive.size());
    std::vector<int> batch;
    for (std::size_t s : alive)
      for (std::size_t k = next[s]; k < std::min(next[s] + per, members[s].size()); ++k)
        batch.push_back(members[s][k]);
    run(batch);
    for (std::size_t s : alive) {
      const std::size_t end = std::min(next[s] + per, members[s].size());
      for (; next[s] < end && !stopped[s]; ++next[s])
        if (computed(members[s][next[s]]).metrics.aborted()) stopped[s] = true;
    }
    if (progress->enabled()) {
      // The runs still to come: those after each going series' last computed run.
      int to_come = 0;
      for (std::size_t s = 0; s < members.size(); ++s)
        if (!stopped[s])
          for (std::size_t k = next[s]; k < members[s].size(); ++k)
            to_come += !computed(members[s][k]).computed;
      progress->Remaining(to_come);
    }
  }
}

// Re-runs the selected reported runs with a trace writer, on threads (runs are deterministic).
void WriteTraces(const SweepPlan& plan, const SweepResult& r,
                 const std::vector<TraceCondition>& conditions, const std::string& dir, int threads,
                 Resolutions* resolutions, Progress* progress) {
  std::vector<int> selected;
  for (std::size_t i = 0; i < r.runs.size(); ++i)
    if (r.runs[i].reported && SelectedForTrace(r, r.runs[i], conditions))
      selected.push_back(static_cast<int>(i));
  // Resolutions of the traced runs first (serially: with worker processes none exist here).
  for (int i : selected) (void)resolutions->Get(plan.runs[static_cast<std::size_t>(i)].resolution);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create the trace folder " + dir + ": " + ec.message());
  progress->Start("trace", static_cast<int>(selected.size()));
  exec::ParallelFor(static_cast<int>(selected.size()), threads, [&](int k) {
    const int i = selected[static_cast<std::size_t>(k)];
    const ResolvedScenario sc = resolutions->Scenario(i);
    io::CsvWriter w(
        (fs::path(dir) / TraceFileName(r, r.runs[static_cast<std::size_t>(i)])).string(),
        TraceHeader());
    RunOptions ro;
    ro.trace = &w;
    (void)RunClosedLoop(sc, sc.stability, ro);
    w.Commit();
    progress->Done(1);
  });
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

std::unique_ptr<exec::WorkerTask> MakeSweepWorkerTask(std::string_view setup, int /*threads*/) {
  return std::make_unique<SweepWorkerTask>(setup);
}

SweepResult RunSweep(const SweepPlan& plan, const SweepExecution& execution,
                     const SweepTraceOptions& traces) {
  const SweepDefinition& d = plan.definition;
  const auto conditions = ParseTraceConditions(plan.axes(), traces.at);
  SweepResult r = EmptyResult(plan);
  const int n = static_cast<int>(plan.runs.size());
  Resolutions resolutions(plan);
  Progress progress(execution);
  progress.Start("run", n);

  exec::Options where = execution;
  where.processes = std::min(execution.processes, std::max(n, 1));
  exec::Executor executor(where, "sweep", [&d] { return EncodeDefinition(d); });
  const auto run = [&](const std::vector<int>& batch) {
    ComputeRuns(plan, executor, &resolutions, &progress, batch, &r);
  };
  if (d.stop_at_first_abort) {
    RunInWaves(plan, executor.workers(), run, &progress, &r);
  } else {
    std::vector<int> all(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) all[static_cast<std::size_t>(i)] = i;
    run(all);
  }
  try {
    executor.Finish();
  } catch (const exec::WorkerError& e) {
    throw std::runtime_error(std::string("sweep ") + e.what() + " at the end of the sweep");
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

  if (!traces.dir.empty())
    WriteTraces(plan, r, conditions, traces.dir, execution.threads, &resolutions, &progress);
  return r;
}

}  // namespace scw::tuning::sweep
