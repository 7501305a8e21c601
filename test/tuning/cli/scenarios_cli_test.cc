// `scw scenarios init` end to end with the built program: the set names its track and vehicle
// relative to its own folder and scw tune reads it from anywhere; an existing file is kept
// unless --force; `-o -` writes to stdout; a track without corners and a missing track are bad
// input (exit 2) and write nothing.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "test/common/cli_run.h"

namespace scw {
namespace {

namespace fs = std::filesystem;

class ScenariosCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("scw_scenarios_cli_" + std::to_string(::getpid()) + "_" + std::string(info->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "sets");
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  test::CliResult Scw(const std::string& args) { return test::RunCli(SCW_BIN, args, dir_); }
  std::string Club() const { return std::string(SCW_SOURCE_DIR) + "/examples/club/club.csv"; }

  fs::path dir_;
};

TEST_F(ScenariosCliTest, TheSetNamesItsFilesRelativeToItsFolderAndLoadsFromAnywhere) {
  ASSERT_EQ(Scw("vehicle init -o " + (dir_ / "car.yaml").string()).code, 0);
  const fs::path set = dir_ / "sets" / "club_set.yaml";
  const auto r =
      Scw("scenarios init --track " + Club() + " --vehicle " + (dir_ / "car.yaml").string() +
          " --training-corners 1 --held-out-corners 0" + " -o " + set.string());
  ASSERT_EQ(r.code, 0) << r.all();
  EXPECT_NE(r.out.find("5 training and 1 held-out scenarios"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("next:  scw tune --scenarios"), std::string::npos) << r.out;
  const std::string text = test::Slurp(set);
  EXPECT_EQ(text.rfind("# Starter scenario set for club", 0), 0u) << text;
  EXPECT_NE(text.find("vehicle=../car.yaml"), std::string::npos) << text;
  const std::string rel =
      fs::canonical(Club()).lexically_relative(fs::canonical(dir_ / "sets")).string();
  EXPECT_NE(text.find("track=" + rel), std::string::npos) << rel << "\n" << text;
  // Evaluated from another working folder: every scenario's track and vehicle resolve and run.
  const auto e =
      test::RunCli("cd / && " + std::string(SCW_BIN), "evaluate --scenarios " + set.string(), dir_);
  ASSERT_EQ(e.code, 0) << e.all();
  EXPECT_NE(e.out.find("power_on_c1"), std::string::npos) << e.out;
  EXPECT_NE(e.out.find("clean_gg1.15"), std::string::npos) << e.out;
}

TEST_F(ScenariosCliTest, AnExistingSetIsKeptUnlessForced) {
  const fs::path set = dir_ / "set.yaml";
  std::ofstream(set) << "# my edits\n";
  const auto r = Scw("scenarios init --track " + Club() + " -o " + set.string());
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("add --force"), std::string::npos) << r.err;
  EXPECT_EQ(test::Slurp(set), "# my edits\n");
  const auto f = Scw("scenarios init --track " + Club() + " -o " + set.string() + " --force");
  EXPECT_EQ(f.code, 0) << f.all();
  EXPECT_EQ(test::Slurp(set).rfind("# Starter scenario set", 0), 0u);
}

TEST_F(ScenariosCliTest, DashWritesTheSetToStdoutAndTheTableToStderr) {
  const auto r =
      Scw("scenarios init --track yas_north --training-corners 1 "
          "--held-out-corners 0 -o -");
  ASSERT_EQ(r.code, 0) << r.all();
  EXPECT_EQ(r.out.rfind("# Starter scenario set for Yas Marina North", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("track=yas_north"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("held_out:\n  - {name: power_on"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("5 training and 1 held-out scenarios"), std::string::npos) << r.err;
}

TEST_F(ScenariosCliTest, ATrackWithoutCornersOrAMissingTrackIsBadInput) {
  // A circle of radius 400 m: never below the 250 m of a corner.
  std::ostringstream csv;
  csv << "# x_m,y_m,w_tr_right_m,w_tr_left_m\n";
  for (int k = 0; k < 500; ++k) {
    const double a = 2 * M_PI * k / 500.0;
    csv << 400 * std::cos(a) << ',' << 400 * std::sin(a) << ",6,6\n";
  }
  std::ofstream(dir_ / "circle.csv") << csv.str();
  const auto r = Scw("scenarios init --track " + (dir_ / "circle.csv").string() + " -o " +
                     (dir_ / "s.yaml").string());
  EXPECT_EQ(r.code, 2) << r.all();
  EXPECT_NE(r.err.find("no corner"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "s.yaml"));
  const auto m = Scw("scenarios init --track missing.csv -o " + (dir_ / "s.yaml").string());
  EXPECT_EQ(m.code, 2) << m.all();
  EXPECT_FALSE(fs::exists(dir_ / "s.yaml"));
}

}  // namespace
}  // namespace scw
