#include "tuning/optim/tuner.h"

#include <nlopt.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "params/io/csv.h"
#include "params/io/write.h"
#include "params/io/yaml_doc.h"

namespace scw::tuning {
namespace {

struct AlgorithmName {
  const char* name;
  nlopt::algorithm alg;
  bool global;
};

constexpr AlgorithmName kAlgorithms[] = {
    {"crs2", nlopt::GN_CRS2_LM, true},   {"isres", nlopt::GN_ISRES, true},
    {"esch", nlopt::GN_ESCH, true},      {"direct_l", nlopt::GN_DIRECT_L, true},
    {"sbplx", nlopt::LN_SBPLX, false},   {"neldermead", nlopt::LN_NELDERMEAD, false},
    {"bobyqa", nlopt::LN_BOBYQA, false}, {"cobyla", nlopt::LN_COBYLA, false},
    {"mlsl", nlopt::G_MLSL_LDS, true},   {"auglag", nlopt::AUGLAG, false},
};

/// The constrained algorithm: its cost is minimised subject to Evaluation::constraint <= 0.
bool Constrained(const std::string& spec) { return spec == "auglag"; }

/// The batched design phase; not an NLopt algorithm.
constexpr const char* kDesign = "lhs";

const AlgorithmName& FindAlgorithm(const std::string& name) {
  for (const auto& a : kAlgorithms)
    if (name == a.name) return a;
  if (name == kDesign)
    throw std::invalid_argument("'lhs' can only be the first part of A+B (lhs+sbplx)");
  std::string known;
  for (const auto& a : kAlgorithms) known += std::string(known.empty() ? "" : ", ") + a.name;
  throw std::invalid_argument("unknown algorithm '" + name + "' (known: " + known + ", " + kDesign +
                              ", or A+B for a global phase A then a local polish B)");
}

/// An algorithm spec taken apart: the global phase (the design or an NLopt algorithm) and the
/// optional second phase.
struct Plan {
  bool design = false;
  const AlgorithmName* first = nullptr;  ///< null for the design
  const AlgorithmName* second = nullptr;
};

Plan ParsePlan(const std::string& spec) {
  const auto plus = spec.find('+');
  const std::string head = spec.substr(0, plus);
  Plan p;
  p.design = head == kDesign;
  if (!p.design) p.first = &FindAlgorithm(head);
  if (plus != std::string::npos) p.second = &FindAlgorithm(spec.substr(plus + 1));
  return p;
}

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny generator whose output is fixed by its
/// definition, so designs are identical on every platform.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t Next() {
    std::uint64_t z = state_ += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1) on the 2^-53 grid.
  double Unit() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }
  /// Uniform in [0, n), n > 0: draws above the largest multiple of n are rejected.
  std::uint64_t Below(std::uint64_t n) {
    const std::uint64_t top = std::numeric_limits<std::uint64_t>::max();
    const std::uint64_t limit = top - top % n;
    for (;;)
      if (const std::uint64_t v = Next(); v < limit) return v % n;
  }

 private:
  std::uint64_t state_;
};

