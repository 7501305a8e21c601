#include "tuning/optim/tuner.h"

#include <nlopt.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

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
};

const AlgorithmName& FindAlgorithm(const std::string& name) {
  for (const auto& a : kAlgorithms)
    if (name == a.name) return a;
  std::string known;
  for (const auto& a : kAlgorithms) known += std::string(known.empty() ? "" : ", ") + a.name;
  throw std::invalid_argument("unknown algorithm '" + name + "' (known: " + known +
                              ", or A+B for a global phase A then a local polish B)");
}

std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

std::string JoinCsv(const std::vector<std::string>& cells) {
  std::string out;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i) out += ',';
    out += cells[i];
  }
  return out;
}

class Run {
 public:
  Run(const Objective& f, const TunerOptions& o, int n) : f_(f), o_(o), n_(n) {
    header_ = {"eval", "phase", "cost", "status", "best_cost"};
    for (int i = 0; i < n; ++i)
      header_.push_back(i < static_cast<int>(o.dimension_names.size())
                            ? o.dimension_names[static_cast<std::size_t>(i)]
                            : "u" + std::to_string(i));
    for (const auto& h : o.log_extra_header) header_.push_back(h);
    if (!o.resume_path.empty()) {
      resume_.open(o.resume_path);
      if (!resume_) throw std::runtime_error("cannot read the resume log " + o.resume_path);
      std::string first;
      std::getline(resume_, first);
      if (first != JoinCsv(header_))
        throw std::runtime_error("the resume log " + o.resume_path +
                                 " was written for a different problem (its header differs)");
    }
    if (!o.log_path.empty()) {
      log_target_ = o.log_path;
      log_file_ = o.log_path == o.resume_path ? o.log_path + ".resume.tmp" : o.log_path;
      log_.open(log_file_, std::ios::trunc);
      if (!log_) throw std::runtime_error("cannot write the evaluation log " + log_file_);
      const std::string head = JoinCsv(header_) + '\n';
      log_ << head << std::flush;
      if (!log_) throw std::runtime_error("cannot write the evaluation log " + log_file_);
      log_bytes_ = head.size();
    }
    start_ = std::chrono::steady_clock::now();
    result_.best_u.assign(static_cast<std::size_t>(n), 0.5);
  }

  ~Run() {
    if (log_.is_open()) log_.close();
  }

  /// Moves a "resume into the same file" log into place.
  void Finish() {
    if (log_.is_open()) {
      log_.close();
      if (log_file_ != log_target_ && std::rename(log_file_.c_str(), log_target_.c_str()) != 0)
        throw std::runtime_error("cannot replace " + log_target_ + " with the resumed log");
    }
    if (!error_.empty()) throw std::runtime_error(error_);
  }

