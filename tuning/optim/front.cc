#include "tuning/optim/front.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "params/io/write.h"
#include "tuning/sim/run_summary.h"

namespace scw::tuning {
namespace {

namespace fs = std::filesystem;

/// One evaluation of any search of the front, scored without a budget.
struct ArchiveEntry {
  int stage = 0, round = 0, search = 0, pos = 0;  ///< its place in the (deterministic) order
  std::vector<double> u;                          ///< full space coordinates
  double stability = 0.0;
  double lap_loss = 0.0;  ///< +inf: a clean lap aborts (or the set is invalid)
  int extra = 0;          ///< activations beyond the base set's on clean laps
};

bool Within(const ArchiveEntry& e, const CleanLapBudget& b) {
  return std::isfinite(e.lap_loss) && (!std::isfinite(b.lap_s) || e.lap_loss <= b.lap_s) &&
         (!b.interventions || e.extra == 0);
}

/// The best archive entry within `b` whose clean-lap loss exceeds `lower` (it uses budget a
/// tighter point does not have; lowest stability cost, then the earliest), or null.
const ArchiveEntry* BestInBand(const std::vector<ArchiveEntry>& archive, double lower,
                               const CleanLapBudget& b) {
  const ArchiveEntry* best = nullptr;
  for (const auto& e : archive)
    if (Within(e, b) && e.lap_loss > lower && (!best || e.stability < best->stability)) best = &e;
  return best;
}

/// The best archive entry within `b`, or null (an entry within a budget has a finite loss).
const ArchiveEntry* BestWithin(const std::vector<ArchiveEntry>& archive, const CleanLapBudget& b) {
  return BestInBand(archive, -std::numeric_limits<double>::infinity(), b);
}

/// The select phase's candidates of a point with budget `b` (TuneReport::top_points): the
/// kSelectCandidates entries of the whole front within `b` with the lowest stability cost (at the
/// search step; ties in archive order), numbered as evaluations of the point's own search
/// (`own_index`: its sets and their first evaluation) or -1 (another point's).
std::vector<TopPoint> Candidates(const std::vector<ArchiveEntry>& archive, const CleanLapBudget& b,
                                 const std::map<std::vector<double>, int>& own_index) {
  std::vector<const ArchiveEntry*> within;
  for (const auto& e : archive)
    if (Within(e, b)) within.push_back(&e);
  std::stable_sort(within.begin(), within.end(), [](const ArchiveEntry* x, const ArchiveEntry* y) {
    return x->stability < y->stability;
  });
  std::vector<TopPoint> out;
  for (const ArchiveEntry* e : within) {
    if (out.size() == kSelectCandidates) break;
    const bool seen =
        std::any_of(out.begin(), out.end(), [&](const TopPoint& t) { return t.u == e->u; });
    if (seen) continue;
    const auto at = own_index.find(e->u);
    out.push_back({at == own_index.end() ? -1 : at->second, e->stability, e->u});
  }
  return out;
}

/// Lockstep rounds over several searches, each in its own thread: a search submits the sets of
/// its next point and waits; the calling thread (Coordinate) waits until every running search has
/// submitted or ended, runs the round's sets as one batch in search order and hands each search
/// its results. The round's composition depends only on what the searches ask, so the batches are
/// the same for any timing; the batch runs on the thread that calls Coordinate (the main thread:
/// MPI is initialised MPI_THREAD_FUNNELED).
class Gate {
 public:
  using Runner = std::function<std::vector<SetEvaluation>(
      const std::vector<params::StabilityParams>&, int round)>;
  Gate(int searches, Runner run)
      : run_(std::move(run)),
        state_(static_cast<std::size_t>(searches), kRunning),
        sets_(static_cast<std::size_t>(searches)),
        results_(static_cast<std::size_t>(searches)) {}

  /// From search k's thread: blocks until the round with these sets has run.
  std::vector<SetEvaluation> Submit(int k, std::vector<params::StabilityParams> sets) {
    std::unique_lock<std::mutex> lock(mutex_);
    const auto i = static_cast<std::size_t>(k);
    sets_[i] = std::move(sets);
    state_[i] = kWaiting;
    cv_.notify_all();
    cv_.wait(lock, [&] { return state_[i] == kAnswered; });
    state_[i] = kRunning;
    if (failure_) std::rethrow_exception(failure_);
    return std::move(results_[i]);
  }

