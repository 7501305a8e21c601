#include "tuning/optim/evaluator.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <numeric>
#include <optional>
#include <stdexcept>

#include "tuning/exec/executor.h"
#include "tuning/exec/parallel_for.h"
#include "tuning/exec/wire.h"
#include "tuning/maneuver/maneuver.h"
#include "tuning/sim/closed_loop.h"
#include "tuning/sim/prep_cache.h"

namespace scw::tuning {
namespace {

// Serialises the progress calls of one batch (see evaluator.h); a no-op without a callback.
class ProgressCounter {
 public:
  ProgressCounter(const BatchProgress& progress, int total) : progress_(progress), total_(total) {}
  void JobDone() {
    if (!progress_) return;
    const std::lock_guard<std::mutex> lock(mutex_);
    progress_(++done_, total_);
  }

 private:
  const BatchProgress& progress_;
  const int total_;
  int done_ = 0;
  std::mutex mutex_;
};

RunOptions OptionsFor(const params::CostWeights& cost) {
  RunOptions ro;
  ro.sideslip_allowed_deg = cost.sideslip_allowed_deg;
  return ro;
}

// One job: `set` on `sc`. A set the schema rejects is a result (kInvalidParams + the first
// problem), not an error.
void RunJob(const ResolvedScenario& sc, const params::StabilityParams& set, const RunOptions& ro,
            RunMetrics* m, std::string* invalid) {
  try {
    if (sc.spec.kind == "maneuver") {
      ManeuverOptions mo;
      mo.sideslip_allowed_deg = ro.sideslip_allowed_deg;
      *m = RunManeuver(sc, set, mo).Summary();
    } else {
      *m = RunClosedLoop(sc, set, ro);
    }
  } catch (const ConfigError& e) {
    *m = RunMetrics{};
    m->status = RunStatus::kInvalidParams;
    m->laps_planned = sc.track ? sc.spec.laps : 0;
    m->distance_planned = sc.track ? sc.spec.laps * sc.track->length() : 0.0;
    *invalid =
        e.problems().empty() ? e.what() : e.problems()[0].path + ": " + e.problems()[0].message;
  }
}

// --- What travels to the other ranks (tuning/exec/wire.h, tuning/exec/executor.h).

std::string EncodeSetup(const std::vector<ScenarioEntry>& entries, const std::string& base_dir,
                        const params::CostWeights& cost) {
  exec::WireWriter w;
  w.Int(static_cast<std::int64_t>(entries.size()));
  for (const auto& e : entries) {
    w.String(e.name);
    w.Double(e.weight);
    w.String(e.file);
    w.Int(static_cast<std::int64_t>(e.overrides.size()));
    for (const auto& o : e.overrides) w.String(o);
  }
  w.String(base_dir);
  w.Params(cost);
  return w.Take();
}

std::string EncodeSets(const std::vector<params::StabilityParams>& sets) {
  exec::WireWriter w;
  w.Int(static_cast<std::int64_t>(sets.size()));
  for (const auto& s : sets) w.Params(s);
  return w.Take();
}

// A set's key in the run memo: its exact bytes.
std::string SetKey(const params::StabilityParams& set) {
  exec::WireWriter w;
  w.Params(set);
  return w.Take();
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// A job's result: the metrics as exact text, a line break, the job's wall time (for the order of
// later jobs only), a line break, the invalid-set message.
std::string EncodeResult(const RunMetrics& m, double wall, const std::string& invalid) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "\n%a\n", wall);
  return EncodeRunMetrics(m) + buf + invalid;
}

void DecodeResult(std::string_view bytes, RunMetrics* m, double* wall, std::string* invalid) {
  const std::string text(bytes);
  const char* end = DecodeRunMetrics(text.c_str(), m);
  char* after = nullptr;
  if (end != nullptr && *end == '\n') *wall = std::strtod(end + 1, &after);
  if (after == nullptr || after == end + 1 || *after != '\n')
    throw std::runtime_error("unreadable result from a rank");
  *invalid = std::string(after + 1);
}

class EvaluatorWorkerTask final : public exec::WorkerTask {
 public:
  EvaluatorWorkerTask(std::string_view setup, int threads) : ev_(Decode(setup, threads)) {}