class Run {
 public:
  Run(const Objective& f, const BatchObjective& fb, const TunerOptions& o, int n)
      : f_(f), fb_(fb), o_(o), n_(n) {
    header_ = {"eval", "phase", "cost", "status", "best_cost"};
    for (int i = 0; i < n; ++i)
      header_.push_back(i < static_cast<int>(o.dimension_names.size())
                            ? o.dimension_names[static_cast<std::size_t>(i)]
                            : "u" + std::to_string(i));
    for (const auto& h : o.log_extra_header) header_.push_back(h);
    constrained_ = Constrained(o.algorithm);
    if (constrained_) header_.push_back("constraint");
    if (!o.resume_path.empty()) {
      resume_ = std::make_unique<io::CsvRowReader>(o.resume_path);
      if (!resume_->is_open()) throw ResumeMismatch("cannot read the resume log " + o.resume_path);
      if (resume_->header_line() != io::CsvRecord(header_))
        throw ResumeMismatch("the resume log " + o.resume_path +
                             " was written for a different problem (its header differs)");
      // A log cut inside a row (the process was killed while writing it) cannot be continued
      // without rewriting it, and a log is never rewritten.
      if (!resume_->ends_with_line_break())
        throw ResumeMismatch("the resume log " + o.resume_path +
                             " ends inside a row (its last line has no line break): remove the "
                             "incomplete last line, then resume");
    }
    if (!o.log_path.empty() && !o.verify_resume) {
      std::error_code ec;
      in_place_ =
          !o.resume_path.empty() && (o.log_path == o.resume_path ||
                                     std::filesystem::equivalent(o.log_path, o.resume_path, ec));
      // Append-only: resuming into the log itself keeps the logged rows as they are, new rows
      // follow them.
      log_ = std::make_unique<io::CsvLog>(
          o.log_path, in_place_ ? io::CsvLog::Open::kAppend : io::CsvLog::Open::kCreate, header_,
          "the evaluation log");
    }
    start_ = std::chrono::steady_clock::now();
    result_.best_u.assign(static_cast<std::size_t>(n), 0.5);
  }

  /// Closes the log; throws what stopped the run (ResumeMismatch for a log that diverges).
  void Finish() {
    if (log_) log_->Close();
    if (verify_left_rows_ && mismatch_.empty())
      mismatch_ = "the resume log " + o_.resume_path +
                  " holds more evaluations than this run makes (" + std::to_string(result_.evals) +
                  " with these settings)";
    if (!mismatch_.empty()) throw ResumeMismatch(mismatch_);
    if (!error_.empty()) throw std::runtime_error(error_);
  }

  /// After a verifying run: whether rows of the resume log were left unread.
  void NoteUnreadRows() {
    if (!o_.verify_resume || !resume_ || !resume_->is_open()) return;
    std::vector<std::string> cells;
    verify_left_rows_ = resume_->Next(&cells) != io::CsvRowReader::Row::kEnd;
  }

  void RunPhase(const AlgorithmName& a, int budget, std::vector<double> x,
                unsigned long long seed) {
    if (budget <= 0 || Stopped()) return;
    phase_ = a.name;
    nlopt::opt opt(a.alg, static_cast<unsigned>(n_));
    // The budget counts real evaluations (memo hits are free), so it is enforced here (Evaluate);
    // NLopt's own limit is only a safety net against an optimiser that keeps asking for known
    // points.
    Configure(opt, a, budget);
    opt.set_min_objective(&Run::Trampoline, this);
    phase_end_ = std::min(o_.max_evals, result_.evals + budget);
    for (auto& v : x) v = std::clamp(std::isfinite(v) ? v : 0.5, 0.0, 1.0);
    opt_ = &opt;
    nlopt::srand(seed);
    double f = 0;
    nlopt::result r = nlopt::FAILURE;
    try {
      r = opt.optimize(x, f);
    } catch (const nlopt::forced_stop&) {
      r = nlopt::FORCED_STOP;
    } catch (const nlopt::roundoff_limited&) {
      r = nlopt::ROUNDOFF_LIMITED;
    } catch (const std::exception& e) {
      if (error_.empty()) error_ = std::string("optimizer error: ") + e.what();
    }
    opt_ = nullptr;
    NoteResult(r);
  }

  /// The batched global phase: a Latin hypercube of `budget` points, o.batch per objective call.
  void RunDesign(int budget, unsigned long long seed) {
    if (Stopped()) return;
    if (result_.evals >= o_.max_evals) {
      if (reason_.empty()) reason_ = "max_evals";
      return;
    }
    budget = std::min(budget, o_.max_evals - result_.evals);
    if (budget <= 0) return;
    phase_ = kDesign;
    phase_end_ = result_.evals + budget;
    const auto design = LatinHypercube(budget, n_, seed);
    const auto k = static_cast<std::size_t>(o_.batch);
    for (std::size_t at = 0; at < design.size() && reason_.empty(); at += k) {
      const auto end = design.begin() + static_cast<long>(std::min(design.size(), at + k));
      EvaluateBatch(std::vector<std::vector<double>>(design.begin() + static_cast<long>(at), end));
    }
    if (reason_.empty() && result_.evals >= phase_end_) reason_ = "max_evals";
  }