  /// From search k's thread when its search has ended (normally or not).
  void Done(int k) {
    std::lock_guard<std::mutex> lock(mutex_);
    state_[static_cast<std::size_t>(k)] = kDone;
    cv_.notify_all();
  }

  /// From the calling thread: runs rounds until every search has ended.
  void Coordinate() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      cv_.wait(lock, [&] {
        return std::all_of(state_.begin(), state_.end(),
                           [](State s) { return s == kWaiting || s == kDone; });
      });
      if (std::all_of(state_.begin(), state_.end(), [](State s) { return s == kDone; })) return;
      std::vector<params::StabilityParams> all;
      std::vector<std::size_t> count(state_.size(), 0);
      for (std::size_t k = 0; k < state_.size(); ++k)
        if (state_[k] == kWaiting) {
          count[k] = sets_[k].size();
          all.insert(all.end(), sets_[k].begin(), sets_[k].end());
        }
      // The searches all wait for this round: the lock costs nothing while the batch runs.
      std::vector<SetEvaluation> results;
      try {
        results = all.empty() ? std::vector<SetEvaluation>{} : run_(all, round_);
        if (results.size() != all.size())
          throw std::runtime_error("the front's batch lost results");
      } catch (...) {
        failure_ = std::current_exception();
      }
      std::size_t at = 0;
      for (std::size_t k = 0; k < state_.size(); ++k) {
        if (state_[k] != kWaiting) continue;
        if (!failure_)
          results_[k].assign(results.begin() + static_cast<long>(at),
                             results.begin() + static_cast<long>(at + count[k]));
        at += count[k];
        state_[k] = kAnswered;
      }
      ++round_;
      cv_.notify_all();
    }
  }

 private:
  enum State { kRunning, kWaiting, kAnswered, kDone };
  Runner run_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<State> state_;
  std::vector<std::vector<params::StabilityParams>> sets_;
  std::vector<std::vector<SetEvaluation>> results_;
  int round_ = 0;
  std::exception_ptr failure_;
};

}  // namespace

TuneStudyOptions FrontPointOptions(const TuneStudyOptions& o, const CleanLapBudget& b,
                                   const std::string& folder) {
  TuneStudyOptions p = o;
  p.objective = ObjectiveKind::kConstrained;
  p.budget = b;
  p.resume_log.clear();
  p.stop_if_complete = false;
  const fs::path root = o.run_folder.empty() ? fs::path(".") : fs::path(o.run_folder);
  p.run_folder = (root / folder).string();
  p.evaluation_log = o.evaluation_log.empty() ? "" : (root / folder / "evaluations.csv").string();
  return p;
}

namespace {

std::string Label(const CleanLapBudget& b) {
  if (!std::isfinite(b.lap_s)) return "no budget";
  if (b.lap_s == 0.0 && b.interventions) return "no loss";
  return "+" + FormatFixed(b.lap_s, 3) + " s";
}

int Aborts(const std::vector<SetEvaluation>& sets, std::size_t i) {
  if (sets.size() <= i) return 0;
  int n = 0;
  for (const auto& m : sets[i].runs) n += m.aborted();
  return n;
}

/// The scenarios (training and held-out) point `now` completes and `before` aborts ("buys"), and
/// the reverse ("loses").
std::pair<std::vector<std::string>, std::vector<std::string>> Bought(const TuneReport& before,
                                                                     std::size_t before_set,
                                                                     const TuneReport& now) {
  std::vector<std::string> buys, loses;
  const auto scan = [&](const std::vector<SetEvaluation>& a, const std::vector<SetEvaluation>& b,
                        const std::vector<ScenarioChange>& names) {
    if (a.size() <= before_set || b.size() < 2) return;
    for (std::size_t s = 0; s < names.size(); ++s) {
      const bool was = a[before_set].runs[s].aborted(), is = b[1].runs[s].aborted();
      if (was && !is) buys.push_back(names[s].scenario);
      if (!was && is) loses.push_back(names[s].scenario);
    }
  };
  scan(before.training, now.training, now.training_change.scenarios);
  scan(before.held_out, now.held_out, now.held_out_change.scenarios);
  return {buys, loses};
}

/// The activations ESC/CS/ABS/TC summed over the clean scenarios of `v` (of the base set with
/// `base`), e.g. "2/43/15/8".
std::string CleanActivations(const ObjectiveValue& v, bool base) {
  std::array<int, 4> sum{};
  for (const CleanLapCheck& c : v.clean)
    for (std::size_t k = 0; k < sum.size(); ++k)
      sum[k] += base ? c.base_activations[k] : c.activations[k];
  return std::to_string(sum[0]) + "/" + std::to_string(sum[1]) + "/" + std::to_string(sum[2]) +
         "/" + std::to_string(sum[3]);
}

std::string Join(const std::vector<std::string>& v) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + v[i];
  return out;
}

}  // namespace