  void StartBatch(std::string_view payload) override {
    exec::WireReader r(payload);
    const std::int64_t n = r.Int();
    if (n < 0 || n > 1000000) throw std::runtime_error("malformed batch");
    sets_.assign(static_cast<std::size_t>(n), params::StabilityParams{});
    for (auto& s : sets_) r.Params(&s);
  }

  std::string Run(int index) const override {
    const std::size_t n_sc = ev_.scenarios().size();
    const auto j = static_cast<std::size_t>(index);
    if (n_sc == 0 || index < 0 || j / n_sc >= sets_.size())
      throw std::runtime_error("job index out of range");
    RunMetrics m;
    std::string invalid;
    const auto t0 = std::chrono::steady_clock::now();
    RunJob(ev_.scenarios()[j % n_sc], sets_[j / n_sc], OptionsFor(ev_.cost()), &m, &invalid);
    return EncodeResult(m, Seconds(t0), invalid);
  }

 private:
  static BatchEvaluator Decode(std::string_view setup, int threads) {
    exec::WireReader r(setup);
    std::vector<ScenarioEntry> entries(static_cast<std::size_t>(r.Int()));
    for (auto& e : entries) {
      e.name = r.String();
      e.weight = r.Double();
      e.file = r.String();
      e.overrides.resize(static_cast<std::size_t>(r.Int()));
      for (auto& o : e.overrides) o = r.String();
    }
    const std::string base_dir = r.String();
    params::CostWeights cost;
    r.Params(&cost);
    return BatchEvaluator::FromEntries(entries, base_dir, cost, threads);
  }

  BatchEvaluator ev_;
  std::vector<params::StabilityParams> sets_;
};

}  // namespace

bool RunMemo::Find(const std::string& set, const std::vector<std::string>& scenarios,
                   std::vector<RunMetrics>* runs, std::vector<std::string>* invalid) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto s = runs_.find(set);
  if (s == runs_.end()) return false;
  runs->clear();
  invalid->clear();
  for (const std::string& k : scenarios) {
    const auto r = s->second.find(k);
    if (r == s->second.end()) return false;
    runs->push_back(r->second.metrics);
    invalid->push_back(r->second.invalid);
  }
  reused_ += static_cast<long>(scenarios.size());
  return true;
}

void RunMemo::Store(const std::string& set, const std::vector<std::string>& scenarios,
                    const RunMetrics* runs, const std::string* invalid) {
  const std::lock_guard<std::mutex> lock(mutex_);
  made_ += static_cast<long>(scenarios.size());
  auto [it, added] = runs_.try_emplace(set);
  if (added) {
    order_.push_back(&it->first);  // a node's key stays where it is until the node is erased
    while (runs_.size() > max_sets_) {
      runs_.erase(*order_.front());
      order_.pop_front();
    }
  }
  auto& by_entry = it->second;
  for (std::size_t i = 0; i < scenarios.size(); ++i)
    by_entry.insert_or_assign(scenarios[i], Run{runs[i], invalid[i]});
}

long RunMemo::reused_runs() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return reused_;
}

long RunMemo::made_runs() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return made_;
}

struct BatchEvaluator::JobLengths {
  std::mutex mutex;
  std::vector<double> length;  ///< per scenario: [s] wall time, or [m] planned before any run
};

std::vector<int> LongestFirst(const std::vector<double>& lengths) {
  std::vector<int> order(lengths.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return lengths[static_cast<std::size_t>(a)] > lengths[static_cast<std::size_t>(b)];
  });
  return order;
}

BatchEvaluator::BatchEvaluator(std::vector<ResolvedScenario> scenarios, std::vector<double> weights,
                               params::CostWeights cost, int threads)
    : scenarios_(std::move(scenarios)),
      weights_(std::move(weights)),
      cost_(cost),
      threads_(exec::ResolveThreads(threads)),
      exec_(std::make_shared<const exec::Executor>(threads)),
      lengths_(std::make_shared<JobLengths>()) {
  weights_.resize(scenarios_.size(), 1.0);
  for (const auto& sc : scenarios_)
    lengths_->length.push_back(sc.track ? sc.spec.laps * sc.track->length() : 0.0);
}

