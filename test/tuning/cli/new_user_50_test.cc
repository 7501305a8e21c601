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

}  // namespace
}  // namespace scw
