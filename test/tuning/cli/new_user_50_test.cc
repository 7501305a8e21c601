// What a new user ran into, issue 50, end to end with the built `scw` program: a corner over the
// start line had a negative length (7), two different "ideal lap" numbers with nothing saying
// what each is (13), a Monza run called "scenario default" (18), a truncated default in
// `params export --help` (19), one-node and kink corners counted without a word (20), and the
// maneuver's console and figure without the standard's limits, the test conditions or a note that
// ESC never acted (9, 17).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "test/common/cli_run.h"

namespace scw {
namespace {

namespace fs = std::filesystem;

using Result = test::CliResult;

class NewUser50Test : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("scw_new_user_50_" + std::to_string(::getpid()) + "_" + std::string(info->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  Result Scw(const std::string& args) { return test::RunCli(SCW_BIN, args, dir_); }

  /// A stadium oval (two 150 m straights, two 180° bends of radius 50 m, anticlockwise) in the
  /// racetrack-database format, its first point in the middle of a bend: the corner there is
  /// found last and runs over s = 0.
  std::string OvalStartingInACorner() {
    const double r = 50.0, straight = 150.0;
    std::ostringstream csv;
    csv << "# x_m,y_m,w_tr_right_m,w_tr_left_m\n";
    auto point = [&](double x, double y) { csv << x << ',' << y << ",6,6\n"; };
    // Right bend (centre (straight, r)) from its middle (angle 0) to its end (angle 90°).
    for (int k = 0; k < 78; ++k) {
      const double a = -M_PI / 2 + M_PI / 2 + (M_PI / 2) * k / 78.0;
      point(straight + r * std::cos(a), r + r * std::sin(a));
    }
    for (int k = 0; k < 150; ++k) point(straight - k, 2 * r);  // top straight, leftwards
    for (int k = 0; k < 157; ++k) {                            // left bend
      const double a = M_PI / 2 + M_PI * k / 157.0;
      point(r * std::cos(a), r + r * std::sin(a));
    }
    for (int k = 0; k < 150; ++k) point(k, 0.0);  // bottom straight, rightwards
    for (int k = 0; k < 78; ++k) {                // first half of the right bend
      const double a = -M_PI / 2 + (M_PI / 2) * k / 78.0;
      point(straight + r * std::cos(a), r + r * std::sin(a));
    }
    const std::string path = Path("oval.csv");
    std::ofstream(path) << csv.str();
    return path;
  }

  fs::path dir_;
};

/// The rows of `scw track info`'s corner table: number → the line.
std::vector<std::string> CornerRows(const std::string& out) {
  std::vector<std::string> rows;
  std::istringstream in(out);
  const std::regex row(R"(^\s+\d+\s+(left |right)\s)");
  for (std::string line; std::getline(in, line);)
    if (std::regex_search(line, row)) rows.push_back(line);
  return rows;
}

// 7: the corner over the start line is measured forward across s = 0.
TEST_F(NewUser50Test, CornerOverTheStartLineHasItsLength) {
  const Result r = Scw("track info --track " + OvalStartingInACorner());
  ASSERT_EQ(r.code, 0) << r.all();
  const auto rows = CornerRows(r.out);
  ASSERT_EQ(rows.size(), 2u) << r.out;
  double total = 0.0;
  for (const auto& row : rows) {
    std::istringstream in(row);
    int number = 0;
    std::string dir;
    double from = 0, to = 0, length = 0, radius = 0;
    in >> number >> dir >> from >> to >> length >> radius;
    EXPECT_GT(length, 100.0) << row;  // each bend is 157 m of arc
    EXPECT_LT(length, 200.0) << row;
    EXPECT_NEAR(radius, 50.0, 5.0) << row;
    total += length;
  }
  EXPECT_NEAR(total, 2 * M_PI * 50.0, 25.0) << r.out;
  EXPECT_NE(rows[1].find("spans the start line"), std::string::npos) << r.out;
  EXPECT_EQ(rows[0].find("spans the start line"), std::string::npos) << r.out;
}

// 20: the rule is stated, one-node and kink corners are flagged, and the numbering is kept (the
// built-in Yas Marina North: #4 has no radius below 220 m, #6 is one node below 250 m).
TEST_F(NewUser50Test, TrackInfoSaysWhatACornerIsAndFlagsTheOddOnes) {
  const Result r = Scw("track info");
  ASSERT_EQ(r.code, 0) << r.all();
  EXPECT_NE(r.out.find("A corner: nodes that curve one way with\n  a radius below 250 m"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("(events.*.corner = N:\n  the apex of corner N, plus s)"), std::string::npos)
      << r.out;
  const auto rows = CornerRows(r.out);
  ASSERT_EQ(rows.size(), 9u) << r.out;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const bool kink = i == 3 || i == 5, short_one = i == 5;
    EXPECT_EQ(rows[i].find("kink: min R above 150 m") != std::string::npos, kink) << rows[i];
    EXPECT_EQ(rows[i].find("short: only 1.0 m below 250 m radius") != std::string::npos, short_one)
        << rows[i];
  }
  EXPECT_NE(r.out.find("note: 2 corner(s) marked short or kink"), std::string::npos) << r.out;
}

// 13 and 18: both "ideal lap" numbers say what they are; the run names its track.
TEST_F(NewUser50Test, IdealLapsSayWhatTheyAreAndTheRunNamesItsTrack) {
  const std::string oval = OvalStartingInACorner();
  const Result line = Scw("track line --track " + oval + " -o " + Path("line.csv"));
  ASSERT_EQ(line.code, 0) << line.all();
  EXPECT_NE(line.out.find("  = the velocity profile on this line at the full limits of a "
                          "representative AV-21/EAV g-g-v\n    table"),
            std::string::npos)
      << line.out;
  EXPECT_NE(line.out.find("It is not the simulated car's: scw simulate\n    plans on the "
                          "vehicle's own envelope x GG x limit_fraction"),
            std::string::npos)
      << line.out;
  const Result sim = Scw("simulate --set track=" + oval + " laps=1 --progress never");
  ASSERT_LE(sim.code, 1) << sim.all();
  EXPECT_EQ(sim.out.rfind("scenario default on oval: ", 0), 0u) << sim.out;
  EXPECT_NE(sim.err.find("the speed profile the car is asked to drive (the vehicle's own g-g-v\n"
                         "  envelope x GG 1 x limit_fraction 0.7; at the envelope's full limits "),
            std::string::npos)
      << sim.err;
}

// 19: the default node keys in full.
TEST_F(NewUser50Test, ParamsHelpShowsTheDefaultNodeKeys) {
  for (const std::string sub : {"export", "init"}) {
    const Result r = Scw("params " + sub + " --help");
    EXPECT_EQ(r.code, 0) << sub;
    // CLI11 wraps long descriptions: compare without the line breaks and indentation.
    const std::string flat = std::regex_replace(r.out, std::regex(R"(\s+)"), " ");
    EXPECT_NE(flat.find("Node key written (default: /core/control/StabilityController, or "
                        "/core/control/TrackingController with --kind tracking)"),
              std::string::npos)
        << sub << ":\n"
        << r.out;
  }
}

/// python3 with matplotlib (Debian's first where a pyenv one lacks it), or "".
std::string PythonWithMatplotlib() {
  for (const char* py : {"python3", "/usr/bin/python3"})
    if (std::system((std::string(py) + " -c 'import matplotlib' >/dev/null 2>&1").c_str()) == 0)
      return py;
  return "";
}

// 9 and 17: the standard's limits, the conditions and what a column is in the console; a note
// when ESC never acted (80 km/h); the same in the figure, whose run colours have a colour bar.
TEST_F(NewUser50Test, ManeuverSaysLimitsConditionsAndWhatWasNotTested) {
  const Result r = Scw("maneuver sine_with_dwell --json " + Path("r.json"));
  ASSERT_EQ(r.code, 0) << r.all();
  for (const char* part :
       {"subsystems: ESC CS ABS TC (stability control on)\n", "pass limits:\n",
        "  ratio_1_00_pct <= 35.0  (FMVSS 126 S5.2.1; every run)\n",
        "  ratio_1_75_pct <= 20.0  (FMVSS 126 S5.2.2; every run)\n",
        "  lateral_displacement_m >= 1.83  (FMVSS 126 S5.2.3; runs 5.00 A to ",
        "  lateral_displacement_m: at BOS + 1.07 s, towards the first steer\n",
        "note: ESC ran but did not act in any run: at these conditions this test does not "
        "exercise ESC"})
    EXPECT_NE(r.out.find(part), std::string::npos) << part << "\n" << r.out;
  EXPECT_EQ(r.out.find("-0.000"), std::string::npos) << r.out;

  const Result off =
      Scw("maneuver sine_with_dwell --set maneuver.speed=40 --subsystems none "
          "--json " +
          Path("off.json") + " --plot " + Path("off.png"));
  ASSERT_TRUE(off.code == 0 || off.code == 1) << off.all();
  EXPECT_NE(off.out.find("subsystems: none (stability control off)"), std::string::npos);
  EXPECT_EQ(off.out.find("note: "), std::string::npos) << off.out;

  const std::string py = PythonWithMatplotlib();
  if (py.empty()) GTEST_SKIP() << "no python3 with matplotlib: the figure is not checked";
  EXPECT_TRUE(fs::exists(Path("off.png"))) << off.err;
  const std::string script = std::string(SCW_SOURCE_DIR) + "/tuning/cli/maneuver_plot.py";
  const Result on_fig =
      test::RunCli(py, script + " " + Path("r.json") + " " + Path("on.png"), dir_);
  ASSERT_EQ(on_fig.code, 0) << on_fig.all();
  for (const char* part :
       {"title: sine_with_dwell (FMVSS 126 / UN R140 sine with dwell) at 22.2 m/s (80 km/h) | "
        "stability control on (ESC CS ABS TC); params: built-in; vehicle: built-in | 0 of ",
        "pass limits: ratio_1_00_pct <= 35 (FMVSS 126 S5.2.1; every run)", "colours: colour bar",
        "notes: 1"})
    EXPECT_NE(on_fig.out.find(part), std::string::npos) << part << "\n" << on_fig.out;
  const Result off_fig =
      test::RunCli(py, script + " " + Path("off.json") + " " + Path("off2.png"), dir_);
  ASSERT_EQ(off_fig.code, 0) << off_fig.all();
  EXPECT_NE(off_fig.out.find("at 40.0 m/s (144 km/h) | stability control off (none)"),
            std::string::npos)
      << off_fig.out;
}

}  // namespace
}  // namespace scw
