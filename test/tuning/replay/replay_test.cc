// `scw replay` (tuning/replay/replay.h, tuning/cli/cmd_replay.cc): one test per subsystem on a
// short hand-made log, exactness against the controller run directly, repeatability, the
// comparison of two parameter sets, and the command's exit codes.
#include "tuning/replay/replay.h"
#include "params/io/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "params/io/load.h"
#include "params/io/write.h"
#include "test/tuning/replay/log_stories.h"
#include "tuning/sim/closed_loop.h"

namespace scw::tuning::replay {
namespace {

using controller::StabilityController;
using controller::StabilityInput;
using controller::StabilityOutput;
using testing::CsvTable;
using testing::ReadCsv;
using testing::TempDir;

std::string Shipped() { return std::string(SCW_SOURCE_DIR) + "/params/stability/default.yaml"; }

params::StabilityParams LoadShipped() {
  return params::LoadRosFile<params::StabilityParams>(Shipped(), params::kStabilityNodeKey);
}

struct Replayed {
  ReplaySummary summary;
  CsvTable out;
};

Replayed ReplayStory(const std::vector<StabilityInput>& rows, const StabilityController& c,
                     const std::string& name) {
  const TempDir dir("scw_replay_" + name);
  testing::WriteLog(dir.File("log.csv"), rows);
  Replayed r;
  r.summary = ReplayLog(dir.File("log.csv"), c, dir.File("out.csv"));
  r.out = ReadCsv(dir.File("out.csv"));
  EXPECT_EQ(r.out.header.size(), kOutputColumns.size());
  for (std::size_t i = 0; i < std::min(r.out.header.size(), kOutputColumns.size()); ++i)
    EXPECT_EQ(r.out.header[i], kOutputColumns[i].name);
  EXPECT_EQ(r.out.rows.size(), rows.size());
  EXPECT_EQ(r.summary.rows, static_cast<std::int64_t>(rows.size()));
  return r;
}

TEST(Replay, OversteerEpisodeTriggersEscAndCountersteer) {
  const params::StabilityParams p = LoadShipped();
  const StabilityController c(p);
  const auto rows = testing::OversteerStory(p);
  const Replayed r = ReplayStory(rows, c, "oversteer");
  const SubsystemActivity& esc = r.summary[Subsystem::kEsc];
  const SubsystemActivity& cs = r.summary[Subsystem::kCountersteer];
  EXPECT_GE(esc.interventions, 1);
  EXPECT_GE(cs.interventions, 1);
  EXPECT_EQ(r.summary[Subsystem::kAbs].interventions, 0);
  EXPECT_EQ(r.summary[Subsystem::kTc].interventions, 0);
  EXPECT_EQ(r.summary.invalid_rows, 0);
  // Nothing before the rear steps out at 1.0 s.
  EXPECT_GT(esc.first_active_t, 1.0);
  EXPECT_GT(cs.first_active_t, 1.0);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (r.out.At(k, "esc_active") == 1.0) {
      EXPECT_LT(r.out.At(k, "yaw_moment_Nm"), 0.0)
          << "left-hand oversteer needs a clockwise moment";
      EXPECT_GT(r.out.At(k, "p_out_fr_bar"), rows[k].brake_request_bar[kFR])
          << "outer front braked";
    }
    if (r.out.At(k, "cs_active") == 1.0) {
      EXPECT_LT(r.out.At(k, "steer_out_rad"), rows[k].steering_request) << "steer into the slide";
    }
  }
}

TEST(Replay, BrakingLockupTriggersAbs) {
  const params::StabilityParams p = LoadShipped();
  const StabilityController c(p);
  const auto rows = testing::LockupStory(p);
  const Replayed r = ReplayStory(rows, c, "lockup");
  const SubsystemActivity& abs = r.summary[Subsystem::kAbs];
  EXPECT_GE(abs.interventions, 1);
  EXPECT_GE(abs.first_active_t, 0.5);
  EXPECT_EQ(r.summary[Subsystem::kEsc].interventions, 0);
  EXPECT_EQ(r.summary[Subsystem::kTc].interventions, 0);
  bool front_released = false;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    for (std::size_t w = 0; w < 4; ++w)
      EXPECT_LE(r.out.At(k, std::string("p_out_") + kWheelNames[w] + "_bar"),
                rows[k].brake_request_bar[w]);
    if (r.out.At(k, "abs_state_fl") != 0.0) {
      EXPECT_EQ(r.out.At(k, "slip_control_active"), 1.0);
      front_released =
          front_released || r.out.At(k, "p_out_fl_bar") < rows[k].brake_request_bar[kFL];
    }
  }
  EXPECT_TRUE(front_released);
}