BatchEvaluator BatchEvaluator::FromEntries(const std::vector<ScenarioEntry>& entries,
                                           const std::string& base_dir,
                                           const params::CostWeights& cost, int threads,
                                           const BatchProgress& progress,
                                           controller::planning::ReferenceCache* cache,
                                           std::shared_ptr<RunMemo> memo) {
  // The other ranks (MPI) resolve the same scenarios meanwhile.
  exec::Options where;
  where.threads = threads;
  auto executor = std::make_shared<const exec::Executor>(
      where, "evaluate", [&] { return EncodeSetup(entries, base_dir, cost); });
  std::vector<ResolvedScenario> resolved(entries.size());
  std::vector<double> weights;
  for (const auto& e : entries) weights.push_back(e.weight);
  ProgressCounter counter(progress, static_cast<int>(entries.size()));
  // One preparation cache for the set at least: scenarios on one track and car share line and
  // table.
  std::optional<controller::planning::ReferenceCache> own;
  if (cache == nullptr) cache = &own.emplace(&PrepCache::Process());
  exec::ParallelFor(static_cast<int>(entries.size()), threads, [&](int i) {
    const ScenarioEntry& e = entries[static_cast<std::size_t>(i)];
    const params::ScenarioParams spec = LoadEntry(e, base_dir);
    std::string dir = base_dir;
    if (!e.file.empty()) {
      const std::filesystem::path f = std::filesystem::path(e.file).is_absolute()
                                          ? std::filesystem::path(e.file)
                                          : std::filesystem::path(base_dir) / e.file;
      dir = f.parent_path().string();
    }
    resolved[static_cast<std::size_t>(i)] =
        Resolve(spec, dir, e.file.empty() ? "built-in" : e.file, cache);
    counter.JobDone();
  });
  BatchEvaluator ev(std::move(resolved), std::move(weights), cost, threads);
  ev.exec_ = std::move(executor);
  if (memo) {
    ev.memo_ = std::move(memo);
    for (const auto& e : entries) ev.memo_keys_.push_back(EncodeSetup({e}, base_dir, cost));
  }
  return ev;
}

std::vector<SetEvaluation> BatchEvaluator::Evaluate(
    const std::vector<params::StabilityParams>& sets, const BatchProgress& progress) const {
  const int n_sc = static_cast<int>(scenarios_.size());
  const auto n_scenarios = static_cast<std::size_t>(n_sc);
  const int n_all = static_cast<int>(sets.size()) * n_sc;
  std::vector<RunMetrics> slots(static_cast<std::size_t>(n_all));
  std::vector<std::string> invalid(static_cast<std::size_t>(n_all));
  ProgressCounter counter(progress, n_all);
  const auto job_done = [&counter] { counter.JobDone(); };
  if (!memo_) {
    Run(sets, &slots, &invalid, job_done);
  } else {
    // The sets the memo does not hold, each distinct set once (a repeat within the call takes
    // the first one's runs).
    std::vector<std::size_t> to_run, same_as(sets.size());
    std::vector<std::string> set_keys(sets.size());
    for (std::size_t s = 0; s < sets.size(); ++s) {
      set_keys[s] = SetKey(sets[s]);
      same_as[s] = static_cast<std::size_t>(
          std::find(set_keys.begin(), set_keys.begin() + static_cast<std::ptrdiff_t>(s),
                    set_keys[s]) -
          set_keys.begin());
      if (same_as[s] != s) continue;
      std::vector<RunMetrics> known;
      std::vector<std::string> known_invalid;
      if (!memo_->Find(set_keys[s], memo_keys_, &known, &known_invalid)) {
        to_run.push_back(s);
        continue;
      }
      for (std::size_t k = 0; k < n_scenarios; ++k) {
        slots[s * n_scenarios + k] = std::move(known[k]);
        invalid[s * n_scenarios + k] = std::move(known_invalid[k]);
        job_done();
      }
    }
    std::vector<params::StabilityParams> run_sets;
    for (std::size_t s : to_run) run_sets.push_back(sets[s]);
    std::vector<RunMetrics> ran(run_sets.size() * n_scenarios);
    std::vector<std::string> ran_invalid(ran.size());
    Run(run_sets, &ran, &ran_invalid, job_done);
    for (std::size_t i = 0; i < to_run.size(); ++i) {
      memo_->Store(set_keys[to_run[i]], memo_keys_, &ran[i * n_scenarios],
                   &ran_invalid[i * n_scenarios]);
      for (std::size_t k = 0; k < n_scenarios; ++k) {
        slots[to_run[i] * n_scenarios + k] = std::move(ran[i * n_scenarios + k]);
        invalid[to_run[i] * n_scenarios + k] = std::move(ran_invalid[i * n_scenarios + k]);
      }
    }
    for (std::size_t s = 0; s < sets.size(); ++s) {
      if (same_as[s] == s) continue;
      for (std::size_t k = 0; k < n_scenarios; ++k) {
        slots[s * n_scenarios + k] = slots[same_as[s] * n_scenarios + k];
        invalid[s * n_scenarios + k] = invalid[same_as[s] * n_scenarios + k];
        job_done();
      }
    }
  }
  std::vector<SetEvaluation> out(sets.size());
  for (std::size_t s = 0; s < sets.size(); ++s) {
    SetEvaluation& ev = out[s];
    for (int k = 0; k < n_sc; ++k) {
      const std::size_t j = s * static_cast<std::size_t>(n_sc) + static_cast<std::size_t>(k);
      ev.runs.push_back(slots[j]);
      ev.costs.push_back(
          ScenarioCostOfKind(slots[j], cost_, scenarios_[static_cast<std::size_t>(k)].spec.kind));
      if (ev.invalid.empty()) ev.invalid = invalid[j];
    }
    ev.total = TotalCost(ev.costs, weights_);
  }
  return out;
}

