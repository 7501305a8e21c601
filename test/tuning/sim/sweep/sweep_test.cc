// scw sweep library: argument parsing, grid expansion, series stopping at the first abort,
// shared resolutions, determinism over thread counts, CSV and trace output.
#include "tuning/sim/sweep/sweep.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <set>

#include "params/schema/field.h"

namespace scw::tuning {
namespace {

namespace fs = std::filesystem;

using Values = std::vector<std::string>;

std::string ErrorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(SweepParseTest, VaryList) {
  const SweepAxis a = ParseVary("gg_scale=1.0, 1.1,1.25");
  EXPECT_EQ(a.key, "gg_scale");
  EXPECT_EQ(a.values, (Values{"1.0", "1.1", "1.25"}));
  // Commas inside brackets belong to a list value.
  const SweepAxis b = ParseVary("grip.wheel_mu_x=[0.8, 1, 0.8, 1],[1,1,1,1]");
  EXPECT_EQ(b.values, (Values{"[0.8, 1, 0.8, 1]", "[1,1,1,1]"}));
  EXPECT_EQ(ParseVary("subsystems.esc=true,false").values, (Values{"true", "false"}));
  EXPECT_EQ(ParseVary("gg_scale=1.3").values, (Values{"1.3"}));
}

TEST(SweepParseTest, VaryRangeIsInclusiveWithTheArgumentsDecimals) {
  EXPECT_EQ(ParseVary("gg_scale=1.0:0.05:1.2").values, (Values{"1", "1.05", "1.1", "1.15", "1.2"}));
  // The stop is reached despite rounding (0.1 is not exact in binary).
  EXPECT_EQ(ParseVary("gg_scale=1.0:0.1:1.6").values.size(), 7u);
  EXPECT_EQ(ParseVary("gg_scale=1.0:0.1:1.6").values.back(), "1.6");
  // A stop between steps is not exceeded; descending ranges work.
  EXPECT_EQ(ParseVary("laps=1:2:6").values, (Values{"1", "3", "5"}));
  EXPECT_EQ(ParseVary("gg_scale=1.5:-0.25:1").values, (Values{"1.5", "1.25", "1"}));
  EXPECT_EQ(ParseVary("gg_scale=1.2:0.1:1.2").values, (Values{"1.2"}));
}

TEST(SweepParseTest, BadVaryNamesTheArgumentAndTheRule) {
  const std::pair<const char*, const char*> bad[] = {
      {"gg_scale", "key=v1,v2"},
      {"=1,2", "key=v1,v2"},
      {"gg_scale=", "key=v1,v2"},
      {"gg_scale=1:0:2", "must not be 0"},
      {"gg_scale=2:0.1:1", "sign"},
      {"gg_scale=1:x:2", "three finite numbers"},
      {"gg_scale=1,,2", "value 2 is empty"},
      {"gg_scale=0:1e-9:1", "more than"},
      {"config=a,b", "--config"},
  };
  for (const auto& [arg, rule] : bad) {
    const std::string msg = ErrorOf([&] { ParseVary(arg); });
    EXPECT_NE(msg.find(std::string("--vary ") + arg), std::string::npos) << arg << ": " << msg;
    EXPECT_NE(msg.find(rule), std::string::npos) << arg << ": " << msg;
  }
}

TEST(SweepParseTest, Config) {
  const SweepConfig c = ParseConfig("none:subsystems.esc=false, subsystems.cs=false");
  EXPECT_EQ(c.name, "none");
  EXPECT_EQ(c.overrides, (Values{"subsystems.esc=false", "subsystems.cs=false"}));
  EXPECT_TRUE(ParseConfig("esc+cs").overrides.empty());
  EXPECT_TRUE(ParseConfig("esc+cs:").overrides.empty());
  for (const char* arg : {":subsystems.esc=false", "no good:x=1", "a:subsystems.esc", "a:=1"}) {
    const std::string msg = ErrorOf([&] { ParseConfig(arg); });
    EXPECT_NE(msg.find(std::string("--config ") + arg), std::string::npos) << arg << ": " << msg;
  }
}

TEST(SweepGridTest, ConfigsTimesCartesianProductWithTheFirstAxisInnermost) {
  const std::vector<SweepAxis> axes = {{"gg_scale", {"1.0", "1.1", "1.2"}},
                                       {"grip.rear_mu_y", {"0.8", "1.0"}},
                                       {"laps", {"1", "2"}}};
  const auto g = ExpandGrid(axes, 2);
  ASSERT_EQ(g.size(), 2u * 3u * 2u * 2u);
  // Every combination exactly once.
  std::set<std::vector<int>> seen;
  for (const auto& p : g) {
    std::vector<int> key = p.value;
    key.push_back(p.config);
    EXPECT_TRUE(seen.insert(key).second);
  }
  // Series: contiguous blocks of the first axis in the given order, same other values.
  ASSERT_EQ(g.back().series, 2 * 2 * 2 - 1);
  for (std::size_t i = 0; i < g.size(); ++i) {
    EXPECT_EQ(g[i].value[0], static_cast<int>(i % 3));
    EXPECT_EQ(g[i].series, static_cast<int>(i / 3));
    EXPECT_EQ(g[i].config, static_cast<int>(i / 12));
  }
  // Last axis faster than the second.
  EXPECT_EQ(g[3].value[2], 1);
  EXPECT_EQ(g[3].value[1], 0);
  EXPECT_EQ(g[6].value[1], 1);
  // No axes: one run per configuration, each its own series.
  const auto none = ExpandGrid({}, 3);
  ASSERT_EQ(none.size(), 3u);
  EXPECT_EQ(none[2].series, 2);
  EXPECT_EQ(none[2].config, 2);
}

TEST(SweepGridTest, SeriesStopsAtItsFirstAbort) {
  struct Row {
    std::vector<int> series;
    std::vector<bool> aborted;
    std::vector<bool> stop, keep_all;
  };
  const Row rows[] = {
      // No abort: everything.
      {{0, 0, 0}, {false, false, false}, {true, true, true}, {true, true, true}},
      // Abort in the middle: up to and including it, even if a later run completes.
      {{0, 0, 0, 0},
       {false, true, false, true},
       {true, true, false, false},
       {true, true, true, true}},
      // First run aborts.
      {{0, 0}, {true, false}, {true, false}, {true, true}},
      // Series are independent.
      {{0, 0, 1, 1, 2},
       {true, false, false, true, true},
       {true, false, true, true, true},
       {true, true, true, true, true}},
  };
  for (const auto& r : rows) {
    EXPECT_EQ(ReportedRuns(r.series, r.aborted, true), r.stop);
    EXPECT_EQ(ReportedRuns(r.series, r.aborted, false), r.keep_all);
  }
}

TEST(SweepValidateTest, BadKeysAndValuesNameTheArgument) {
  SweepDefinition d;
  d.axes = {ParseVary("gg_sclae=1,2"), ParseVary("gg_scale=1.0,abc"), ParseVary("laps=1,1")};
  d.configs = {ParseConfig("esc:subsystems.ecs=false"), ParseConfig("x"), ParseConfig("x")};
  const std::string msg = ErrorOf([&] { ValidateSweep(d); });
  EXPECT_NE(msg.find("--vary gg_sclae=1,2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("did you mean gg_scale"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--vary gg_scale=1.0,abc"), std::string::npos) << msg;
  EXPECT_NE(msg.find("abc"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--vary laps=1,1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--config esc:subsystems.ecs=false"), std::string::npos) << msg;
  EXPECT_NE(msg.find("used twice"), std::string::npos) << msg;
}

// A small, fast sweep: centre line (no racing-line optimisation), one lap. The lateral-error
// threshold is a run-time key: 0.01 m aborts at once, so the series stops there.
SweepDefinition Small() {
  SweepDefinition d;
  d.base_overrides = {"laps=1", "motion.raceline=centerline"};
  d.axes = {ParseVary("abort.max_lateral_error=100,0.01,50")};
  d.configs = {ParseConfig("all"), ParseConfig("no_esc:subsystems.esc=false")};
  d.stop_at_first_abort = true;
  return d;
}

TEST(SweepRunTest, StopsEachSeriesAtTheFirstAbortAndSharesTheResolution) {
  const SweepResult r = RunSweep(Small(), 2);
  ASSERT_EQ(r.runs.size(), 6u);
  EXPECT_EQ(r.resolves, 1) << "subsystem and abort keys must not trigger a new resolution";
  for (int c = 0; c < 2; ++c) {
    const auto& first = r.runs[static_cast<std::size_t>(3 * c)];
    const auto& second = r.runs[static_cast<std::size_t>(3 * c + 1)];
    const auto& third = r.runs[static_cast<std::size_t>(3 * c + 2)];
    EXPECT_EQ(first.metrics.status, RunStatus::kCompleted) << RunStatusName(first.metrics.status);
    EXPECT_EQ(second.metrics.status, RunStatus::kLateralError);
    EXPECT_TRUE(first.reported);
    EXPECT_TRUE(second.reported);
    EXPECT_FALSE(third.reported);  // would complete, but comes after the first abort
    EXPECT_EQ(third.spec.abort.max_lateral_error, 50.0);
    EXPECT_EQ(third.spec.subsystems.esc, c == 0);
  }
}

TEST(SweepRunTest, BitIdenticalForOneAndTwoThreads) {
  SweepDefinition d = Small();
  d.axes.insert(d.axes.begin(), ParseVary("gg_scale=1.0,1.2"));
  d.axes.pop_back();
  const SweepResult a = RunSweep(d, 1);
  const SweepResult b = RunSweep(d, 2);
  EXPECT_EQ(a.resolves, 2);
  ASSERT_EQ(a.runs.size(), b.runs.size());
  for (std::size_t i = 0; i < a.runs.size(); ++i) {
    const RunMetrics& x = a.runs[i].metrics;
    const RunMetrics& y = b.runs[i].metrics;
    EXPECT_EQ(x.status, y.status);
    EXPECT_EQ(x.lap_times, y.lap_times);
    EXPECT_EQ(x.time, y.time);
    EXPECT_EQ(x.max_abs_sideslip, y.max_abs_sideslip);
    EXPECT_EQ(x.max_slip_front, y.max_slip_front);
    EXPECT_EQ(x.max_slip_rear, y.max_slip_rear);
    EXPECT_EQ(x.max_abs_lateral_error, y.max_abs_lateral_error);
    EXPECT_EQ(x.esc_brake_energy, y.esc_brake_energy);
    EXPECT_EQ(a.runs[i].reported, b.runs[i].reported);
  }
  // Stopping at the first abort: the reported runs do not depend on the thread count either.
  SweepDefinition s = Small();
  s.axes = {ParseVary("abort.max_lateral_error=100,50,0.01,40,30")};
  const SweepResult c = RunSweep(s, 1);
  const SweepResult e = RunSweep(s, 2);
  ASSERT_EQ(c.runs.size(), e.runs.size());
  for (std::size_t i = 0; i < c.runs.size(); ++i) {
    EXPECT_EQ(c.runs[i].reported, e.runs[i].reported) << i;
    EXPECT_EQ(c.runs[i].reported, i % 5 < 3) << i;
    if (c.runs[i].reported) {
      EXPECT_EQ(c.runs[i].metrics.status, e.runs[i].metrics.status);
      EXPECT_EQ(c.runs[i].metrics.lap_times, e.runs[i].metrics.lap_times);
    }
  }
}

TEST(SweepRunTest, CsvHasOneRowPerReportedRunAndTracesTheSelectedRuns) {
  const fs::path dir = fs::temp_directory_path() / ("scw_sweep_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  SweepTraceOptions to;
  to.dir = (dir / "traces").string();
  to.at = {"config=no_esc", "abort.max_lateral_error=1e2", "abort.max_lateral_error=50"};
  const SweepResult r = RunSweep(Small(), 2, to);
  WriteSweepCsv((dir / "sweep.csv").string(), r);

  std::ifstream in(dir / "sweep.csv");
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(
      header.rfind("config,abort.max_lateral_error,status,progress,laps_completed,lap_1_s,", 0), 0u)
      << header;
  EXPECT_NE(header.find("max_slip_rear_pct"), std::string::npos);
  std::vector<std::string> rows;
  while (std::getline(in, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[1].rfind("all,0.01,lateral_error,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("no_esc,100,completed,1,1,", 0), 0u) << rows[2];

  // Only the reported no_esc run at 100 m (1e2 matches by value; 50 was not reported).
  std::vector<std::string> files;
  for (const auto& f : fs::directory_iterator(to.dir)) files.push_back(f.path().filename());
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(files[0], "no_esc__abort.max_lateral_error-100.csv");
  EXPECT_EQ(TraceFileName(r, r.runs[4]), "no_esc__abort.max_lateral_error-0.01.csv");

  EXPECT_NE(ErrorOf([&] {
              MatchesTraceConditions(r, r.runs[0], {"gg_scale=1"});
            }).find("neither config nor a varied key"),
            std::string::npos);
  fs::remove_all(dir);
}

// ---------------------------------------------------------------------------------------------
// Worker processes (--processes): the same table as in-process threads, clear errors.

SweepExecution Processes(int n, std::vector<std::string> command = {SCW_BINARY, "sweep"}) {
  SweepExecution e;
  e.processes = n;
  e.threads = 1;
  e.worker_command = std::move(command);
  return e;
}

std::string CsvOf(const SweepResult& r, const std::string& name) {
  const fs::path path = fs::temp_directory_path() /
                        ("scw_sweep_proc_" + std::to_string(::getpid()) + "_" + name + ".csv");
  WriteSweepCsv(path.string(), r);
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  fs::remove(path);
  return text;
}

TEST(SweepProcessTest, WorkerProcessesGiveTheSameTableAsOneThread) {
  // Two configurations × two CS settings (one resolution, which every worker repeats), each
  // series stopping at its first abort (0.01 m).
  SweepDefinition d = Small();
  d.axes = {ParseVary("abort.max_lateral_error=100,0.01,50"),
            ParseVary("subsystems.cs=true,false")};
  const SweepResult serial = RunSweep(d, 1);
  const std::string expected = CsvOf(serial, "serial");
  for (const int n : {2, 3}) {
    const SweepResult r = RunSweep(d, Processes(n));
    EXPECT_EQ(CsvOf(r, "p" + std::to_string(n)), expected) << n << " processes";
    ASSERT_EQ(r.runs.size(), serial.runs.size());
    for (std::size_t i = 0; i < r.runs.size(); ++i) {
      EXPECT_EQ(r.runs[i].reported, serial.runs[i].reported) << i;
      if (!r.runs[i].reported) continue;
      // Every field, bit for bit (the CSV rounds nothing, but not every field is in it).
      const RunMetrics &x = serial.runs[i].metrics, &y = r.runs[i].metrics;
      EXPECT_EQ(x.lap_times, y.lap_times);
      EXPECT_EQ(x.distance_planned, y.distance_planned);
      EXPECT_EQ(x.sideslip_excess_integral, y.sideslip_excess_integral);
      EXPECT_EQ(x.laps_planned, y.laps_planned);
      EXPECT_EQ(serial.runs[i].ideal_lap_time, r.runs[i].ideal_lap_time);
    }
  }
}

TEST(SweepProcessTest, PmpcSweepInWorkerProcessesEqualsOneThread) {
  // The case the worker processes exist for: Ipopt-based runs (one lap each, with and without
  // ESC + CS), in two processes and in one thread.
  SweepDefinition d;
  d.base_overrides = {"laps=1", "motion.raceline=centerline", "motion.controller=pmpc"};
  d.axes = {ParseVary("gg_scale=1.0")};
  d.configs = {ParseConfig("off:subsystems.esc=false,subsystems.cs=false"), ParseConfig("sc")};
  d.stop_at_first_abort = true;
  const SweepResult serial = RunSweep(d, 1);
  EXPECT_EQ(CsvOf(RunSweep(d, Processes(2)), "pmpc_p2"), CsvOf(serial, "pmpc_serial"));
  EXPECT_GT(serial.runs[0].metrics.distance, 100.0);
}

TEST(SweepProcessTest, WorkerArgumentsRebuildTheDefinition) {
  SweepDefinition d = Small();
  d.axes.push_back(ParseVary("grip.wheel_mu_x=[0.8, 1, 0.8, 1],[1,1,1,1]"));
  d.stability_file = "params/stability/default.yaml";
  const std::vector<std::string> a = SweepWorkerArguments(d);
  const std::vector<std::string> expected = {"--set=laps=1",
                                             "--set=motion.raceline=centerline",
                                             "--stability=params/stability/default.yaml",
                                             "--vary=abort.max_lateral_error=100,0.01,50",
                                             "--vary=grip.wheel_mu_x=[0.8, 1, 0.8, 1],[1,1,1,1]",
                                             "--config=all",
                                             "--config=no_esc:subsystems.esc=false"};
  EXPECT_EQ(a, expected);
  // Parsed back, the axes are the same values.
  EXPECT_EQ(ParseVary(a[4].substr(7)).values, d.axes[1].values);
}

TEST(SweepProcessTest, AFailedWorkerIsAnErrorNamingTheRun) {
  const SweepDefinition d = Small();
  const auto message = [&](std::vector<std::string> command) {
    try {
      (void)RunSweep(d, Processes(2, std::move(command)));
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // Killed while computing its first run (the shell ignores the sweep arguments).
  const std::string killed = message({"/bin/sh", "-c", "read job; kill -9 $$", "sh"});
  EXPECT_NE(killed.find("killed by signal 9"), std::string::npos) << killed;
  EXPECT_NE(killed.find("(config "), std::string::npos) << killed;  // whichever died first
  EXPECT_NE(killed.find(", abort.max_lateral_error="), std::string::npos) << killed;
  EXPECT_NE(killed.find("no table written"), std::string::npos) << killed;
  // Not startable.
  const std::string missing = message({"/nonexistent/scw", "sweep"});
  EXPECT_NE(missing.find("could not be started"), std::string::npos) << missing;
  // Protocol garbage.
  const std::string garbage =
      message({"/bin/sh", "-c", "read job; echo hello >&3; exec sleep 5", "sh"});
  EXPECT_NE(garbage.find("unreadable line"), std::string::npos) << garbage;
}

}  // namespace
}  // namespace scw::tuning