TEST(Replay, RearSpinTriggersTcUnlessReleaseCompat) {
  const params::StabilityParams p = LoadShipped();
  const auto rows = testing::RearSpinStory(p);
  const Replayed on = ReplayStory(rows, StabilityController(p), "spin");
  EXPECT_GE(on.summary[Subsystem::kTc].interventions, 1);
  EXPECT_GE(on.summary[Subsystem::kTc].first_active_t, 0.5);
  EXPECT_EQ(on.summary[Subsystem::kAbs].interventions, 0);
  bool rear_braked = false;
  for (std::size_t k = 0; k < rows.size(); ++k)
    if (on.out.At(k, "tc_state_rl") != 0.0) rear_braked |= on.out.At(k, "p_out_rl_bar") > 0.0;
  EXPECT_TRUE(rear_braked);

  const Replayed compat =
      ReplayStory(rows, StabilityController(p, {.release_compat = true}), "spin_compat");
  EXPECT_EQ(compat.summary[Subsystem::kTc].interventions, 0);
  EXPECT_EQ(compat.summary[Subsystem::kTc].active_rows, 0);
  // The throttle cut (slip > 25 %) works in both modes.
  const std::size_t last = rows.size() - 1;
  EXPECT_EQ(on.out.At(last, "throttle_out"), 0.0);
  EXPECT_EQ(compat.out.At(last, "throttle_out"), 0.0);
}

TEST(Replay, ReproducesTheControllerBitForBit) {
  // The closed loop's path: inputs written with ControllerLogWriter while the controller runs.
  const params::StabilityParams p = LoadShipped();
  const StabilityController c(p);
  const TempDir dir("scw_replay_exact");
  std::vector<double> t;
  std::vector<StabilityOutput> expected;
  {
    ControllerLogWriter log(dir.File("log.csv"));
    StabilityController::State s;
    for (long k = 0; k < 4000; ++k) {
      const StabilityInput in = testing::SyntheticRow(p, k);
      log.Write(in);
      expected.push_back(c.Step(in, &s));
      t.push_back(in.t);
    }
    log.Commit();
  }
  const ReplaySummary sum = ReplayLog(dir.File("log.csv"), c, dir.File("out.csv"));
  const CsvTable out = ReadCsv(dir.File("out.csv"));
  ASSERT_EQ(out.rows.size(), expected.size());
  std::size_t mismatches = 0;
  for (std::size_t k = 0; k < expected.size(); ++k) {
    ASSERT_EQ(out.rows[k].size(), kOutputColumns.size());
    EXPECT_TRUE(testing::SameBits(out.rows[k][0], t[k]));
    for (std::size_t i = 1; i < kOutputColumns.size(); ++i)
      if (!testing::SameBits(out.rows[k][i], OutputValue(expected[k], i)) && mismatches++ < 10)
        ADD_FAILURE() << "row " << k << ", column " << kOutputColumns[i].name << ": "
                      << out.rows[k][i] << " vs " << OutputValue(expected[k], i);
  }
  EXPECT_EQ(mismatches, 0u);
  // The synthetic lap exercises every subsystem and the pass-through.
  for (std::size_t k = 0; k < kNumSubsystems; ++k)
    EXPECT_GT(sum.activity[k].interventions, 0) << kSubsystemNames[k];
  EXPECT_GT(sum.invalid_rows, 0);
  EXPECT_EQ(sum.valid_rows + sum.invalid_rows, sum.rows);
}

TEST(Replay, ReplayingTwiceGivesIdenticalFiles) {
  const params::StabilityParams p = LoadShipped();
  const StabilityController c(p);
  const TempDir dir("scw_replay_twice");
  std::vector<StabilityInput> rows;
  for (long k = 0; k < 2500; ++k) rows.push_back(testing::SyntheticRow(p, k));
  testing::WriteLog(dir.File("log.csv"), rows);
  ReplayLog(dir.File("log.csv"), c, dir.File("a.csv"));
  ReplayLog(dir.File("log.csv"), c, dir.File("b.csv"));
  const std::string a = testing::ReadFile(dir.File("a.csv"));
  EXPECT_GT(a.size(), 100000u);
  EXPECT_EQ(a, testing::ReadFile(dir.File("b.csv")));
}

