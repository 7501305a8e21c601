#include "tuning/optim/tuner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

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
  o.max_evals = 40;
  o.seed = 1;
  o.log_path = TempPath("scw_tuner_seed.csv");
  Tune({0.5, 0.5, 0.5, 0.5}, Bowl, o);
  o.seed = 2;
  o.resume_path = o.log_path;
  o.log_path = TempPath("scw_tuner_seed2.csv");
  EXPECT_THROW(Tune({0.5, 0.5, 0.5, 0.5}, Bowl, o), std::runtime_error);
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
  for (const std::string alg :
       {"crs2+sbplx", "direct_l", "isres", "esch", "sbplx", "neldermead", "bobyqa", "cobyla"}) {
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

}  // namespace
}  // namespace scw::tuning
