#include "tuning/optim/tuner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <utility>

#include "params/io/atomic_file.h"
#include "params/io/write.h"
#include "params/io/yaml_doc.h"

namespace scw::tuning {
namespace {

// Shifted, rotated-ish quadratic with a known optimum at (0.3, 0.7, 0.55, 0.2).
Evaluation Bowl(const std::vector<double>& u) {
  const double t[] = {0.3, 0.7, 0.55, 0.2};
  double c = 0;
  for (std::size_t i = 0; i < u.size(); ++i) {
    const double d = u[i] - t[i];
    c += (1.0 + i) * d * d;
  }
  c += 0.5 * (u[0] - t[0]) * (u[1] - t[1]);
  return {c, "ok", {std::to_string(c)}};
}

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / name).string();
}

TEST(TunerTest, ConvergesOnASyntheticObjective) {
  for (const std::string alg : {"crs2+sbplx", "sbplx", "bobyqa", "isres+sbplx"}) {
    SCOPED_TRACE(alg);
    TunerOptions o;
    o.algorithm = alg;
    o.max_evals = 600;
    o.seed = 7;
    const auto r = Tune({0.9, 0.1, 0.9, 0.9}, Bowl, o);
    EXPECT_LT(r.best_cost, 1e-4);
    EXPECT_NEAR(r.best_u[0], 0.3, 0.02);
    EXPECT_NEAR(r.best_u[1], 0.7, 0.02);
    EXPECT_LE(r.evals, 600);
  }
}

// auglag (issue 47's benchmark of the constrained tune): the bowl's optimum lies outside the
// constraint u0 <= 0.2; the best is the best point that meets it, the log carries the constraint,
// and a resume replays it.
TEST(TunerTest, AuglagKeepsTheBestWithinTheConstraintAndLogsIt) {
  const auto f = [](const std::vector<double>& u) {
    Evaluation ev = Bowl(u);
    ev.constraint = u[0] - 0.2;
    return ev;
  };
  TunerOptions o;
  o.algorithm = "auglag";
  o.max_evals = 400;
  o.log_extra_header = {"c"};
  o.log_path = TempPath("scw_tuner_auglag.csv");
  const auto r = Tune({0.1, 0.1, 0.9, 0.9}, f, o);
  EXPECT_LE(r.best_u[0], 0.2);
  EXPECT_GT(r.best_u[0], 0.1);  // it moved toward the bound
  EXPECT_LT(r.best_cost, Bowl({0.1, 0.1, 0.9, 0.9}).cost);
  std::ifstream in(o.log_path);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.substr(header.rfind(',') + 1), "constraint") << header;
  TunerOptions again = o;
  again.resume_path = o.log_path;
  again.log_path = TempPath("scw_tuner_auglag_2.csv");
  const auto replayed = Tune({0.1, 0.1, 0.9, 0.9}, f, again);
  EXPECT_EQ(replayed.replayed, r.evals);
  EXPECT_EQ(replayed.best_u, r.best_u);
  std::filesystem::remove(o.log_path);
  std::filesystem::remove(again.log_path);
}

TEST(TunerTest, ThrowingOrNaNObjectiveDoesNotCrash) {
  int calls = 0;
  auto nasty = [&](const std::vector<double>& u) -> Evaluation {
    ++calls;
    if (calls % 3 == 0) throw std::runtime_error("simulation exploded");
    if (calls % 5 == 0) return {std::nan(""), "ok", {}};
    return Bowl(u);
  };
  TunerOptions o;
  o.max_evals = 120;
  o.log_path = TempPath("scw_tuner_nasty.csv");
  const auto r = Tune({0.5, 0.5, 0.5, 0.5}, nasty, o);
  EXPECT_TRUE(std::isfinite(r.best_cost));
  EXPECT_LT(r.best_cost, 0.5);
  const std::string log = params::ReadTextFile(o.log_path);
  EXPECT_NE(log.find("exception: simulation exploded"), std::string::npos);
  EXPECT_NE(log.find("non-finite cost"), std::string::npos);
}