TEST(Replay, BadLogLeavesNoOutput) {
  const TempDir dir("scw_replay_badlog");
  const params::StabilityParams p;
  std::vector<StabilityInput> rows;
  for (long k = 0; k < 10; ++k) rows.push_back(testing::SyntheticRow(p, k));
  {
    ControllerLogWriter w(dir.File("ok.csv"));
    for (const auto& r : rows) w.Write(r);
    w.Commit();
  }
  std::string text = testing::ReadFile(dir.File("ok.csv"));
  const std::string last_row = text.substr(text.rfind('\n', text.size() - 2) + 1);
  text += "-1" + last_row.substr(last_row.find(','));  // one more row, with t = -1 s
  std::ofstream(dir.File("bad.csv")) << text;
  EXPECT_THROW(ReplayLog(dir.File("bad.csv"), StabilityController(p), dir.File("out.csv")),
               LogFormatError);
  EXPECT_FALSE(std::filesystem::exists(dir.File("out.csv")));
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 2u) << "no temporary output left behind";
}

/// Corner at 30 m/s with three mild slides (above the halved ESC thresholds, below the shipped
/// ones) and one full slide.
std::vector<StabilityInput> MildSlides(const params::StabilityParams& p) {
  return testing::CornerStory(p, 9.0, [](double t) {
    double s = 0.0;
    for (double t0 : {1.5, 3.0, 4.5})
      s += 0.3 * testing::Ramp(t, t0, t0 + 0.15) * (1.0 - testing::Ramp(t, t0 + 0.5, t0 + 0.8));
    s += testing::Ramp(t, 6.5, 6.65) * (1.0 - testing::Ramp(t, 7.0, 7.4));
    return s;
  });
}

params::StabilityParams HalvedEscThresholds(params::StabilityParams p) {
  auto& e = p.ESC;
  for (auto* v : {&e.beta_threshold_activate, &e.psi_dot_error_threshold_activate,
                  &e.beta_error_threshold_activate})
    for (double& x : *v) x *= 0.5;
  e.beta_threshold_deactivate *= 0.5;
  e.psi_dot_error_threshold_deactivate *= 0.5;
  e.beta_error_threshold_deactivate *= 0.5;
  return p;
}

TEST(Replay, CompareReportsMoreEscInterventionsWithHalvedThresholds) {
  const params::StabilityParams shipped = LoadShipped();
  const params::StabilityParams halved = HalvedEscThresholds(shipped);
  const TempDir dir("scw_replay_compare");
  testing::WriteLog(dir.File("log.csv"), MildSlides(shipped));
  const ComparisonSummary c =
      CompareOnLog(dir.File("log.csv"), StabilityController(shipped), StabilityController(halved));
  const auto esc = static_cast<std::size_t>(Subsystem::kEsc);
  EXPECT_GE(c.a.activity[esc].interventions, 1);
  EXPECT_GT(c.b.activity[esc].interventions, c.a.activity[esc].interventions);
  EXPECT_GT(c.b.activity[esc].active_time, c.a.activity[esc].active_time);
  EXPECT_TRUE(c.diverged);
  EXPECT_GT(c.first_divergence_t, 1.5);
  EXPECT_GT(c.first_divergence_line, 1);
  EXPECT_FALSE(c.first_divergence_column.empty());
  EXPECT_GT(c.pressure_bar[kFR].value, 0.0);
  EXPECT_GT(c.differing_rows, 0);
  const std::string report = FormatComparison(c, "shipped", "halved");
  EXPECT_NE(report.find("ESC"), std::string::npos) << report;
  EXPECT_NE(report.find("first diverge"), std::string::npos) << report;

  // The same set twice: nothing differs.
  const ComparisonSummary same =
      CompareOnLog(dir.File("log.csv"), StabilityController(shipped), StabilityController(shipped));
  EXPECT_FALSE(same.diverged);
  EXPECT_EQ(same.differing_rows, 0);
  EXPECT_EQ(same.steering.value, 0.0);
}

TEST(ReplayDocs, ColumnTablesOfTheDocsAreCurrent) {
  const std::string docs = testing::ReadFile(std::string(SCW_SOURCE_DIR) + "/docs/replay.md");
  ASSERT_FALSE(docs.empty());
  EXPECT_NE(docs.find(ColumnsMarkdown()), std::string::npos)
      << "docs/replay.md is out of date: replace its generated part with the output of "
         "`scw replay --columns`";
}

