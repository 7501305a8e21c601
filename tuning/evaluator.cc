#include "tuning/evaluator.h"

#include <filesystem>
#include <mutex>

#include "tuning/closed_loop.h"
#include "tuning/optim/parallel.h"

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

}  // namespace

BatchEvaluator::BatchEvaluator(std::vector<ResolvedScenario> scenarios, std::vector<double> weights,
                               params::CostWeights cost, int threads)
    : scenarios_(std::move(scenarios)),
      weights_(std::move(weights)),
      cost_(cost),
      threads_(ResolveThreads(threads)) {
  weights_.resize(scenarios_.size(), 1.0);
}

BatchEvaluator BatchEvaluator::FromEntries(const std::vector<ScenarioEntry>& entries,
                                           const std::string& base_dir,
                                           const params::CostWeights& cost, int threads,
                                           const BatchProgress& progress) {
  std::vector<ResolvedScenario> resolved(entries.size());
  std::vector<double> weights;
  for (const auto& e : entries) weights.push_back(e.weight);
  ProgressCounter counter(progress, static_cast<int>(entries.size()));
  ParallelFor(static_cast<int>(entries.size()), threads, [&](int i) {
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
        Resolve(spec, dir, e.file.empty() ? "built-in" : e.file);
    counter.JobDone();
  });
  return BatchEvaluator(std::move(resolved), std::move(weights), cost, threads);
}

std::vector<SetEvaluation> BatchEvaluator::Evaluate(
    const std::vector<params::StabilityParams>& sets, const BatchProgress& progress) const {
  const int n_sc = static_cast<int>(scenarios_.size());
  const int n_jobs = static_cast<int>(sets.size()) * n_sc;
  std::vector<RunMetrics> slots(static_cast<std::size_t>(n_jobs));
  std::vector<std::string> invalid(static_cast<std::size_t>(n_jobs));
  RunOptions ro;
  ro.sideslip_allowed_deg = cost_.sideslip_allowed_deg;
  ProgressCounter counter(progress, n_jobs);
  ParallelFor(n_jobs, threads_, [&](int j) {
    const auto& sc = scenarios_[static_cast<std::size_t>(j % n_sc)];
    const auto& set = sets[static_cast<std::size_t>(j / n_sc)];
    RunMetrics& m = slots[static_cast<std::size_t>(j)];
    try {
      m = RunClosedLoop(sc, set, ro);
    } catch (const ConfigError& e) {
      m = RunMetrics{};
      m.status = RunStatus::kInvalidParams;
      m.laps_planned = sc.spec.laps;
      m.distance_planned = sc.spec.laps * sc.track->length();
      invalid[static_cast<std::size_t>(j)] =
          e.problems().empty() ? e.what() : e.problems()[0].path + ": " + e.problems()[0].message;
    }
    counter.JobDone();
  });
  std::vector<SetEvaluation> out(sets.size());
  for (std::size_t s = 0; s < sets.size(); ++s) {
    SetEvaluation& ev = out[s];
    for (int k = 0; k < n_sc; ++k) {
      const std::size_t j = s * static_cast<std::size_t>(n_sc) + static_cast<std::size_t>(k);
      ev.runs.push_back(slots[j]);
      ev.costs.push_back(ScenarioCost(
          slots[j], cost_, scenarios_[static_cast<std::size_t>(k)].spec.kind == "critical"));
      if (ev.invalid.empty()) ev.invalid = invalid[j];
    }
    ev.total = TotalCost(ev.costs, weights_);
  }
  return out;
}

SetEvaluation BatchEvaluator::Evaluate(const params::StabilityParams& set) const {
  return Evaluate(std::vector<params::StabilityParams>{set}).front();
}

}  // namespace scw::tuning