TEST(TunerTest, SameSeedSameLog) {
  TunerOptions o;
  o.max_evals = 80;
  o.seed = 3;
  o.log_extra_header = {"echo"};
  o.log_path = TempPath("scw_tuner_a.csv");
  const auto a = Tune({0.5, 0.5, 0.5, 0.5}, Bowl, o);
  o.log_path = TempPath("scw_tuner_b.csv");
  const auto b = Tune({0.5, 0.5, 0.5, 0.5}, Bowl, o);
  EXPECT_EQ(a.best_u, b.best_u);
  EXPECT_EQ(params::ReadTextFile(TempPath("scw_tuner_a.csv")),
            params::ReadTextFile(TempPath("scw_tuner_b.csv")));
}

TEST(TunerTest, StopFlagKeepsBestAndResumeContinuesIdentically) {
  TunerOptions o;
  o.max_evals = 150;
  o.seed = 11;
  o.log_extra_header = {"echo"};
  // Reference: uninterrupted.
  o.log_path = TempPath("scw_tuner_full.csv");
  const auto full = Tune({0.5, 0.5, 0.5, 0.5}, Bowl, o);

  // Interrupted after 60 evaluations (as Ctrl-C would).
  std::atomic<bool> stop{false};
  int calls = 0;
  auto counting = [&](const std::vector<double>& u) {
    if (++calls == 60) stop = true;
    return Bowl(u);
  };
  o.stop = &stop;
  o.log_path = TempPath("scw_tuner_part.csv");
  const auto part = Tune({0.5, 0.5, 0.5, 0.5}, counting, o);
  EXPECT_EQ(part.stop_reason, "interrupted");
  EXPECT_EQ(part.evals, 60);
  EXPECT_TRUE(std::isfinite(part.best_cost));

  // Resume into the same log: the 60 logged evaluations are replayed, not recomputed.
  stop = false;
  int fresh_calls = 0;
  auto fresh = [&](const std::vector<double>& u) {
    ++fresh_calls;
    return Bowl(u);
  };
  o.resume_path = o.log_path;
  const auto resumed = Tune({0.5, 0.5, 0.5, 0.5}, fresh, o);
  EXPECT_EQ(resumed.replayed, 60);
  EXPECT_EQ(fresh_calls, full.evals - 60);
  EXPECT_EQ(resumed.best_u, full.best_u);
  EXPECT_EQ(resumed.best_cost, full.best_cost);
  EXPECT_EQ(params::ReadTextFile(TempPath("scw_tuner_part.csv")),
            params::ReadTextFile(TempPath("scw_tuner_full.csv")));
}

TEST(TunerTest, ResumeWithDifferentSeedIsRefused) {
  TunerOptions o;
  o.algorithm = "crs2+sbplx";  // a stochastic one: the seed changes the run
  o.max_evals = 40;
  o.seed = 1;
  o.log_path = TempPath("scw_tuner_seed.csv");
  Tune({0.5, 0.5, 0.5, 0.5}, Bowl, o);
  o.seed = 2;
  o.resume_path = o.log_path;
  o.log_path = TempPath("scw_tuner_seed2.csv");
  EXPECT_THROW(Tune({0.5, 0.5, 0.5, 0.5}, Bowl, o), std::runtime_error);
}

