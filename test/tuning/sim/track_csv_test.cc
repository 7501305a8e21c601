// CSV loaders: both public track formats and a given raceline load; bad cells fail naming file,
// line and column.
#include "tuning/sim/track_csv.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "test/test_data.h"

namespace scw::plant {
namespace {

using tuning::LoadTrackCsv;

class TrackCsvBad : public ::testing::Test {
 protected:
  std::string Write(const std::string& name, const std::string& text) {
    const auto p = std::filesystem::temp_directory_path() /
                   ("scw_track_csv_" + std::to_string(::getpid()) + "_" + name);
    std::ofstream(p) << text;
    files_.push_back(p);
    return p.string();
  }
  void TearDown() override {
    for (const auto& f : files_) std::filesystem::remove(f);
  }
  // A closed 12-point loop in the racetrack-database format with one line replaced.
  std::string Loop(int bad_row = -1, const std::string& bad_line = "") {
    std::string text = "# x_m,y_m,w_tr_right_m,w_tr_left_m\n";
    for (int i = 0; i < 12; ++i) {
      const double a = 2 * 3.141592653589793 * i / 12;
      text += i == bad_row ? bad_line + "\n"
                           : std::to_string(40 * std::cos(a)) + "," +
                                 std::to_string(40 * std::sin(a)) + ",4.0,4.0\n";
    }
    return text;
  }
  static std::string Message(const std::string& path) {
    try {
      LoadTrackCsv(path);
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "no error";
  }
  std::vector<std::filesystem::path> files_;
};

TEST_F(TrackCsvBad, ValidLoopLoads) {
  const Track t = LoadTrackCsv(Write("ok.csv", Loop()));
  EXPECT_NEAR(t.length(), 2 * 3.141592653589793 * 40, 2.0);
}

TEST_F(TrackCsvBad, NanCellNamesFileLineAndColumn) {
  const std::string f = Write("nan.csv", Loop(3, "1.0,nan,4.0,4.0"));
  const std::string msg = Message(f);
  EXPECT_NE(msg.find(f), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 5, column y_m"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not a finite number"), std::string::npos) << msg;
}

TEST_F(TrackCsvBad, NonNumericCellNamesFileLineAndColumn) {
  const std::string msg = Message(Write("text.csv", Loop(6, "1.0,2.0,abc,4.0")));
  EXPECT_NE(msg.find("line 8, column w_tr_right_m: 'abc' is not a number"), std::string::npos)
      << msg;
}

TEST_F(TrackCsvBad, MissingColumnIsNamed) {
  const std::string msg = Message(Write("col.csv", "x_m,y_m,w_tr_right_m\n1,2,3\n"));
  EXPECT_NE(msg.find("missing column 'w_tr_left_m'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 1"), std::string::npos) << msg;
}

TEST_F(TrackCsvBad, MissingCellIsNamed) {
  const std::string msg = Message(Write("short.csv", Loop(2, "1.0,2.0,4.0")));
  EXPECT_NE(msg.find("line 4, column w_tr_left_m: missing value"), std::string::npos) << msg;
}

// Issue 50 finding 11: a binary file is one problem that says so; a header or cell of raw bytes
// is quoted as \xNN (the terminal never gets the file's control bytes).
TEST_F(TrackCsvBad, BinaryFileAndRawBytesAreNotEchoed) {
  const std::string nul = Message(Write("nul.csv", std::string("\x1B[2J\x9B") + '\0' + "x\n1\n"));
  EXPECT_NE(nul.find("nul.csv: line 1: a NUL byte: this is a binary file, not CSV text"),
            std::string::npos)
      << nul;
  EXPECT_EQ(nul.find('\x1B'), std::string::npos) << nul;
  const std::string header = Message(Write("head.csv", "x_m,\x1B]0;t\x07,y\xFF\xC3\xA9\n1,2,3\n"));
  EXPECT_NE(header.find("(the header is 'x_m,\\x1B]0;t\\x07,y\\xFF\xC3\xA9'"), std::string::npos)
      << header;
  const std::string cell = Message(Write("cell.csv", Loop(6, "1.0,2.0,\x1B[31m,4.0")));
  EXPECT_NE(cell.find("line 8, column w_tr_right_m: '\\x1B[31m' is not a number"),
            std::string::npos)
      << cell;
}

TEST_F(TrackCsvBad, TooFewRowsAndOpenLoopsAreRejected) {
  const std::string few =
      Message(Write("few.csv", "x_m,y_m,w_tr_right_m,w_tr_left_m\n0,0,1,1\n1,0,1,1\n"));
  EXPECT_NE(few.find("too few rows"), std::string::npos) << few;
  std::string open = "x_m,y_m,w_tr_right_m,w_tr_left_m\n";
  for (int i = 0; i < 20; ++i) open += std::to_string(10.0 * i) + ",0,3,3\n";
  const std::string msg = Message(Write("open.csv", open));
  EXPECT_NE(msg.find("does not close"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 21 (last row)"), std::string::npos) << msg;
}

TEST(TrackCsvPublic, BothPublicFormatsLoad) {
  const std::string yas = test::SharedData(test::kYasSmoothed);
  const std::string monza = test::SharedData(test::kMonza);
  if (yas.empty() || monza.empty()) GTEST_SKIP() << "../shared/data/tracks not present";
  const Track y = LoadTrackCsv(yas);  // Track3D: negative right widths, closing row repeated
  EXPECT_NEAR(y.length(), 3004.1, 3.0);
  EXPECT_GT(y.width_right()[0], 0.0);
  const Track m = LoadTrackCsv(monza);  // racetrack-database
  EXPECT_NEAR(m.length(), 5790.2, 10.0);
  EXPECT_NEAR(std::abs(m.total_turning()), 2 * 3.141592653589793, 1e-9);
}

// The shipped example of a user's own track (examples/club, docs/track-files.md) loads as the
// docs describe it, and a point on the normal of node 0 projects there from any side: the racing
// line of this track starts 5e-12 m behind node 0 and 3.9 m to its right, where the tangent of
// node N (= node 0, at psi0 + 2 pi) rounded differently and the search took a segment 138 m away,
// so every run on it ended off track at t = 0.
TEST(TrackCsvPublic, TheClubExampleLoadsAndItsStartNormalProjectsToTheStart) {
  const Track t = LoadTrackCsv(std::string(SCW_SOURCE_DIR) + "/examples/club/club.csv");
  EXPECT_EQ(t.name(), "club");
  EXPECT_NEAR(t.length(), 1523.5, 1.0);
  EXPECT_EQ(t.width_left()[0] + t.width_right()[0], 12.0);
  EXPECT_NEAR(t.total_turning(), 2 * 3.141592653589793, 1e-9);
  const TrackPose p0 = t.PoseAt(0.0);
  const double nx = -std::sin(p0.heading), ny = std::cos(p0.heading);
  const double tx = std::cos(p0.heading), ty = std::sin(p0.heading);
  for (double n : {-5.9, -3.9192725794505785, 0.0, 2.5, 5.9})
    for (double along : {-1e-9, -5.388756266230354e-12, 0.0, 1e-12, 1e-9}) {
      const TrackProjection r = t.Project(p0.x + n * nx + along * tx, p0.y + n * ny + along * ty,
                                          p0.heading, Track::kNoHint);
      const double s = r.s > t.length() / 2 ? r.s - t.length() : r.s;
      EXPECT_NEAR(s, 0.0, 1e-6) << "n " << n << ", along " << along;
      EXPECT_NEAR(r.n, n, 1e-6) << "n " << n << ", along " << along;
    }
  // The racing line's first point, as the planner gives it.
  const TrackProjection line =
      t.Project(-5.388756266230354e-12, -3.9192725794505785, -0.010067302224018903, Track::kNoHint);
  EXPECT_LT(std::min(line.s, t.length() - line.s), 1e-6);
  EXPECT_NEAR(line.n, -3.919, 0.01);
}

TEST(RacingLine, GivenRacelineFileLoads) {
  const std::string ref = test::SharedData(test::kYasSmoothed);
  const std::string line =
      test::SharedData("tracks/yas_north/global_racing_lines/yasnorth_3d_dallaraAV21_gg_0.1.csv");
  if (ref.empty() || line.empty()) GTEST_SKIP() << "../shared/data/tracks/yas_north not present";
  const plant::Track t = tuning::LoadTrackCsv(ref);
  const controller::planning::RacingLine rl = tuning::LoadRacingLine(line, t);
  EXPECT_NEAR(rl.line.length(), 2990.0, 60.0);
  EXPECT_LT(controller::planning::SquaredCurvatureIntegral(rl.line),
            controller::planning::SquaredCurvatureIntegral(t));
}

}  // namespace
}  // namespace scw::plant