// ---------------------------------------------------------------------------------------------
// The command.

int RunScw(const std::string& args, const std::string& capture) {
  const std::string cmd = std::string(SCW_BIN) + " " + args + " > " + capture + " 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

TEST(ReplayCommand, SummaryCompareOutputAndExitCodes) {
  const params::StabilityParams shipped = LoadShipped();
  const TempDir dir("scw_replay_cli");
  const std::string log = dir.File("log.csv");
  const std::string txt = dir.File("stdout.txt");
  testing::WriteLog(log, MildSlides(shipped));
  io::WriteFileAtomic(dir.File("halved.yaml"),
                      params::ToRosYaml(HalvedEscThresholds(shipped), params::kStabilityNodeKey));

  EXPECT_EQ(RunScw("replay " + log + " --params " + Shipped(), txt), 0);
  std::string s = testing::ReadFile(txt);
  EXPECT_NE(s.find("rows:       900"), std::string::npos) << s;
  EXPECT_NE(s.find("countersteer"), std::string::npos) << s;

  EXPECT_EQ(RunScw("replay " + log + " --params " + Shipped() + " -o " + dir.File("out.csv"), txt),
            0);
  EXPECT_EQ(ReadCsv(dir.File("out.csv")).rows.size(), 900u);

  EXPECT_EQ(RunScw("replay " + log + " --params " + Shipped() + " --compare " +
                       dir.File("halved.yaml") + " --release-compat",
                   txt),
            0);
  s = testing::ReadFile(txt);
  EXPECT_NE(s.find("first diverge"), std::string::npos) << s;

  // Bad log: exit 2 naming the line and the column.
  std::string text = testing::ReadFile(log);
  const std::size_t third_row = text.find('\n', text.find('\n', text.find('\n') + 1) + 1) + 1;
  text.replace(text.find(',', third_row) + 1, 0, "x");  // vx of line 4 → "x…"
  std::ofstream(dir.File("bad.csv")) << text;
  EXPECT_EQ(RunScw("replay " + dir.File("bad.csv") + " --params " + Shipped(), txt), 2);
  s = testing::ReadFile(txt);
  EXPECT_NE(s.find("line 4, column vx_mps"), std::string::npos) << s;

  // Bad params file, missing log, missing --params: bad input too.
  std::ofstream(dir.File("bad.yaml")) << "/core/control/StabilityController:\n"
                                         "  ros__parameters:\n    tS: 0.01\n";
  EXPECT_EQ(RunScw("replay " + log + " --params " + dir.File("bad.yaml"), txt), 2);
  EXPECT_EQ(RunScw("replay " + dir.File("none.csv") + " --params " + Shipped(), txt), 2);
  EXPECT_EQ(RunScw("replay " + log, txt), 2);
  EXPECT_NE(testing::ReadFile(txt).find("--params"), std::string::npos);
  EXPECT_EQ(RunScw("replay --params " + Shipped(), txt), 2);
  EXPECT_EQ(RunScw("replay --columns", txt), 0);
  EXPECT_NE(testing::ReadFile(txt).find("| `long_fx_N` | N |"), std::string::npos);
  EXPECT_EQ(RunScw("replay " + log + " --params " + Shipped() + " -o " + log, txt), 2);
  // Output folder missing: the run failed (1).
  EXPECT_EQ(
      RunScw("replay " + log + " --params " + Shipped() + " -o /nonexistent-dir/out.csv", txt), 1);
}

/// Bytes a terminal acts on or shows as garbage: control characters (line breaks aside), DEL and
/// bytes of no UTF-8 character (the messages must quote a file's text as \xNN).
std::string RawBytesIn(const std::string& text) {
  std::string found;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto b = static_cast<unsigned char>(text[i]);
    if ((b < 0x20 && b != '\n') || b == 0x7F || b >= 0x80) found += "\\x" + std::to_string(b);
  }
  return found;
}