void BatchEvaluator::Run(const std::vector<params::StabilityParams>& sets,
                         std::vector<RunMetrics>* slots_out, std::vector<std::string>* invalid_out,
                         const std::function<void()>& job_done) const {
  const int n_sc = static_cast<int>(scenarios_.size());
  const int n_jobs = static_cast<int>(sets.size()) * n_sc;
  std::vector<RunMetrics>& slots = *slots_out;
  std::vector<std::string>& invalid = *invalid_out;
  std::vector<double> wall(static_cast<std::size_t>(n_jobs), 0.0);
  const RunOptions ro = OptionsFor(cost_);
  std::vector<int> order;
  {
    const std::lock_guard<std::mutex> lock(lengths_->mutex);
    std::vector<double> job_length(static_cast<std::size_t>(n_jobs));
    for (int j = 0; j < n_jobs; ++j)
      job_length[static_cast<std::size_t>(j)] =
          lengths_->length[static_cast<std::size_t>(j % n_sc)];
    order = LongestFirst(job_length);
  }
  exec::Batch batch;
  batch.jobs = n_jobs;
  batch.order = std::move(order);
  batch.local = [&](int j) {
    const auto t0 = std::chrono::steady_clock::now();
    RunJob(scenarios_[static_cast<std::size_t>(j % n_sc)], sets[static_cast<std::size_t>(j / n_sc)],
           ro, &slots[static_cast<std::size_t>(j)], &invalid[static_cast<std::size_t>(j)]);
    wall[static_cast<std::size_t>(j)] = Seconds(t0);
    job_done();
  };
  if (exec_->backend() != exec::Backend::kThreads) {
    batch.payload = EncodeSets(sets);
    batch.remote = [&](int j, std::string_view bytes) {
      const auto k = static_cast<std::size_t>(j);
      DecodeResult(bytes, &slots[k], &wall[k], &invalid[k]);
      job_done();
    };
  }
  exec_->Run(batch);
  if (n_jobs > 0) {  // this call's lengths order the next call's jobs
    const std::lock_guard<std::mutex> lock(lengths_->mutex);
    std::fill(lengths_->length.begin(), lengths_->length.end(), 0.0);
    for (int j = 0; j < n_jobs; ++j) {
      double& l = lengths_->length[static_cast<std::size_t>(j % n_sc)];
      l = std::max(l, wall[static_cast<std::size_t>(j)]);
    }
  }
}

SetEvaluation BatchEvaluator::Evaluate(const params::StabilityParams& set) const {
  return Evaluate(std::vector<params::StabilityParams>{set}).front();
}

std::unique_ptr<exec::WorkerTask> MakeEvaluatorWorkerTask(std::string_view setup, int threads) {
  return std::make_unique<EvaluatorWorkerTask>(setup, threads);
}

}  // namespace scw::tuning