  /// Up to `searches` runs of the local algorithm `a`, one thread each, from the best points so
  /// far, in lockstep (see the header) until the budget is spent, they end or the run stops.
  void RunLockstep(const AlgorithmName& a, int searches, unsigned long long seed) {
    const int budget = o_.max_evals - result_.evals;
    if (budget <= 0 || Stopped()) return;
    phase_ = a.name;
    phase_end_ = o_.max_evals;
    // Start points: the best points evaluated so far; equal costs: the earlier evaluation first.
    std::vector<const std::pair<const std::vector<double>, Known>*> ranked;
    for (const auto& entry : memo_) ranked.push_back(&entry);
    std::sort(ranked.begin(), ranked.end(), [](const auto* p, const auto* q) {
      return p->second.cost != q->second.cost ? p->second.cost < q->second.cost
                                              : p->second.index < q->second.index;
    });
    const std::size_t count = std::min(ranked.size(), static_cast<std::size_t>(searches));
    std::vector<Search> all(count);  // never resized: the threads hold references
    for (std::size_t i = 0; i < count; ++i) {
      all[i].run = this;
      all[i].x = ranked[i]->first;
    }
    std::vector<std::thread> threads;
    threads.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
      try {
        threads.emplace_back(&Run::RunSearch, this, std::ref(all[i]), std::cref(a), budget,
                             seed + i);
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(gate_);
        all[i].error = std::string("cannot start a search thread: ") + e.what();
        all[i].state = Search::kDone;
      }
    }
    // Rounds: wait until every search has asked or ended, evaluate the asked points as one batch
    // in search order, hand out the costs. An exception halts every search before it is rethrown
    // (the threads must be joined first).
    std::exception_ptr failure;
    for (;;) {
      std::vector<Search*> asking;
      std::vector<std::vector<double>> points;
      {
        std::unique_lock<std::mutex> lock(gate_);
        gate_cv_.wait(lock, [&all] {
          return std::all_of(all.begin(), all.end(), [](const Search& s) {
            return s.state == Search::kAsked || s.state == Search::kDone;
          });
        });
        for (auto& s : all)
          if (s.state == Search::kAsked) {
            asking.push_back(&s);
            points.push_back(s.asked);
          }
      }
      if (asking.empty()) break;
      // The searches wait for their answers, so the memo and the log are the coordinator's here.
      std::vector<Answer> answers;
      if (!failure) {
        try {
          answers = EvaluateBatch(points);
        } catch (...) {
          failure = std::current_exception();
        }
      }
      if (failure) answers.assign(points.size(), Answer{o_.failure_cost, true});
      {
        std::lock_guard<std::mutex> lock(gate_);
        for (std::size_t k = 0; k < asking.size(); ++k) {
          asking[k]->answer = answers[k];
          asking[k]->state = Search::kAnswered;
        }
      }
      gate_cv_.notify_all();
    }
    for (auto& t : threads) t.join();
    if (failure) std::rethrow_exception(failure);
    for (const auto& s : all)
      if (!s.error.empty() && error_.empty()) error_ = s.error;
    for (const auto& s : all) NoteResult(s.result);
  }

  /// Evaluation 0: the start point itself, whatever the algorithm.
  void EvaluateStart(std::vector<double> x) {
    phase_ = "start";
    for (auto& v : x) v = std::clamp(std::isfinite(v) ? v : 0.5, 0.0, 1.0);
    Evaluate(x);
  }

  bool Stopped() const {
    return !reason_.empty() && reason_ != "max_evals" && reason_ != "converged";
  }
  int evals() const { return result_.evals; }
  TuneResult& result() { return result_; }
  std::string& reason() { return reason_; }

 private:
  struct Known {
    double cost;
    int index;                ///< evaluation number
    double constraint = 0.0;  ///< auglag only
  };
  struct Answer {
    double cost;
    bool halt;  ///< the point was not evaluated: the search must stop
  };
  /// One lockstep search; its fields are guarded by gate_ while the search runs.
  struct Search {
    enum State { kRunning, kAsked, kAnswered, kDone };
    Run* run = nullptr;
    std::vector<double> x;      ///< start point
    std::vector<double> asked;  ///< the point waiting for its cost
    Answer answer{0.0, false};
    State state = kRunning;
    nlopt::opt* opt = nullptr;  ///< used by the search's own thread only
    nlopt::result result = nlopt::FAILURE;
    std::string error;
  };
  enum class Replayed { kNo, kYes, kMismatch };

  void Configure(nlopt::opt& opt, const AlgorithmName& a, int budget) {
    opt.set_lower_bounds(std::vector<double>(static_cast<std::size_t>(n_), 0.0));
    opt.set_upper_bounds(std::vector<double>(static_cast<std::size_t>(n_), 1.0));
    opt.set_maxeval(4 * budget + 100);
    opt.set_xtol_abs(o_.xtol_abs);
    if (!a.global) opt.set_initial_step(o_.initial_step);
    if (a.alg == nlopt::GN_CRS2_LM || a.alg == nlopt::GN_ISRES)
      opt.set_population(static_cast<unsigned>(o_.population > 0 ? o_.population : 5 * (n_ + 1)));
    // MLSL (multi-level single linkage on a low-discrepancy sequence) starts local Subplex
    // searches from the most promising of its sample points; AUGLAG solves its augmented
    // Lagrangian's subproblems with Subplex, the clean-lap budget as the inequality constraint.
    if (a.alg == nlopt::G_MLSL_LDS || a.alg == nlopt::AUGLAG) {
      nlopt::opt local(nlopt::LN_SBPLX, static_cast<unsigned>(n_));
      local.set_lower_bounds(std::vector<double>(static_cast<std::size_t>(n_), 0.0));
      local.set_upper_bounds(std::vector<double>(static_cast<std::size_t>(n_), 1.0));
      local.set_xtol_abs(o_.xtol_abs);
      local.set_initial_step(o_.initial_step);
      opt.set_local_optimizer(local);
    }
    if (a.alg == nlopt::AUGLAG)
      opt.add_inequality_constraint(&Run::ConstraintTrampoline, this, 0.0);
  }

  void NoteResult(nlopt::result r) {
    if (reason_.empty()) {
      if (r == nlopt::MAXEVAL_REACHED) reason_ = "max_evals";
      if (r == nlopt::XTOL_REACHED || r == nlopt::FTOL_REACHED) reason_ = "converged";
    }
  }

  /// Body of a search thread. NLopt's generator is thread-local: seeded here, in this thread.
  void RunSearch(Search& s, const AlgorithmName& a, int budget, unsigned long long seed) {
    nlopt::result r = nlopt::FAILURE;
    std::string error;
    try {
      nlopt::opt opt(a.alg, static_cast<unsigned>(n_));
      Configure(opt, a, budget);
      opt.set_min_objective(&Run::GateTrampoline, &s);
      s.opt = &opt;
      nlopt::srand(seed);
      double f = 0;
      try {
        r = opt.optimize(s.x, f);
      } catch (const nlopt::forced_stop&) {
        r = nlopt::FORCED_STOP;
      } catch (const nlopt::roundoff_limited&) {
        r = nlopt::ROUNDOFF_LIMITED;
      }
    } catch (const std::exception& e) {
      error = std::string("optimizer error: ") + e.what();
    } catch (...) {
      error = "optimizer error";
    }
    std::lock_guard<std::mutex> lock(gate_);
    s.opt = nullptr;
    s.result = r;
    s.error = error;
    s.state = Search::kDone;
    gate_cv_.notify_all();
  }

  static double GateTrampoline(unsigned n, const double* x, double* /*grad*/, void* data) {
    auto& s = *static_cast<Search*>(data);
    return s.run->Ask(s, std::vector<double>(x, x + n));
  }

  /// A search's objective: a known point is answered at once, a new one waits for its round.
  double Ask(Search& s, std::vector<double> u) {
    std::unique_lock<std::mutex> lock(gate_);
    if (auto hit = memo_.find(u); hit != memo_.end()) return hit->second.cost;
    s.asked = std::move(u);
    s.state = Search::kAsked;
    gate_cv_.notify_all();
    gate_cv_.wait(lock, [&s] { return s.state == Search::kAnswered; });
    s.state = Search::kRunning;
    if (s.answer.halt) s.opt->force_stop();
    return s.answer.cost;
  }

  static double Trampoline(unsigned n, const double* x, double* /*grad*/, void* data) {
    return static_cast<Run*>(data)->Evaluate(std::vector<double>(x, x + n));
  }

  /// AUGLAG asks for the constraint at the point whose cost it has just asked for: the memo holds
  /// it. A point not evaluated (the run stopped) counts as violating.
  static double ConstraintTrampoline(unsigned n, const double* x, double* /*grad*/, void* data) {
    Run& run = *static_cast<Run*>(data);
    const std::vector<double> u(x, x + n);
    if (auto hit = run.memo_.find(u); hit != run.memo_.end()) return hit->second.constraint;
    run.Evaluate(u);
    const auto hit = run.memo_.find(u);
    return hit != run.memo_.end() ? hit->second.constraint : 1.0;
  }

  double Elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

  static std::vector<std::string> Cells(const std::vector<double>& u) {
    std::vector<std::string> out;
    for (double v : u) out.push_back(params::FormatDouble(v));
    return out;
  }

  /// The log does not belong to this run, or cannot be written: nothing more is evaluated.
  bool Broken() const { return !mismatch_.empty() || !error_.empty(); }

  double Evaluate(const std::vector<double>& u) {
    if (Broken()) return Halt(reason_.empty() ? "resume_mismatch" : reason_);
    if (o_.stop && o_.stop->load()) return Halt("interrupted");
    if (result_.evals >= std::min(o_.max_evals, phase_end_)) return Halt("max_evals");
    const double elapsed = Elapsed();
    if (o_.max_time_s > 0 && elapsed >= o_.max_time_s) return Halt("max_time");

    // A point asked for again (Subplex re-evaluates its start, CRS2 its x0): the objective is
    // deterministic, so its cost is reused — no new evaluation, no log row.
    if (auto hit = memo_.find(u); hit != memo_.end()) return hit->second.cost;

    const std::vector<std::string> ucells = Cells(u);
    Evaluation ev;
    const Replayed replayed = ReplayNext(ucells, &ev);
    if (replayed == Replayed::kMismatch) return Halt("resume_mismatch");
    if (replayed == Replayed::kNo && o_.verify_resume) return Halt("verified");
    if (replayed == Replayed::kNo) ev = Call(u);
    const double cost = ev.cost;
    if (!Record(u, ucells, std::move(ev), elapsed, replayed == Replayed::kYes))
      return Halt("log_error");
    return cost;
  }

  /// Evaluates `points` (in order, one objective call for the new ones) and answers each: its
  /// cost, or a halt when the run stops before it. A batch is refused whole on the stop flag or
  /// the time limit; the budget admits its first new points only.
  std::vector<Answer> EvaluateBatch(const std::vector<std::vector<double>>& points) {
    std::vector<Answer> out(points.size(), Answer{o_.failure_cost, true});
    if (Broken()) return out;
    if (o_.stop && o_.stop->load()) {
      Halt("interrupted");
      return out;
    }
    if (o_.max_time_s > 0 && Elapsed() >= o_.max_time_s) {
      Halt("max_time");
      return out;
    }
    // The points to evaluate: new ones (not known, not earlier in this batch) within the budget.
    const int limit = std::min(o_.max_evals, phase_end_);
    std::vector<std::size_t> fresh;
    std::map<std::vector<double>, std::size_t> seen;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!seen.emplace(points[i], i).second || memo_.count(points[i])) continue;
      if (result_.evals + static_cast<int>(fresh.size()) >= limit) {
        Halt("max_evals");
        continue;
      }
      fresh.push_back(i);
    }
    // Replayed from the resume log as far as it goes, then the rest in one call.
    std::vector<std::vector<std::string>> cells(fresh.size());
    std::size_t done = 0;
    bool ok = true;
    for (; done < fresh.size(); ++done) {
      const auto& u = points[fresh[done]];
      cells[done] = Cells(u);
      Evaluation ev;
      const Replayed replayed = ReplayNext(cells[done], &ev);
      if (replayed == Replayed::kNo) break;
      ok = replayed == Replayed::kYes ? Record(u, cells[done], std::move(ev), Elapsed(), true)
                                      : false;
      if (!ok) {
        Halt(replayed == Replayed::kYes ? "log_error" : "resume_mismatch");
        break;
      }
    }
    if (ok && done < fresh.size() && o_.verify_resume) {
      Halt("verified");
      return out;
    }
    if (ok && done < fresh.size()) {
      std::vector<std::vector<double>> todo;
      for (std::size_t k = done; k < fresh.size(); ++k) todo.push_back(points[fresh[k]]);
      std::vector<Evaluation> evs = CallBatch(todo);
      for (std::size_t k = done; k < fresh.size(); ++k) {
        if (cells[k].empty()) cells[k] = Cells(points[fresh[k]]);
        if (!Record(points[fresh[k]], cells[k], std::move(evs[k - done]), Elapsed(), false)) {
          Halt("log_error");
          break;
        }
      }
    }
    for (std::size_t i = 0; i < points.size(); ++i)
      if (auto hit = memo_.find(points[i]); hit != memo_.end()) out[i] = {hit->second.cost, false};
    return out;
  }

  /// The next row of the resume log, if it is open and not exhausted; kMismatch (with error_ set)
  /// if that row holds another point.
  Replayed ReplayNext(const std::vector<std::string>& ucells, Evaluation* ev) {
    if (!resume_ || !resume_->is_open()) return Replayed::kNo;
    std::vector<std::string> cells;
    const io::CsvRowReader::Row row = resume_->Next(&cells);
    if (row == io::CsvRowReader::Row::kEnd) {
      resume_->Close();  // log exhausted: continue with real evaluations
      return Replayed::kNo;
    }
    bool match = row == io::CsvRowReader::Row::kCells;  // a malformed row is not the logged point
    const std::size_t nu = static_cast<std::size_t>(n_);
    match = match && cells.size() == header_.size();
    for (std::size_t i = 0; match && i < nu; ++i) match = cells[5 + i] == ucells[i];
    if (!match) {
      mismatch_ = "the resume log " + o_.resume_path + " diverges at evaluation " +
                  std::to_string(result_.evals) +
                  " (different settings, seed or problem than the logged run)";
      return Replayed::kMismatch;
    }
    params::ParseDouble(cells[2], &ev->cost);
    ev->status = cells[3];
    ev->columns.assign(cells.begin() + 5 + static_cast<long>(nu), cells.end());
    if (constrained_ && !ev->columns.empty()) {
      params::ParseDouble(ev->columns.back(), &ev->constraint);
      ev->columns.pop_back();
    }
    ++result_.replayed;
    return Replayed::kYes;
  }

  static void CleanStatus(Evaluation& ev) {
    for (auto& c : ev.status)
      if (c == ',' || c == '\n') c = ';';
  }

  void PenaliseNonFinite(Evaluation& ev) const {
    if (!std::isfinite(ev.cost)) {
      ev.status = "non-finite cost";
      ev.cost = o_.failure_cost;
    }
  }

  /// One point through the objective: never throws, never non-finite.
  Evaluation Call(const std::vector<double>& u) const {
    Evaluation ev;
    try {
      ev = f_(u);
      PenaliseNonFinite(ev);
    } catch (const std::exception& e) {
      ev = Evaluation{o_.failure_cost, std::string("exception: ") + e.what(), {}};
    } catch (...) {
      ev = Evaluation{o_.failure_cost, "unknown exception", {}};
    }
    CleanStatus(ev);
    return ev;
  }

  /// Several points through the batch objective (or point by point without one); an exception
  /// fails every point of the call.
  std::vector<Evaluation> CallBatch(const std::vector<std::vector<double>>& points) const {
    std::vector<Evaluation> out;
    if (!fb_) {
      for (const auto& u : points) out.push_back(Call(u));
      return out;
    }
    try {
      out = fb_(points);
      if (out.size() != points.size())
        throw std::length_error("the batch objective returned " + std::to_string(out.size()) +
                                " results for " + std::to_string(points.size()) + " points");
      for (auto& ev : out) PenaliseNonFinite(ev);
    } catch (const std::exception& e) {
      out.assign(points.size(),
                 Evaluation{o_.failure_cost, std::string("exception: ") + e.what(), {}});
    } catch (...) {
      out.assign(points.size(), Evaluation{o_.failure_cost, "unknown exception", {}});
    }
    for (auto& ev : out) CleanStatus(ev);
    return out;
  }

  /// Logs an evaluation and updates the memo and the best; false if the log cannot be written. A
  /// row replayed from the log being appended to is already there and is not written again.
  bool Record(const std::vector<double>& u, const std::vector<std::string>& ucells, Evaluation ev,
              double elapsed, bool replayed) {
    const int index = result_.evals++;
    memo_.emplace(u, Known{ev.cost, index, ev.constraint});
    if (o_.on_record) o_.on_record(index, u, ev);
    if (index == 0) result_.start_cost = ev.cost;
    // With a constraint the best is the best point that meets it (evaluation 0, the base, does).
    if (ev.cost < result_.best_cost && (!constrained_ || ev.constraint <= 0.0)) {
      if (!std::isfinite(result_.best_cost) ||
          result_.best_cost - ev.cost > kSignificantImprovement * std::abs(result_.best_cost))
        result_.last_improvement_eval = index;
      result_.best_cost = ev.cost;
      result_.best_u = u;
      result_.best_eval = index;
    }
    if (log_ && log_->is_open() && !(replayed && in_place_)) {
      std::vector<std::string> row = {std::to_string(index), phase_, params::FormatDouble(ev.cost),
                                      ev.status, params::FormatDouble(result_.best_cost)};
      row.insert(row.end(), ucells.begin(), ucells.end());
      ev.columns.resize(o_.log_extra_header.size());
      row.insert(row.end(), ev.columns.begin(), ev.columns.end());
      if (constrained_) row.push_back(params::FormatDouble(ev.constraint));
      if (!log_->Write(row)) {  // the log keeps its whole rows, so --resume can continue from it
        error_ = log_->error();
        return false;
      }
    }
    if (o_.on_progress)
      o_.on_progress(Progress{result_.evals, o_.max_evals, result_.best_cost, elapsed, phase_});
    return true;
  }

  double Halt(const std::string& why) {
    if (reason_.empty() || reason_ == "max_evals" || reason_ == "converged") reason_ = why;
    if (opt_) opt_->force_stop();
    return o_.failure_cost;
  }

  const Objective& f_;
  const BatchObjective& fb_;
  const TunerOptions& o_;
  int n_;
  std::vector<std::string> header_;
  std::unique_ptr<io::CsvRowReader> resume_;
  std::unique_ptr<io::CsvLog> log_;
  bool in_place_ = false;          ///< appending to the resume log itself
  bool constrained_ = false;       ///< auglag: best and log respect Evaluation::constraint
  bool verify_left_rows_ = false;  ///< a verifying run left rows of the resume log unread
  std::string mismatch_;           ///< why the resume log does not belong to this run
  std::chrono::steady_clock::time_point start_;
  TuneResult result_;
  std::string phase_, reason_, error_;
  nlopt::opt* opt_ = nullptr;
  int phase_end_ = std::numeric_limits<int>::max();  ///< evaluation count that ends the phase
  std::map<std::vector<double>, Known> memo_;        ///< every point evaluated so far
  std::mutex gate_;                                  ///< lockstep: guards the searches' state
  std::condition_variable gate_cv_;
};

}  // namespace