  void RunPhase(const AlgorithmName& a, int budget, std::vector<double> x,
                unsigned long long seed) {
    if (budget <= 0 || Stopped()) return;
    phase_ = a.name;
    nlopt::opt opt(a.alg, static_cast<unsigned>(n_));
    opt.set_lower_bounds(std::vector<double>(static_cast<std::size_t>(n_), 0.0));
    opt.set_upper_bounds(std::vector<double>(static_cast<std::size_t>(n_), 1.0));
    opt.set_min_objective(&Run::Trampoline, this);
    // The budget counts real evaluations (memo hits are free), so it is enforced here (Evaluate);
    // NLopt's own limit is only a safety net against an optimiser that keeps asking for known
    // points.
    phase_end_ = std::min(o_.max_evals, result_.evals + budget);
    opt.set_maxeval(4 * budget + 100);
    opt.set_xtol_abs(o_.xtol_abs);
    if (!a.global) opt.set_initial_step(o_.initial_step);
    if (a.alg == nlopt::GN_CRS2_LM || a.alg == nlopt::GN_ISRES)
      opt.set_population(static_cast<unsigned>(o_.population > 0 ? o_.population : 5 * (n_ + 1)));
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
    if (reason_.empty()) {
      if (r == nlopt::MAXEVAL_REACHED) reason_ = "max_evals";
      if (r == nlopt::XTOL_REACHED || r == nlopt::FTOL_REACHED) reason_ = "converged";
    }
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
  static double Trampoline(unsigned n, const double* x, double* /*grad*/, void* data) {
    return static_cast<Run*>(data)->Evaluate(std::vector<double>(x, x + n));
  }

  double Evaluate(const std::vector<double>& u) {
    if (o_.stop && o_.stop->load()) return Halt("interrupted");
    if (result_.evals >= std::min(o_.max_evals, phase_end_)) return Halt("max_evals");
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (o_.max_time_s > 0 && elapsed >= o_.max_time_s) return Halt("max_time");

    // A point asked for again (Subplex re-evaluates its start, CRS2 its x0): the objective is
    // deterministic, so its cost is reused — no new evaluation, no log row.
    if (auto hit = memo_.find(u); hit != memo_.end()) return hit->second;

    std::vector<std::string> ucells;
    for (double v : u) ucells.push_back(params::FormatDouble(v));
    Evaluation ev;
    bool replayed = false;
    if (resume_.is_open()) {
      std::string line;
      if (std::getline(resume_, line) && !line.empty()) {
        const auto cells = SplitCsvLine(line);
        const std::size_t nu = static_cast<std::size_t>(n_);
        bool match = cells.size() == header_.size();
        for (std::size_t i = 0; match && i < nu; ++i) match = cells[5 + i] == ucells[i];
        if (!match) {
          error_ = "the resume log " + o_.resume_path + " diverges at evaluation " +
                   std::to_string(result_.evals) +
                   " (different settings, seed or problem than the logged run)";
          return Halt("resume_mismatch");
        }
        params::ParseDouble(cells[2], &ev.cost);
        ev.status = cells[3];
        ev.columns.assign(cells.begin() + 5 + static_cast<long>(nu), cells.end());
        replayed = true;
        ++result_.replayed;
      } else {
        resume_.close();  // log exhausted: continue with real evaluations
      }
    }
    if (!replayed) {
      try {
        ev = f_(u);
        if (!std::isfinite(ev.cost)) {
          ev.status = "non-finite cost";
          ev.cost = o_.failure_cost;
        }
      } catch (const std::exception& e) {
        ev = Evaluation{o_.failure_cost, std::string("exception: ") + e.what(), {}};
      } catch (...) {
        ev = Evaluation{o_.failure_cost, "unknown exception", {}};
      }
      for (auto& c : ev.status)
        if (c == ',' || c == '\n') c = ';';
    }
    memo_.emplace(u, ev.cost);
    const int index = result_.evals++;
    if (index == 0) result_.start_cost = ev.cost;
    if (ev.cost < result_.best_cost) {
      result_.best_cost = ev.cost;
      result_.best_u = u;
      result_.best_eval = index;
    }
    if (log_.is_open()) {
      std::vector<std::string> row = {std::to_string(index), phase_, params::FormatDouble(ev.cost),
                                      ev.status, params::FormatDouble(result_.best_cost)};
      row.insert(row.end(), ucells.begin(), ucells.end());
      ev.columns.resize(o_.log_extra_header.size());
      row.insert(row.end(), ev.columns.begin(), ev.columns.end());
      const std::string line = JoinCsv(row) + '\n';
      log_ << line << std::flush;
      if (!log_) {
        // Disk full or similar: cut the log back to its last whole row, so that it stays a valid
        // CSV that --resume can continue from.
        log_.close();
        std::error_code ec;
        std::filesystem::resize_file(log_file_, log_bytes_, ec);
        error_ = "writing the evaluation log " + log_file_ + " failed";
        return Halt("log_error");
      }
      log_bytes_ += line.size();
    }
    if (o_.on_progress)
      o_.on_progress(Progress{result_.evals, o_.max_evals, result_.best_cost, elapsed, phase_});
    return ev.cost;
  }

  double Halt(const std::string& why) {
    if (reason_.empty() || reason_ == "max_evals" || reason_ == "converged") reason_ = why;
    if (opt_) opt_->force_stop();
    return o_.failure_cost;
  }

  const Objective& f_;
  const TunerOptions& o_;
  int n_;
  std::vector<std::string> header_;
  std::ifstream resume_;
  std::ofstream log_;
  std::uintmax_t log_bytes_ = 0;  ///< size of the log's whole rows written so far
  std::string log_file_, log_target_;
  std::chrono::steady_clock::time_point start_;
  TuneResult result_;
  std::string phase_, reason_, error_;
  nlopt::opt* opt_ = nullptr;
  int phase_end_ = std::numeric_limits<int>::max();  ///< evaluation count that ends the phase
  std::map<std::vector<double>, double> memo_;       ///< cost of every point evaluated so far
};

}  // namespace

std::vector<std::string> TunerAlgorithms() {
  std::vector<std::string> out;
  for (const auto& a : kAlgorithms) out.push_back(a.name);
  return out;
}

void CheckTunerAlgorithm(const std::string& spec) {
  const auto plus = spec.find('+');
  (void)FindAlgorithm(spec.substr(0, plus));
  if (plus != std::string::npos) (void)FindAlgorithm(spec.substr(plus + 1));
}

TuneResult Tune(const std::vector<double>& u0, const Objective& f, const TunerOptions& o) {
  if (u0.empty()) throw std::invalid_argument("the search space has no dimension");
  if (o.max_evals <= 0) throw std::invalid_argument("max_evals must be positive");
  const auto plus = o.algorithm.find('+');
  const AlgorithmName& first = FindAlgorithm(o.algorithm.substr(0, plus));
  const AlgorithmName* second =
      plus == std::string::npos ? nullptr : &FindAlgorithm(o.algorithm.substr(plus + 1));
  const int n = static_cast<int>(u0.size());
  Run run(f, o, n);
  run.EvaluateStart(u0);
  const int budget1 = second
                          ? std::max(1, static_cast<int>(std::lround(o.global_share * o.max_evals)))
                          : o.max_evals;
  run.RunPhase(first, budget1, u0, o.seed);
  if (second && !run.Stopped() && run.evals() < o.max_evals) {
    run.reason().clear();
    run.RunPhase(*second, o.max_evals - run.evals(), run.result().best_u, o.seed + 1);
  }
  TuneResult r = run.result();
  r.stop_reason = run.reason().empty() ? "finished" : run.reason();
  run.Finish();
  return r;
}

}  // namespace scw::tuning