// The log is append-only: a resume into the log itself that diverges (another seed) is found
// while replaying and leaves every byte as it was; verify_resume replays without writing at all.
TEST(TunerTest, ADivergingResumeIntoTheLogItselfLeavesItByteIdentical) {
  TunerOptions o;
  o.algorithm = "crs2+sbplx";  // a stochastic one: another seed diverges
  o.max_evals = 30;
  o.log_path = TempPath("scw_tuner_append.csv");
  std::atomic<bool> stop{false};
  int calls = 0;
  o.stop = &stop;
  Tune(
      {0.5, 0.5, 0.5, 0.5},
      [&](const std::vector<double>& u) {
        if (++calls == 12) stop = true;
        return Bowl(u);
      },
      o);
  o.stop = nullptr;
  const std::string logged = params::ReadTextFile(o.log_path);
  o.resume_path = o.log_path;
  o.seed = 2;
  EXPECT_THROW(Tune({0.5, 0.5, 0.5, 0.5}, Bowl, o), ResumeMismatch);
  EXPECT_EQ(params::ReadTextFile(o.log_path), logged);
  // Verifying with the right seed replays the 12 rows, calls nothing and writes nothing.
  o.seed = 1;
  o.verify_resume = true;
  int verify_calls = 0;
  const auto v = Tune(
      {0.5, 0.5, 0.5, 0.5},
      [&](const std::vector<double>& u) {
        ++verify_calls;
        return Bowl(u);
      },
      o);
  EXPECT_EQ(v.stop_reason, "verified");
  EXPECT_EQ(v.replayed, 12);
  EXPECT_EQ(verify_calls, 0);
  EXPECT_EQ(params::ReadTextFile(o.log_path), logged);
  // A log cut inside its last row is refused, never repaired by rewriting.
  io::WriteFileAtomic(TempPath("scw_tuner_torn.csv"), logged.substr(0, logged.size() - 3));
  o.verify_resume = false;
  o.resume_path = o.log_path = TempPath("scw_tuner_torn.csv");
  EXPECT_THROW(Tune({0.5, 0.5, 0.5, 0.5}, Bowl, o), ResumeMismatch);
  EXPECT_EQ(params::ReadTextFile(o.log_path), logged.substr(0, logged.size() - 3));
}