int FrontPointEvals(int k, int n, int max_evals) {
  if (k <= 0 || k >= n - 1) return max_evals;
  return 2 * max_evals;
}

double FrontSpan(double unbudgeted_loss) {
  return std::max(std::isfinite(unbudgeted_loss) ? unbudgeted_loss : 0.0, kFrontMinSpan);
}

CleanLapBudget FrontBudget(int k, int n, double loss_span) {
  CleanLapBudget b;
  if (k <= 0) {
    b.lap_s = 0.0;
    b.interventions = true;
  } else if (k >= n - 1) {
    b.lap_s = std::numeric_limits<double>::infinity();
    b.interventions = false;
  } else {
    const double f = static_cast<double>(k) / static_cast<double>(n - 1);
    // Rounded to the millisecond: the budget is printed and compared in those units.
    b.lap_s = std::round(std::max(0.0, loss_span) * f * f * 1000.0) / 1000.0;
    b.interventions = false;
  }
  return b;
}

bool TighterSetDominates(const TuneReport& tighter, const TuneReport& looser,
                         const CleanLapBudget& looser_budget) {
  const ObjectiveValue& a = tighter.tuned_value;
  const ObjectiveValue& b = looser.tuned_value;
  if (tighter.exported_u.empty() || tighter.exported_u == looser.exported_u) return false;
  const bool within = std::isfinite(a.lap_loss) &&
                      (!std::isfinite(looser_budget.lap_s) || a.lap_loss <= looser_budget.lap_s) &&
                      (!looser_budget.interventions || a.extra_activations == 0);
  if (!within || !(a.stability <= b.stability)) return false;
  if (!tighter.neighbourhood_done || !looser.neighbourhood_done) return a.stability < b.stability;
  const int edges_a = OwnEdges(tighter.neighbourhood), edges_b = OwnEdges(looser.neighbourhood);
  return edges_a <= edges_b && (a.stability < b.stability || edges_a < edges_b);
}

double Hypervolume2D(std::vector<std::pair<double, double>> points,
                     std::pair<double, double> reference) {
  std::sort(points.begin(), points.end());
  double area = 0.0, best_y = reference.second;
  for (const auto& [x, y] : points) {
    if (!(x < reference.first) || !(y < best_y)) continue;
    area += (reference.first - x) * (best_y - y);
    best_y = y;
  }
  return area;
}

