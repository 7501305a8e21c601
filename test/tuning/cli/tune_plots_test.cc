// The figures of a scw tune run folder (tuning/cli/tune_plots.h) on a small run folder
// written with the real writers: the tuner's evaluation log and ComparisonCsv. Tests that need
// python3 with matplotlib skip when it is absent.
#include "tuning/cli/tune_plots.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "params/io/atomic_file.h"
#include "params/io/write.h"
#include "tuning/optim/comparison.h"
#include "tuning/optim/evaluator.h"
#include "tuning/optim/tuner.h"

namespace scw::tuning {
namespace {

namespace fs = std::filesystem;
using cli::kComparisonPlotFile;
using cli::kConvergencePlotFile;
using cli::TunePlotOptions;
using cli::TunePlotScript;
using cli::TunePlotsMarkdown;
using cli::WriteTunePlots;

std::string Read(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

RunMetrics Metrics(RunStatus status, double lap, double progress, int esc, int abs) {
  RunMetrics m;
  m.status = status;
  m.laps_planned = 2;
  m.distance_planned = 10000.0;
  m.distance = progress * m.distance_planned;
  if (status == RunStatus::kCompleted) m.lap_times = {lap, lap + 0.2};
  m.max_abs_sideslip = 0.05 + 0.01 * esc;
  m.esc_count = esc;
  m.cs_count = esc / 2;
  m.abs_count = abs;
  m.tc_count = 1;
  return m;
}

SetEvaluation Set(const std::vector<RunMetrics>& runs) {
  SetEvaluation s;
  s.runs = runs;
  for (const auto& m : runs) {
    CostBreakdown c;
    c.total = m.aborted() ? 200.0 + 200.0 * (1.0 - m.Progress()) : m.MeanLapTime();
    s.costs.push_back(c);
    s.total += c.total;
  }
  return s;
}

BatchEvaluator Named(const std::vector<std::string>& names) {
  std::vector<ResolvedScenario> sc(names.size());
  for (std::size_t i = 0; i < names.size(); ++i) sc[i].spec.name = names[i];
  return BatchEvaluator(sc, {}, params::CostWeights{}, 1);
}

class TunePlotsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("scw_tune_plots_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }

  // evaluations.csv from the tuner itself (phases start, crs2, sbplx), with the per-scenario
  // columns scw tune adds; a corner of the cube "aborts" and one point is "infeasible".
  void WriteEvaluations() const {
    TunerOptions o;
    o.max_evals = 80;
    o.seed = 3;
    o.log_path = (dir_ / "evaluations.csv").string();
    o.dimension_names = {"u:a", "u:b", "u:c"};
    o.log_extra_header = {"cost:nominal", "status:nominal"};
    const auto f = [](const std::vector<double>& u) {
      Evaluation e;
      const double d0 = u[0] - 0.3, d1 = u[1] - 0.6, d2 = u[2] - 0.45;
      e.cost = 120.0 + 30.0 * (d0 * d0 + 2.0 * d1 * d1 + d2 * d2);
      if (u[0] > 0.85) {
        e.cost += 250.0;
        e.status = "1 abort(s)";
      } else if (u[1] < 0.05) {
        e.cost = 1e6;
        e.status = "infeasible: ESC.kp_beta";
      }
      e.columns = {params::FormatDouble(e.cost), e.status == "ok" ? "completed" : "sideslip"};
      return e;
    };
    Tune({0.5, 0.5, 0.5}, f, o);
  }

  void WriteComparison() const {
    const std::vector<std::string> labels = {"baseline", "tuned"};
    const auto training = Named({"nominal_gg1.2", "low_mu_braking"});
    const std::vector<SetEvaluation> train = {
        Set({Metrics(RunStatus::kCompleted, 71.2, 1, 12, 3),
             Metrics(RunStatus::kCompleted, 80.4, 1, 4, 30)}),
        Set({Metrics(RunStatus::kCompleted, 71.0, 1, 9, 3),
             Metrics(RunStatus::kCompleted, 80.1, 1, 5, 26)})};
    const auto held = Named({"nominal_gg1.1", "mu_split_left", "rear_grip-15_gg1.25"});
    const std::vector<SetEvaluation> held_res = {
        Set({Metrics(RunStatus::kCompleted, 72.5, 1, 6, 2),
             Metrics(RunStatus::kSideslip, 0, 0.41, 14, 8),
             Metrics(RunStatus::kCompleted, 73.0, 1, 20, 1)}),
        Set({Metrics(RunStatus::kCompleted, 72.4, 1, 5, 2),
             Metrics(RunStatus::kSideslip, 0, 0.47, 12, 8),
             Metrics(RunStatus::kWheelLock, 0, 0.9, 22, 40)})};
    const std::string csv = ComparisonCsv("training", training, labels, train, true) +
                            ComparisonCsv("held_out", held, labels, held_res, false);
    io::WriteFileAtomic((dir_ / "comparison.csv").string(), csv);
  }

  fs::path dir_;
};

bool NoPlotter(const std::string& message) {
  return message.find("matplotlib is not installed") != std::string::npos ||
         message.find("no Python interpreter") != std::string::npos;
}

TEST_F(TunePlotsTest, WritesBothFiguresFromARealRunFolder) {
  WriteEvaluations();
  WriteComparison();
  std::string message = "unchanged";
  const bool ok = WriteTunePlots(dir_, &message);
  if (!ok && NoPlotter(message)) GTEST_SKIP() << "no python3 with matplotlib: " << message;
  ASSERT_TRUE(ok) << message;
  EXPECT_TRUE(message.empty());
  for (const char* name : {kConvergencePlotFile, kComparisonPlotFile}) {
    SCOPED_TRACE(name);
    const std::string png = Read(dir_ / name);
    ASSERT_GT(png.size(), 1000u);
    EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  }
  // Written under a temporary name and renamed: nothing else is left in the folder.
  for (const auto& e : fs::directory_iterator(dir_)) {
    const std::string n = e.path().filename().string();
    EXPECT_TRUE(n == "evaluations.csv" || n == "comparison.csv" || n == kConvergencePlotFile ||
                n == kComparisonPlotFile)
        << n;
  }
}

TEST_F(TunePlotsTest, TheSameInputsGiveTheSameBytes) {
  WriteEvaluations();
  WriteComparison();
  std::string message;
  if (!WriteTunePlots(dir_, &message)) {
    if (NoPlotter(message)) GTEST_SKIP() << message;
    FAIL() << message;
  }
  const std::string a = Read(dir_ / kConvergencePlotFile), b = Read(dir_ / kComparisonPlotFile);
  ASSERT_TRUE(WriteTunePlots(dir_, &message)) << message;
  EXPECT_EQ(a, Read(dir_ / kConvergencePlotFile));
  EXPECT_EQ(b, Read(dir_ / kComparisonPlotFile));
}

// front.png from a front.csv whose looser points found the same set (one label for the spot) with
// the base set's columns (its marker in both panels), and from one written before those columns.
TEST_F(TunePlotsTest, AFrontIsDrawnWithTheBaseSetAndSharedSpots) {
  const std::string header =
      "point,label,lap_budget_s,activations_limited,changed_keys,training_lap_loss_s,"
      "training_stability,training_aborts,held_out_lap_loss_s,held_out_stability,"
      "held_out_aborts,knife_edges,own_knife_edges,base_training_stability,file,"
      "training_clean_activations";
  const std::string rows[] = {
      "0,no loss,0.0,true,9,0.0,1501.4,1,0.01,849.0,1,38,12,3037.2,point_0/x.yaml,2/41/8/2",
      "1,+0.025 s,0.025,false,26,-0.067,1161.1,0,-0.103,491.5,0,48,30,3037.2,point_1/x.yaml,"
      "2/37/19/23",
      "2,no budget,inf,false,26,-0.067,1161.1,0,-0.103,491.5,0,48,30,3037.2,point_2/x.yaml,"
      "2/37/19/23"};
  for (bool base_columns : {true, false}) {
    SCOPED_TRACE(base_columns);
    std::string csv = header + (base_columns ? ",base_held_out_stability,base_training_aborts,"
                                               "base_held_out_aborts\n"
                                             : "\n");
    for (const std::string& r : rows) csv += r + (base_columns ? ",1111.9,5,1\n" : "\n");
    std::ofstream(dir_ / "front.csv") << csv;
    fs::remove(dir_ / cli::kFrontPlotFile);
    std::string message;
    const bool ok = cli::WriteFrontPlot(dir_, &message);
    if (!ok && NoPlotter(message)) GTEST_SKIP() << message;
    ASSERT_TRUE(ok) << message;
    EXPECT_GT(fs::file_size(dir_ / cli::kFrontPlotFile), 1000u);
  }
}

TEST_F(TunePlotsTest, AMissingInputIsAOneLineReason) {
  WriteEvaluations();  // no comparison.csv
  std::string message;
  const bool ok = WriteTunePlots(dir_, &message);
  if (NoPlotter(message)) GTEST_SKIP() << message;
  EXPECT_FALSE(ok);
  EXPECT_NE(message.find("comparison.csv"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_EQ(message.find("Traceback"), std::string::npos) << message;
}

TEST_F(TunePlotsTest, AMissingInterpreterIsReportedNotThrown) {
  WriteEvaluations();
  WriteComparison();
  std::string message;
  TunePlotOptions o;
  o.python = (dir_ / "no-such-python3").string();
  EXPECT_FALSE(WriteTunePlots(dir_, &message, o));
  EXPECT_NE(message.find("no Python interpreter found"), std::string::npos) << message;
  EXPECT_NE(message.find("no-such-python3"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(dir_ / kConvergencePlotFile));
  // The same through the environment variable (the default when no interpreter is given).
  ::setenv("SCW_PYTHON", o.python.c_str(), 1);
  message.clear();
  const bool ok = WriteTunePlots(dir_, &message);
  ::unsetenv("SCW_PYTHON");
  EXPECT_FALSE(ok);
  EXPECT_NE(message.find("no-such-python3"), std::string::npos) << message;
  EXPECT_FALSE(WriteTunePlots(dir_ / "absent", nullptr, o));  // null message: fine
}

// An interpreter without matplotlib: a stand-in that behaves like the script does there.
TEST_F(TunePlotsTest, AMissingMatplotlibIsReported) {
  const fs::path fake = dir_ / "python-without-matplotlib";
  {
    std::ofstream f(fake);
    f << "#!/bin/sh\ncat >/dev/null\necho 'tune_plots: matplotlib is not installed' >&2\n"
         "exit 3\n";
  }
  fs::permissions(fake, fs::perms::owner_all);
  std::string message;
  TunePlotOptions o;
  o.python = fake.string();
  EXPECT_FALSE(WriteTunePlots(dir_, &message, o));
  EXPECT_EQ(message, "matplotlib is not installed for " + fake.string() +
                         " (Debian: apt-get install python3-matplotlib)");
}

TEST(TunePlotsScriptTest, TheEmbeddedScriptIsTheSourceFile) {
  const std::string source = Read(fs::path(SCW_SOURCE_DIR) / "tuning/cli/tune_plots.py");
  ASSERT_FALSE(source.empty());
  EXPECT_EQ(TunePlotScript(), source);
}

TEST(TunePlotsScriptTest, TheMarkdownEmbedsBothFiguresRelatively) {
  const std::string md = TunePlotsMarkdown();
  EXPECT_NE(md.find("](convergence.png)"), std::string::npos) << md;
  EXPECT_NE(md.find("](comparison.png)"), std::string::npos) << md;
}

}  // namespace
}  // namespace scw::tuning
