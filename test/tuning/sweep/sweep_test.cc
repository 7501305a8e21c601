// scw sweep library, running and writing (sweep_run.h, sweep_write.h): series stopping at the
// first abort, shared resolutions, determinism over thread counts and worker processes, CSV and
// trace output. Parsing and expansion: sweep_spec_test.cc, sweep_plan_test.cc.
#include "tuning/sweep/sweep.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "params/schema/field.h"
#include "test/common/error_of.h"

namespace scw::tuning::sweep {
namespace {

namespace fs = std::filesystem;

using Values = std::vector<std::string>;

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

  // The console table: one line per reported run, the text columns padded to a common width.
  const std::string table = SweepTable(r);
  std::vector<std::string> lines;
  std::istringstream table_in(table);
  while (std::getline(table_in, line)) lines.push_back(line);
  ASSERT_EQ(lines.size(), 4u) << table;
  EXPECT_EQ(lines[0].rfind("all     abort.max_lateral_error=100   completed      mean lap ", 0), 0u)
      << table;
  EXPECT_EQ(lines[1].rfind("all     abort.max_lateral_error=0.01  lateral_error  mean lap ", 0), 0u)
      << table;
  EXPECT_EQ(lines[2].rfind("no_esc  abort.max_lateral_error=100   completed      mean lap ", 0), 0u)
      << table;
  for (const auto& l : lines) {
    EXPECT_EQ(l.size(), lines[0].size()) << table;
    EXPECT_EQ(l.substr(l.size() - 2), " %") << table;
  }
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
}  // namespace scw::tuning::sweep