std::vector<std::vector<std::string>> LogRows(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream cs(line);
    while (std::getline(cs, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

TEST(TunerTest, EvaluationZeroIsTheStartPointForEveryAlgorithm) {
  const std::vector<double> u0 = {0.125, 0.8, 0.4, 0.6};
  for (const std::string alg : {"crs2+sbplx", "direct_l", "isres", "esch", "sbplx", "neldermead",
                                "bobyqa", "cobyla", "lhs", "lhs+sbplx"}) {
    SCOPED_TRACE(alg);
    TunerOptions o;
    o.algorithm = alg;
    o.max_evals = 60;
    o.log_path = TempPath("scw_tuner_start_" + alg + ".csv");
    const auto r = Tune(u0, Bowl, o);
    const auto rows = LogRows(o.log_path);
    ASSERT_EQ(static_cast<int>(rows.size()), r.evals);
    ASSERT_GE(rows.size(), 1u);
    EXPECT_EQ(rows[0][0], "0");
    EXPECT_EQ(rows[0][1], "start");
    int at_start = 0;
    for (const auto& row : rows) {
      bool same = true;
      for (std::size_t i = 0; i < u0.size(); ++i)
        same = same && row[5 + i] == params::FormatDouble(u0[i]);
      at_start += same;
    }
    // Asked for again (Subplex, CRS2 evaluate their start point): reused, not logged twice.
    EXPECT_EQ(at_start, 1);
    EXPECT_EQ(r.start_cost, Bowl(u0).cost);
    EXPECT_LE(r.best_cost, r.start_cost);
  }
}

TEST(TunerTest, OneEvaluationKeepsTheStartPoint) {
  TunerOptions o;
  o.max_evals = 1;
  const std::vector<double> u0 = {0.9, 0.1, 0.9, 0.9};
  const auto r = Tune(u0, Bowl, o);
  EXPECT_EQ(r.evals, 1);
  EXPECT_EQ(r.best_eval, 0);
  EXPECT_EQ(r.best_u, u0);
  EXPECT_EQ(r.stop_reason, "max_evals");
}

TEST(TunerTest, UnknownAlgorithmIsRejected) {
  TunerOptions o;
  o.algorithm = "magic";
  EXPECT_THROW(Tune({0.5}, Bowl, o), std::invalid_argument);
}

// ---- Batched search: "lhs" and "lhs+B" with TunerOptions::batch ----

/// Minimum 0 at t_i = 0.2 + 0.6·frac(0.37·i), unevenly scaled, in any dimension.
double ShiftedTarget(std::size_t i) {
  const double f = 0.37 * static_cast<double>(i);
  return 0.2 + 0.6 * (f - std::floor(f));
}

Evaluation Shifted(const std::vector<double>& u) {
  double c = 0;
  for (std::size_t i = 0; i < u.size(); ++i) {
    const double d = u[i] - ShiftedTarget(i);
    c += (1.0 + 0.5 * static_cast<double>(i % 4)) * d * d;
  }
  return {c, "ok", {params::FormatDouble(c)}};
}

/// A batch objective that evaluates its points on `threads` threads into per-index slots, the
/// points finishing in an irregular order; counts its calls and the largest batch.
struct ThreadedBatch {
  ThreadedBatch(Objective fn, int n_threads) : f(std::move(fn)), threads(n_threads) {}

  Objective f;
  int threads;
  int calls = 0;
  std::size_t largest = 0;
  std::vector<std::size_t> sizes;         // points per call
  bool jitter = true;                     // points take unequal times
  std::function<void(int call)> on_call;  // e.g. sets a stop flag

  BatchObjective Get() {
    return [this](const std::vector<std::vector<double>>& points) {
      ++calls;
      largest = std::max(largest, points.size());
      sizes.push_back(points.size());
      if (on_call) on_call(calls);
      std::vector<Evaluation> out(points.size());
      std::atomic<std::size_t> next{0};
      auto work = [&] {
        for (std::size_t i = next++; i < points.size(); i = next++) {
          if (jitter)
            std::this_thread::sleep_for(std::chrono::microseconds(50 * ((i * 7 + 3) % 5)));
          out[i] = f(points[i]);
        }
      };
      std::vector<std::thread> pool;
      for (int t = 1; t < threads; ++t) pool.emplace_back(work);
      work();
      for (auto& t : pool) t.join();
      return out;
    };
  }
};

TEST(TunerBatchTest, LatinHypercubeHasOnePointPerStratumInEveryDimension) {
  const auto design = LatinHypercube(37, 5, 9);
  ASSERT_EQ(design.size(), 37u);
  for (std::size_t d = 0; d < 5; ++d) {
    std::vector<int> hits(37, 0);
    for (const auto& x : design) {
      ASSERT_EQ(x.size(), 5u);
      ASSERT_GE(x[d], 0.0);
      ASSERT_LT(x[d], 1.0);
      ++hits[static_cast<std::size_t>(x[d] * 37.0)];
    }
    for (int h : hits) EXPECT_EQ(h, 1);
  }
  EXPECT_EQ(design, LatinHypercube(37, 5, 9));
  EXPECT_NE(design, LatinHypercube(37, 5, 10));
}

TEST(TunerBatchTest, OnlyTheBatchedDesignTakesMoreThanOneCandidate) {
  EXPECT_NO_THROW(CheckTunerAlgorithm("lhs+sbplx"));
  EXPECT_NO_THROW(CheckTunerAlgorithm("lhs"));
  EXPECT_THROW(CheckTunerAlgorithm("sbplx+lhs"), std::invalid_argument);
  EXPECT_NO_THROW(CheckTunerBatch("crs2+sbplx", 1));
  EXPECT_NO_THROW(CheckTunerBatch("lhs+sbplx", 4));
  EXPECT_NO_THROW(CheckTunerBatch("lhs+neldermead", 3));
  EXPECT_THROW(CheckTunerBatch("crs2+sbplx", 2), std::invalid_argument);
  EXPECT_THROW(CheckTunerBatch("sbplx", 2), std::invalid_argument);
  EXPECT_THROW(CheckTunerBatch("lhs+sbplx", 0), std::invalid_argument);
  TunerOptions o;
  o.batch = 2;
  o.max_evals = 10;
  EXPECT_THROW(Tune({0.5, 0.5}, Bowl, o), std::invalid_argument);  // the default, sbplx
}

TEST(TunerBatchTest, SameLogForAnyNumberOfEvaluatorThreads) {
  const std::vector<double> u0(8, 0.5);
  for (int batch : {1, 2, 4}) {
    SCOPED_TRACE(batch);
    TunerOptions o;
    o.algorithm = "lhs+sbplx";
    o.batch = batch;
    o.max_evals = 120;
    o.seed = 5;
    o.log_extra_header = {"echo"};
    // Point by point (no batch objective) is the reference.
    o.log_path = TempPath("scw_tuner_batch_ref.csv");
    const auto ref = Tune(u0, Shifted, o);
    const std::string ref_log = params::ReadTextFile(o.log_path);
    EXPECT_EQ(ref.evals, 120);
    for (int threads : {1, 2, 3, 2}) {
      SCOPED_TRACE(threads);
      ThreadedBatch tb{Shifted, threads};
      o.log_path = TempPath("scw_tuner_batch_t.csv");
      const auto r = Tune(u0, Shifted, tb.Get(), o);
      EXPECT_EQ(params::ReadTextFile(o.log_path), ref_log);
      EXPECT_EQ(r.best_u, ref.best_u);
      EXPECT_EQ(r.best_cost, ref.best_cost);
      EXPECT_LE(tb.largest, static_cast<std::size_t>(batch));
      EXPECT_EQ(tb.largest, static_cast<std::size_t>(batch));
    }
  }
}

TEST(TunerBatchTest, TheDesignDoesNotDependOnTheBatchSize) {
  TunerOptions o;
  o.algorithm = "lhs";
  o.max_evals = 41;
  o.seed = 8;
  std::string logs[3];
  for (int batch : {1, 3, 7}) {
    o.batch = batch;
    o.log_path = TempPath("scw_tuner_design.csv");
    ThreadedBatch tb{Shifted, 2};
    EXPECT_EQ(Tune(std::vector<double>(5, 0.5), Shifted, tb.Get(), o).evals, 41);
    logs[batch / 3] = params::ReadTextFile(o.log_path);
  }
  EXPECT_EQ(logs[0], logs[1]);
  EXPECT_EQ(logs[0], logs[2]);
}

TEST(TunerBatchTest, BudgetIsRespectedAndEvaluationZeroIsTheStartPoint) {
  const std::vector<double> u0 = {0.125, 0.8, 0.4, 0.6, 0.3};
  for (const std::string alg : {"lhs+sbplx", "lhs", "lhs+neldermead"}) {
    for (int batch : {1, 3}) {
      SCOPED_TRACE(alg + " batch " + std::to_string(batch));
      TunerOptions o;
      o.algorithm = alg;
      o.batch = batch;
      o.max_evals = 50;
      o.log_path = TempPath("scw_tuner_batch_budget.csv");
      ThreadedBatch tb{Shifted, 2};
      const auto r = Tune(u0, Shifted, tb.Get(), o);
      EXPECT_EQ(r.evals, 50);
      EXPECT_EQ(r.stop_reason, "max_evals");
      EXPECT_EQ(r.start_cost, Shifted(u0).cost);
      EXPECT_LE(r.best_cost, r.start_cost);
      const auto rows = LogRows(o.log_path);
      ASSERT_EQ(rows.size(), 50u);
      EXPECT_EQ(rows[0][1], "start");
      for (std::size_t i = 0; i < u0.size(); ++i)
        EXPECT_EQ(rows[0][5 + i], params::FormatDouble(u0[i]));
      int design = 0;
      for (const auto& row : rows) design += row[1] == "lhs";
      EXPECT_EQ(design, alg == "lhs" ? 49 : 30);  // the global share: round(0.6 · 50)
      // The design in calls of `batch`; then the searches ask together (rounds of `batch`).
      ASSERT_GE(tb.sizes.size(), 10u);
      for (std::size_t k = 0; k < 10; ++k) EXPECT_EQ(tb.sizes[k], static_cast<std::size_t>(batch));
      if (alg != "lhs") {
        EXPECT_EQ(*std::max_element(tb.sizes.begin() + 10, tb.sizes.end()),
                  static_cast<std::size_t>(batch));
      }
    }
  }
  TunerOptions one;
  one.algorithm = "lhs+sbplx";
  one.batch = 4;
  one.max_evals = 1;
  const auto r = Tune(u0, Shifted, one);
  EXPECT_EQ(r.evals, 1);
  EXPECT_EQ(r.best_eval, 0);
  EXPECT_EQ(r.best_u, u0);
  EXPECT_EQ(r.stop_reason, "max_evals");
}

TEST(TunerBatchTest, StopAndResumeGiveTheUninterruptedLog) {
  const std::vector<double> u0(6, 0.5);
  TunerOptions o;
  o.algorithm = "lhs+sbplx";
  o.batch = 3;
  o.max_evals = 90;
  o.seed = 4;
  o.log_extra_header = {"echo"};
  o.log_path = TempPath("scw_tuner_batch_full.csv");
  const auto full = Tune(u0, Shifted, o);
  const std::string full_log = params::ReadTextFile(o.log_path);
  ASSERT_EQ(full.evals, 90);

  // Ctrl-C during the 5th call (the design) and during the 25th (the lockstep searches): the
  // batch in progress is finished and logged whole, the next one is not started.
  for (int stop_at : {5, 25}) {
    SCOPED_TRACE(stop_at);
    std::atomic<bool> stop{false};
    ThreadedBatch tb{Shifted, 2};
    tb.on_call = [&stop, stop_at](int call) {
      if (call == stop_at) stop = true;
    };
    o.stop = &stop;
    o.resume_path.clear();
    o.log_path = TempPath("scw_tuner_batch_part.csv");
    const auto part = Tune(u0, Shifted, tb.Get(), o);
    EXPECT_EQ(part.stop_reason, "interrupted");
    EXPECT_EQ(tb.calls, stop_at);
    if (stop_at == 5) {
      EXPECT_EQ(part.evals, 1 + 5 * 3);
    }
    const std::string part_log = params::ReadTextFile(o.log_path);
    EXPECT_EQ(full_log.compare(0, part_log.size(), part_log), 0) << "not a prefix";

    stop = false;
    ThreadedBatch fresh{Shifted, 1};
    o.resume_path = o.log_path;
    const auto resumed = Tune(u0, Shifted, fresh.Get(), o);
    EXPECT_EQ(resumed.replayed, part.evals);
    EXPECT_EQ(resumed.best_u, full.best_u);
    EXPECT_EQ(resumed.best_cost, full.best_cost);
    EXPECT_EQ(params::ReadTextFile(o.log_path), full_log);
  }
  o.stop = nullptr;

  // A log cut inside a batch (a killed run) replays just as exactly.
  for (int rows : {8, 41, 67}) {
    SCOPED_TRACE(rows);
    std::size_t at = 0;
    for (int line = 0; line <= rows; ++line) at = full_log.find('\n', at) + 1;
    io::WriteFileAtomic(TempPath("scw_tuner_batch_cut.csv"), full_log.substr(0, at));
    o.resume_path = TempPath("scw_tuner_batch_cut.csv");
    o.log_path = TempPath("scw_tuner_batch_cut.csv");
    ThreadedBatch fresh{Shifted, 2};
    const auto resumed = Tune(u0, Shifted, fresh.Get(), o);
    EXPECT_EQ(resumed.replayed, rows);
    EXPECT_EQ(params::ReadTextFile(o.log_path), full_log);
  }

  // Another batch size asks for other points: the resume log is refused.
  o.batch = 2;
  o.resume_path = TempPath("scw_tuner_batch_full.csv");
  o.log_path = TempPath("scw_tuner_batch_other.csv");
  EXPECT_THROW(Tune(u0, Shifted, o), std::runtime_error);
}

TEST(TunerBatchTest, TimeLimitStopsBetweenWholeBatches) {
  TunerOptions o;
  o.algorithm = "lhs+sbplx";
  o.batch = 4;
  o.max_evals = 1000;
  o.max_time_s = 0.15;
  o.log_path = TempPath("scw_tuner_batch_time.csv");
  ThreadedBatch tb{[](const std::vector<double>& u) {
                     std::this_thread::sleep_for(std::chrono::milliseconds(5));
                     return Shifted(u);
                   },
                   2};
  const auto r = Tune(std::vector<double>(4, 0.5), Shifted, tb.Get(), o);
  EXPECT_EQ(r.stop_reason, "max_time");
  EXPECT_LT(r.evals, 1000);
  EXPECT_EQ((r.evals - 1) % 4, 0) << r.evals;  // the start point, then whole design batches
  EXPECT_EQ(static_cast<int>(LogRows(o.log_path).size()), r.evals);
}

TEST(TunerBatchTest, AThrowingBatchFailsItsPointsAndTheRunGoesOn) {
  TunerOptions o;
  o.algorithm = "lhs+sbplx";
  o.batch = 3;
  o.max_evals = 40;
  o.log_path = TempPath("scw_tuner_batch_throw.csv");
  int calls = 0;
  BatchObjective nasty = [&calls](const std::vector<std::vector<double>>& points) {
    if (++calls == 2) throw std::runtime_error("cluster down, node 3");
    std::vector<Evaluation> out;
    for (const auto& u : points) out.push_back(Shifted(u));
    if (calls == 4) out.back().cost = std::nan("");
    return out;
  };
  const auto r = Tune(std::vector<double>(4, 0.5), Shifted, nasty, o);
  EXPECT_EQ(r.evals, 40);
  const auto rows = LogRows(o.log_path);
  for (int i = 4; i <= 6; ++i) {
    EXPECT_EQ(rows[static_cast<std::size_t>(i)][3], "exception: cluster down; node 3");
    EXPECT_EQ(rows[static_cast<std::size_t>(i)][2], params::FormatDouble(o.failure_cost));
  }
  EXPECT_EQ(rows[12][3], "non-finite cost");
  EXPECT_TRUE(std::isfinite(r.best_cost));
}

TEST(TunerBatchTest, BatchedSearchFindsTheOptimum) {
  // The shifted quadratic in 12 and 30 dimensions from far off (0.9 everywhere). K searches share
  // the budget, so they need about K times the evaluations of one search on a single bowl.
  struct Case {
    std::size_t dims;
    int batch, max_evals;
    double cost_tol, u_tol;
  };
  for (const Case& c : {Case{12, 2, 3000, 1e-6, 0.005}, Case{12, 4, 3000, 1e-6, 0.005},
                        Case{30, 4, 6000, 1e-5, 0.01}}) {
    SCOPED_TRACE(std::to_string(c.dims) + " dims, batch " + std::to_string(c.batch));
    TunerOptions o;
    o.algorithm = "lhs+sbplx";
    o.batch = c.batch;
    o.global_share = 0.1;
    o.max_evals = c.max_evals;
    o.xtol_abs = 1e-7;
    ThreadedBatch tb{Shifted, 1};
    tb.jitter = false;
    const auto r = Tune(std::vector<double>(c.dims, 0.9), Shifted, tb.Get(), o);
    EXPECT_LE(r.evals, c.max_evals);
    EXPECT_LT(r.best_cost, c.cost_tol);
    for (std::size_t i = 0; i < c.dims; ++i)
      EXPECT_NEAR(r.best_u[i], ShiftedTarget(i), c.u_tol) << i;
  }
}

}  // namespace
}  // namespace scw::tuning