FrontResult RunFront(const TuneStudy& study, int n, TuneObserver& observer,
                     FrontObserver& front_observer) {
  const TuneStudyOptions& o = study.options();
  if (n < 2)
    throw std::invalid_argument("a front needs at least 2 points, got " + std::to_string(n));
  if (!o.resume_log.empty()) throw std::invalid_argument("a front cannot be resumed");
  TuneReport shared;
  const TunePrepared prep = study.Prepare(observer, &shared);
  const ParameterSpace search_space = study.space().WithPinned(shared.frozen_dims);
  bool all_frozen = false;
  const std::vector<int> free_dims = study.FreeDimensions(shared, &all_frozen);
  const std::vector<double>& u0 = study.start_point();
  const auto expand = [&](const std::vector<double>& v) {
    std::vector<double> u = u0;
    for (std::size_t k = 0; k < free_dims.size() && k < v.size(); ++k)
      u[static_cast<std::size_t>(free_dims[k])] = v[k];
    return u;
  };
  const auto reduce = [&](const std::vector<double>& u) {
    std::vector<double> v;
    for (int i : free_dims) v.push_back(u[static_cast<std::size_t>(i)]);
    return v;
  };
  // Scores every evaluation without a budget (the archive), against the base at the search step.
  CleanLapBudget open;
  open.lap_s = std::numeric_limits<double>::infinity();
  open.interventions = false;
  const TuneObjective scorer =
      TuneObjective::For(prep.search(), ObjectiveKind::kConstrained, open, prep.search_base());

  std::vector<FrontPoint> points(static_cast<std::size_t>(n));
  std::vector<TuneResult> searches(static_cast<std::size_t>(n));
  std::vector<ArchiveEntry> archive;
  // Per point: the sets its own search evaluated and the first evaluation of each.
  std::vector<std::map<std::vector<double>, int>> evaluation_index(static_cast<std::size_t>(n));
  std::mutex archive_mutex;
  FrontResult result;

  // One stage: the searches `which` in lockstep from their start points.
  const auto stage = [&](int stage_no, const std::vector<int>& which,
                         const std::vector<std::vector<double>>& starts) {
    const int m = static_cast<int>(which.size());
    std::vector<TuneStudy> studies;
    std::vector<TuneObjective> objectives;
    for (int j = 0; j < m; ++j) {
      FrontPoint& p = points[static_cast<std::size_t>(which[static_cast<std::size_t>(j)])];
      TuneStudyOptions po = FrontPointOptions(o, p.budget, p.folder);
      po.max_evals = FrontPointEvals(p.index, n, o.max_evals);
      studies.emplace_back(study.base(), study.given_space(), study.scenarios(), po);
      objectives.push_back(studies.back().ObjectiveOn(prep.search(), prep.search_base()));
      if (!o.evaluation_log.empty())
        fs::create_directories(fs::path(studies.back().options().evaluation_log).parent_path());
    }
    std::vector<TrainingObjective> objs;
    for (int j = 0; j < m; ++j)
      objs.emplace_back(search_space, study.base(), prep.search(),
                        objectives[static_cast<std::size_t>(j)]);
    // Round bookkeeping for the archive: the points of each search in the round, in order.
    std::vector<std::vector<std::vector<double>>> asked(static_cast<std::size_t>(m));
    int evaluations = 0;
    int total = 0;
    for (const auto& s : studies) total += all_frozen ? 1 : s.options().max_evals;
    Gate gate(m, [&](const std::vector<params::StabilityParams>& sets, int round) {
      std::vector<SetEvaluation> res = prep.search().Evaluate(sets);
      std::size_t at = 0;
      std::lock_guard<std::mutex> lock(archive_mutex);
      for (int j = 0; j < m; ++j)
        for (std::size_t q = 0; q < asked[static_cast<std::size_t>(j)].size(); ++q, ++at) {
          const ObjectiveValue v = scorer.Of(res[at]);
          ArchiveEntry e;
          e.stage = stage_no;
          e.round = round;
          e.search = which[static_cast<std::size_t>(j)];
          e.pos = static_cast<int>(q);
          e.u = asked[static_cast<std::size_t>(j)][q];
          e.stability = v.stability;
          e.lap_loss = v.within_budget() ? v.lap_loss : std::numeric_limits<double>::infinity();
          e.extra = v.extra_activations;
          archive.push_back(std::move(e));
        }
      evaluations += static_cast<int>(sets.size());
      front_observer.OnRound(evaluations, total);
      return res;
    });
    std::vector<std::thread> threads;
    std::vector<std::exception_ptr> failures(static_cast<std::size_t>(m));
    for (int j = 0; j < m; ++j) {
      threads.emplace_back([&, j] {
        const auto jj = static_cast<std::size_t>(j);
        try {
          const TrainingObjective& obj = objs[jj];
          const BatchObjective batch = [&](const std::vector<std::vector<double>>& vs) {
            std::vector<std::vector<double>> us;
            for (const auto& v : vs) us.push_back(expand(v));
            TrainingObjective::Pending pending = obj.Decode(us);
            {
              std::lock_guard<std::mutex> lock(archive_mutex);
              asked[jj].clear();
              for (std::size_t at : pending.at) asked[jj].push_back(us[at]);
            }
            const std::vector<SetEvaluation> res = gate.Submit(j, pending.sets);
            return obj.Complete(std::move(pending), res);
          };
          const Objective single = [&](const std::vector<double>& v) { return batch({v}).front(); };
          TunerOptions to = studies[jj].SearchOptions(shared, obj);
          to.log_path = studies[jj].options().evaluation_log;
          if (prep.coarse) {  // only a select phase numbers its candidates
            auto& index = evaluation_index[static_cast<std::size_t>(which[jj])];
            to.on_record = [&](int i, const std::vector<double>& v, const Evaluation&) {
              std::lock_guard<std::mutex> lock(archive_mutex);
              index.emplace(expand(v), i);  // the first evaluation of a set
            };
          }
          searches[static_cast<std::size_t>(which[jj])] =
              Tune(reduce(starts[jj]), single, batch, to);
        } catch (...) {
          failures[jj] = std::current_exception();
        }
        gate.Done(j);
      });
    }
    gate.Coordinate();
    for (auto& t : threads) t.join();
    for (const auto& f : failures)
      if (f) std::rethrow_exception(f);
    result.evaluations += evaluations;
  };

  // The ends first (the span L comes from the unbudgeted one), then the inner points.
  points.front().budget = FrontBudget(0, n, 0.0);
  points.back().budget = FrontBudget(n - 1, n, 0.0);
  for (int k = 0; k < n; ++k) {
    points[static_cast<std::size_t>(k)].index = k;
    points[static_cast<std::size_t>(k)].folder = "point_" + std::to_string(k);
  }
  front_observer.OnStage(1, 2, FrontPointEvals(0, n, o.max_evals));
  stage(1, {0, n - 1}, {u0, u0});
  const ArchiveEntry* survive = BestWithin(archive, points.back().budget);
  result.loss_found = survive ? std::max(0.0, survive->lap_loss) : 0.0;
  result.loss_span = FrontSpan(result.loss_found);
  std::vector<int> inner;
  std::vector<std::vector<double>> inner_starts;
  for (int k = 1; k < n - 1; ++k) {
    FrontPoint& p = points[static_cast<std::size_t>(k)];
    p.budget = FrontBudget(k, n, result.loss_span);
    // Its own band first: the best set that spends budget the tighter neighbour does not have,
    // so that neighbouring points whose budgets both bind nowhere do not run the same search.
    const ArchiveEntry* warm =
        BestInBand(archive, FrontBudget(k - 1, n, result.loss_span).lap_s, p.budget);
    if (!warm) warm = BestWithin(archive, p.budget);
    inner.push_back(k);
    inner_starts.push_back(warm ? warm->u : u0);
  }
  if (!inner.empty()) {
    front_observer.OnStage(2, static_cast<int>(inner.size()), FrontPointEvals(1, n, o.max_evals));
    stage(2, inner, inner_starts);
  }

  // Each point: the best within its budget over the whole front, then the export phases.
  for (int k = 0; k < n; ++k) {
    FrontPoint& p = points[static_cast<std::size_t>(k)];
    p.label = Label(p.budget);
    TuneStudyOptions po = FrontPointOptions(o, p.budget, p.folder);
    po.max_evals = FrontPointEvals(k, n, o.max_evals);
    const TuneStudy point_study(study.base(), study.given_space(), study.scenarios(), po);
    front_observer.OnPointBegin(k, n);
    TuneReport r = shared;
    r.objective = point_study.ObjectiveOn(*prep.training, prep.fine_base).Describe();
    r.optimisation = searches[static_cast<std::size_t>(k)];
    const ArchiveEntry* best = BestWithin(archive, p.budget);
    const double base_merit =
        point_study.ObjectiveOn(prep.search(), prep.search_base()).base_value().merit;
    r.optimisation.start_cost = base_merit;
    // A search at a coarser plant step: the select phase runs these at the vehicle's step.
    if (prep.coarse)
      r.top_points = Candidates(archive, p.budget, evaluation_index[static_cast<std::size_t>(k)]);
    if (best && best->stability < base_merit) {
      r.optimisation.best_u = best->u;
      r.optimisation.best_cost = best->stability;
      if (best->search != k) r.optimisation.best_eval = -1;  // another point's evaluation
    } else {
      r.optimisation.best_u = u0;
      r.optimisation.best_cost = base_merit;
      r.optimisation.best_eval = 0;
    }
    r.convergence =
        all_frozen ? std::string("nothing to tune: every parameter is frozen")
                   : ConvergenceVerdict(searches[static_cast<std::size_t>(k)],
                                        FrontPointEvals(k, n, o.max_evals), shared.free_dimensions);
    if (best && best->search != k)
      r.convergence += "; the point's set comes from point " + std::to_string(best->search) +
                       "'s search (the best within this budget over the whole front)";
    TuneReport own = r;  // before its export phases: the start of a re-export
    TuneObserver quiet;
    point_study.Finish(prep, quiet, &r);
    if (k > 0) {
      const TuneReport& tighter = points[static_cast<std::size_t>(k - 1)].report;
      if (TighterSetDominates(tighter, r, p.budget)) {
        // The tighter neighbour's set went through the export rules under a budget this one
        // contains: exported as it is (no sensitivity, no revert, no robust rounds), then compared
        // and checked for knife edges under this point's budget (its runs come from the memo).
        TuneStudyOptions again = po;
        again.sensitivity = false;
        again.robust = false;
        const TuneStudy adopt(study.base(), study.given_space(), study.scenarios(), again);
        // Its set as a point of the space: the dimensions its export reverted at the base value.
        std::vector<double> u = tighter.exported_u;
        for (int d : tighter.pinned_dims)
          u[static_cast<std::size_t>(d)] = u0[static_cast<std::size_t>(d)];
        own.optimisation.best_u = u;  // what Finish exports
        own.pinned_dims = tighter.pinned_dims;
        own.top_points.clear();
        if (prep.coarse) {
          // The select phase's only candidate besides the base, with its merit at the search step.
          const params::StabilityParams set = search_space.Decode(u, study.base(), nullptr);
          own.top_points.push_back({-1,
                                    adopt.ObjectiveOn(prep.search(), prep.search_base())
                                        .Of(prep.search().Evaluate(set))
                                        .merit,
                                    u});
        }
        const auto edges = [](const TuneReport& t) {
          return t.neighbourhood_done ? ", " + std::to_string(OwnEdges(t.neighbourhood)) +
                                            " knife edge(s) of its own"
                                      : std::string();
        };
        own.convergence +=
            "; the point's set is point " + std::to_string(k - 1) +
            "'s exported set: this point's export ended on a set it dominates (stability " +
            FormatFixed(r.tuned_value.stability, 3) + edges(r) + " against " +
            FormatFixed(tighter.tuned_value.stability, 3) + edges(tighter) +
            "), so it is exported as it is (point " + std::to_string(k - 1) +
            "'s revert decisions hold), without a sensitivity of its own and robust rounds";
        adopt.Finish(prep, quiet, &own);
        own.chosen_eval = -1;  // not an evaluation of this point's search
        r = std::move(own);
        p.adopted_from = k - 1;
      }
    }
    p.report = std::move(r);
    front_observer.OnPoint(p);
  }

  result.runs_made = prep.memo->made_runs();
  result.runs_reused = prep.memo->reused_runs();

  // The front's numbers and tables.
  double max_loss = 0.0;
  std::vector<std::pair<double, double>> xy;
  for (const auto& p : points) {
    const ObjectiveValue& v = p.report.tuned_value;
    if (std::isfinite(v.lap_loss)) {
      max_loss = std::max(max_loss, v.lap_loss);
      xy.emplace_back(v.lap_loss, v.stability);
    }
  }
  const double s_base = points.front().report.base_value.stability;
  result.reference = {std::max(1.1 * max_loss, 0.01), s_base};
  result.hypervolume = Hypervolume2D(xy, result.reference);

  std::string csv =
      "point,label,lap_budget_s,activations_limited,changed_keys,training_lap_loss_s,"
      "training_stability,training_aborts,held_out_lap_loss_s,held_out_stability,"
      "held_out_aborts,knife_edges,own_knife_edges,base_training_stability,file,"
      "training_clean_activations,base_held_out_stability,base_training_aborts,"
      "base_held_out_aborts\n";
  std::string md =
      "# scw tune --front " + std::to_string(n) + ": clean-lap time against stability\n\n";
  md +=
      "Each point is a tune within its clean-lap budget (the largest loss of a clean lap "
      "against the base set, per lap); the stability cost is that of the critical scenarios "
      "(lower is better). Base set: stability " +
      FormatFixed(s_base, 3) + " on the training scenarios, " +
      std::to_string(Aborts(points.front().report.training, 0)) + " training and " +
      std::to_string(Aborts(points.front().report.held_out, 0)) +
      " held-out aborts, clean-lap activations ESC/CS/ABS/TC " +
      CleanActivations(points.front().report.tuned_value, true) +
      " (training). Hypervolume of the training front " + FormatFixed(result.hypervolume, 3) +
      " (reference point: loss " + FormatFixed(result.reference.first, 3) + " s/lap, stability " +
      FormatFixed(result.reference.second, 3) + "); " + std::to_string(result.evaluations) +
      " evaluations. Inner budgets L·(k/(N−1))² with L = " + FormatFixed(result.loss_span, 3) +
      " s/lap (the unbudgeted search's best set lost " + FormatFixed(result.loss_found, 3) +
      " s/lap; L is at least " + FormatFixed(kFrontMinSpan, 1) + ").\n\n";
  md +=
      "| point | budget | clean-lap loss train / held-out [s/lap] | stability train / held-out "
      "| aborts train / held-out | clean-lap activations (train) | buys (vs the point before) "
      "| knife edges | file |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (std::size_t k = 0; k < points.size(); ++k) {
    const FrontPoint& p = points[k];
    const TuneReport& r = p.report;
    const auto loss = [](const ObjectiveValue& v) {
      return std::isfinite(v.lap_loss) ? (v.lap_loss >= 0 ? "+" : "") + FormatFixed(v.lap_loss, 3)
                                       : std::string("abort");
    };
    const std::string file = p.folder + "/stability_tuned.yaml";
    const int own = r.neighbourhood_done ? OwnEdges(r.neighbourhood) : -1;
    const auto num = [](double x) {
      return std::isfinite(x) ? params::FormatDouble(x) : std::string(x > 0 ? "inf" : "nan");
    };
    csv += std::to_string(k) + "," + p.label + "," + num(p.budget.lap_s) + "," +
           (p.budget.interventions ? "true" : "false") + "," + std::to_string(r.changed.size()) +
           "," + num(r.tuned_value.lap_loss) + "," + num(r.tuned_value.stability) + "," +
           std::to_string(Aborts(r.training, 1)) + "," + num(r.held_out_value.lap_loss) + "," +
           num(r.held_out_value.stability) + "," + std::to_string(Aborts(r.held_out, 1)) + "," +
           (r.neighbourhood_done ? std::to_string(r.neighbourhood.edges.size()) : "") + "," +
           (r.neighbourhood_done ? std::to_string(own) : "") + "," + num(s_base) + "," + file +
           "," + CleanActivations(r.tuned_value, false) + "," +
           (r.held_out.empty() ? std::string() : num(r.held_out_base_value.stability)) + "," +
           std::to_string(Aborts(r.training, 0)) + "," +
           (r.held_out.empty() ? std::string() : std::to_string(Aborts(r.held_out, 0))) + "\n";
    const auto [buys, loses] = k == 0 ? Bought(r, 0, r) : Bought(points[k - 1].report, 1, r);
    std::string bought = buys.empty() ? "-" : "survives " + Join(buys);
    if (!loses.empty()) bought += "; loses " + Join(loses);
    md += "| " + std::to_string(k) + " | " + p.label + " | " + loss(r.tuned_value) + " / " +
          loss(r.held_out_value) + " | " + FormatFixed(r.tuned_value.stability, 1) + " / " +
          FormatFixed(r.held_out_value.stability, 1) + " | " +
          std::to_string(Aborts(r.training, 1)) + " / " + std::to_string(Aborts(r.held_out, 1)) +
          " | " + CleanActivations(r.tuned_value, false) + " | " + bought + " | " +
          (r.neighbourhood_done
               ? std::to_string(own) + " own of " + std::to_string(r.neighbourhood.edges.size())
               : std::string("not checked")) +
          " | " + file + " |\n";
  }
  md +=
      "\nPoint 0 keeps the base set's clean laps (no loss, no activation the base does not "
      "have); the last has no budget (whatever it takes to survive). \"buys\": the scenarios "
      "the point completes that the point before aborts (point 0: against the base set).\n";
  result.csv = std::move(csv);
  result.markdown = std::move(md);
  result.points = std::move(points);
  return result;
}

}  // namespace scw::tuning