// Issue 50 finding 11: a binary file given as the log (4000 bytes of a fixed pseudo-random
// sequence, with the header line made long and free of NUL so that the control byte is found
// by the text check, not the NUL check) is one message saying so; nothing of it is echoed.
TEST(ReplayCommand, BinaryLogIsNamedNotEchoed) {
  const TempDir dir("scw_replay_binary");
  const std::string txt = dir.File("out.txt");
  std::string bytes;
  std::uint32_t x = 2463534242u;  // xorshift32: the same bytes on every run
  for (int i = 0; i < 4000; ++i) {
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    bytes.push_back(static_cast<char>(x & 0xFF));
  }
  struct Case {
    std::string name, text, message;
  };
  std::string no_nul = bytes;
  for (char& c : no_nul)
    if (c == '\0' || c == '\n') c = '\x1B';
  const Case cases[] = {
      {"random.csv", bytes, "this is a binary file, not a CSV controller log"},
      {"escape.csv", no_nul, "a control character (\\x"},
      {"nul.csv", "t_s,vx_mps" + std::string(1, '\0') + ",vy\n0,0,0\n", "a NUL byte"},
  };
  for (const Case& c : cases) {
    std::ofstream(dir.File(c.name), std::ios::binary) << c.text;
    EXPECT_EQ(RunScw("replay " + dir.File(c.name) + " --params " + Shipped(), txt), 2) << c.name;
    const std::string s = testing::ReadFile(txt);
    EXPECT_NE(s.find(dir.File(c.name) + ": line 1: "), std::string::npos) << s;
    EXPECT_NE(s.find(c.message), std::string::npos) << s;
    EXPECT_EQ(RawBytesIn(s), "") << c.name << ": " << s;
    EXPECT_LT(s.size(), 400u) << s;
  }
}

// Issue 50 finding 21: a CSV with other columns altogether is one short message that says what a
// log needs and where the list is, not one line per missing column.
TEST(ReplayCommand, OtherCsvIsOneShortMessage) {
  const TempDir dir("scw_replay_other_csv");
  const std::string txt = dir.File("out.txt");
  std::ofstream(dir.File("s.csv")) << "a,b,c\n1,2,3\n";
  EXPECT_EQ(RunScw("replay " + dir.File("s.csv") + " --params " + Shipped(), txt), 2);
  const std::string s = testing::ReadFile(txt);
  const auto required = std::count_if(kInputColumns.begin(), kInputColumns.end(),
                                      [](const LogColumn& c) { return c.required; });
  EXPECT_NE(s.find(dir.File("s.csv") +
                   ": line 1: not a controller log header: none of its 3 "
                   "column(s) (a, b, c) is a log column; a log needs the " +
                   std::to_string(required) + " required columns t_s, vx_mps, "),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("scw replay --columns"), std::string::npos) << s;
  // After "error: invalid input", the one problem on one line.
  const std::size_t at = s.find("error: invalid input\n");
  ASSERT_NE(at, std::string::npos) << s;
  const std::string problem = s.substr(at + 21);
  EXPECT_EQ(std::count(problem.begin(), problem.end(), '\n'), 1) << s;
  EXPECT_LT(problem.size(), 400u) << s;
}

}  // namespace
}  // namespace scw::tuning::replay

namespace scw::tuning::replay {
namespace {

// Issue 27 item 18: a replay output and a simulate trace share a column name only for the same
// quantity. The controller's slip and slip-angle estimates are `slip_est_*` / `alpha_est_*`; the
// trace's `slip_*_pct` / `alpha_*_rad` are the plant's true values.
TEST(ReplayColumns, EstimatesAreNamedApartFromThePlantsTrueValues) {
  std::set<std::string> replay, trace;
  for (const auto& c : kOutputColumns) replay.insert(std::string(c.name));
  for (const auto& name : TraceHeader()) trace.insert(name);
  for (const char* w : {"fl", "fr", "rl", "rr"}) {
    EXPECT_TRUE(replay.count(std::string("slip_est_") + w + "_pct")) << w;
    EXPECT_TRUE(replay.count(std::string("alpha_est_") + w + "_rad")) << w;
    EXPECT_TRUE(trace.count(std::string("slip_") + w + "_pct")) << w;
  }
  // Every name the two files share means the same signal: the controller's outputs.
  for (const auto& name : replay) {
    if (!trace.count(name)) continue;
    EXPECT_TRUE(name.find("_out") != std::string::npos || name == "t_s" || name == "esc_active" ||
                name == "cs_active" || name == "yaw_moment_Nm")
        << name << " is in both files";
  }
}

}  // namespace
}  // namespace scw::tuning::replay