std::vector<std::string> TunerAlgorithms() {
  std::vector<std::string> out;
  for (const auto& a : kAlgorithms) out.push_back(a.name);
  out.push_back(kDesign);
  return out;
}

void CheckTunerAlgorithm(const std::string& spec) { (void)ParsePlan(spec); }

void CheckTunerBatch(const std::string& spec, int batch) {
  if (batch < 1) throw std::invalid_argument("the batch size must be at least 1");
  if (batch > 1 && !ParsePlan(spec).design)
    throw std::invalid_argument(
        "'" + spec + "' asks for one candidate at a time; a batch of " + std::to_string(batch) +
        " needs the batched design: lhs+sbplx (or lhs, lhs+B for another local algorithm B)");
}

std::vector<std::vector<double>> LatinHypercube(int points, int dims, unsigned long long seed) {
  const auto m = static_cast<std::size_t>(std::max(points, 0));
  std::vector<std::vector<double>> design(m, std::vector<double>(static_cast<std::size_t>(dims)));
  SplitMix64 rng(seed);
  std::vector<std::size_t> stratum(m);
  for (int d = 0; d < dims; ++d) {
    // A random permutation of the strata (Fisher-Yates), a random offset inside each.
    for (std::size_t i = 0; i < m; ++i) stratum[i] = i;
    for (std::size_t i = m; i > 1; --i) std::swap(stratum[i - 1], stratum[rng.Below(i)]);
    for (std::size_t i = 0; i < m; ++i)
      design[i][static_cast<std::size_t>(d)] =
          (static_cast<double>(stratum[i]) + rng.Unit()) / static_cast<double>(m);
  }
  return design;
}

TuneResult Tune(const std::vector<double>& u0, const Objective& f, const TunerOptions& o) {
  return Tune(u0, f, BatchObjective{}, o);
}

TuneResult Tune(const std::vector<double>& u0, const Objective& f, const BatchObjective& batch_f,
                const TunerOptions& o) {
  if (u0.empty()) throw std::invalid_argument("the search space has no dimension");
  if (o.max_evals <= 0) throw std::invalid_argument("max_evals must be positive");
  const Plan plan = ParsePlan(o.algorithm);
  CheckTunerBatch(o.algorithm, o.batch);
  const int n = static_cast<int>(u0.size());
  Run run(f, batch_f, o, n);
  run.EvaluateStart(u0);
  const int budget1 = plan.second
                          ? std::max(1, static_cast<int>(std::lround(o.global_share * o.max_evals)))
                          : o.max_evals;
  if (plan.design)
    run.RunDesign(budget1, o.seed);
  else
    run.RunPhase(*plan.first, budget1, u0, o.seed);
  if (plan.second && !run.Stopped() && run.evals() < o.max_evals) {
    run.reason().clear();
    if (plan.design)
      run.RunLockstep(*plan.second, o.batch, o.seed + 1);
    else
      run.RunPhase(*plan.second, o.max_evals - run.evals(), run.result().best_u, o.seed + 1);
  }
  run.NoteUnreadRows();
  TuneResult r = run.result();
  r.stop_reason = run.reason().empty() ? "finished" : run.reason();
  run.Finish();
  return r;
}

}  // namespace scw::tuning
