// The preparation cache on disk (tuning/sim/prep_cache.h): exact round trip, misses for anything
// not whole or not ours, the folder from the environment, and a racing line built from cached
// offsets equal bit for bit to the optimised one.
#include "tuning/sim/prep_cache.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "controller/planning/racing_line.h"
#include "plant/track/track.h"

namespace scw::tuning {
namespace {

namespace fs = std::filesystem;

class PrepCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("scw_prep_cache_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

bool BitEqual(const CachedArrays& a, const CachedArrays& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].size() != b[i].size()) return false;
    for (std::size_t k = 0; k < a[i].size(); ++k)
      if (std::memcmp(&a[i][k], &b[i][k], sizeof(double)) != 0) return false;
  }
  return true;
}

TEST_F(PrepCacheTest, StoresAndLoadsEveryDoubleExactly) {
  const PrepCache cache(dir_.string(), "program A");
  const CachedArrays arrays = {{0.1, -0.0, 1e-300, 1.7976931348623157e308, -2.5},
                               {},
                               {std::numeric_limits<double>::infinity(), 3.0 / 7.0}};
  EXPECT_FALSE(cache.Load("ggv", "key").has_value());  // before: a miss (no folder yet)
  cache.Store("ggv", "key", arrays);
  const auto back = cache.Load("ggv", "key");
  ASSERT_TRUE(back.has_value());
  EXPECT_TRUE(BitEqual(*back, arrays));
  // Another kind, key or program is another entry.
  EXPECT_FALSE(cache.Load("line", "key").has_value());
  EXPECT_FALSE(cache.Load("ggv", "key2").has_value());
  EXPECT_FALSE(PrepCache(dir_.string(), "program B").Load("ggv", "key").has_value());
  EXPECT_NE(cache.PathOf("ggv", "key"), PrepCache(dir_.string(), "program B").PathOf("ggv", "key"));
}

TEST_F(PrepCacheTest, ATornForeignOrMalformedEntryIsAMissNeverAnError) {
  const PrepCache cache(dir_.string(), "p");
  cache.Store("ggv", "k", {{1.0, 2.0, 3.0}});
  const std::string path = cache.PathOf("ggv", "k");
  std::string whole;
  {
    std::ifstream in(path);
    whole.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  ASSERT_TRUE(cache.Load("ggv", "k").has_value());
  const auto with = [&](const std::string& text) {
    std::ofstream(path, std::ios::trunc) << text;
    return cache.Load("ggv", "k");
  };
  EXPECT_FALSE(with(whole.substr(0, whole.size() - 4)).has_value());  // torn: no "end"
  EXPECT_FALSE(with("").has_value());
  EXPECT_FALSE(with("something else\n").has_value());
  std::string wrong_count = whole;
  wrong_count.replace(wrong_count.find("\n3\n"), 3, "\n4\n");  // says 4 values, holds 3
  EXPECT_FALSE(with(wrong_count).has_value());
  std::string bad_value = whole;
  bad_value.replace(bad_value.find("0x1p+1"), 6, "0x1p+1x");
  EXPECT_FALSE(with(bad_value).has_value());
  EXPECT_TRUE(with(whole).has_value());
}

TEST_F(PrepCacheTest, DisabledStoresNothing) {
  const PrepCache off("", "p");
  EXPECT_FALSE(off.enabled());
  off.Store("ggv", "k", {{1.0}});
  EXPECT_FALSE(off.Load("ggv", "k").has_value());
  EXPECT_FALSE(fs::exists(dir_));
}

TEST_F(PrepCacheTest, AFolderThatCannotBeMadeIsIgnored) {
  fs::create_directories(dir_);
  std::ofstream(dir_ / "file") << "x";
  const PrepCache cache((dir_ / "file" / "sub").string(), "p");  // below a regular file
  cache.Store("ggv", "k", {{1.0}});
  EXPECT_FALSE(cache.Load("ggv", "k").has_value());
}

TEST(PrepCacheFolder, FromTheEnvironment) {
  const char* saved = std::getenv("SCW_CACHE_DIR");
  const std::string keep = saved ? saved : "";
  ::setenv("SCW_CACHE_DIR", "/somewhere/scw", 1);
  EXPECT_EQ(PrepCacheFolderFromEnvironment(), "/somewhere/scw");
  ::setenv("SCW_CACHE_DIR", "off", 1);
  EXPECT_EQ(PrepCacheFolderFromEnvironment(), "");
  ::setenv("SCW_CACHE_DIR", "", 1);
  EXPECT_EQ(PrepCacheFolderFromEnvironment(), "");
  ::unsetenv("SCW_CACHE_DIR");
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const std::string keep_xdg = xdg ? xdg : "";
  ::setenv("XDG_CACHE_HOME", "/xdg", 1);
  EXPECT_EQ(PrepCacheFolderFromEnvironment(), "/xdg/scw");
  ::unsetenv("XDG_CACHE_HOME");
  if (const char* home = std::getenv("HOME")) {
    EXPECT_EQ(PrepCacheFolderFromEnvironment(), std::string(home) + "/.cache/scw");
  }
  if (xdg) ::setenv("XDG_CACHE_HOME", keep_xdg.c_str(), 1);
  if (saved) ::setenv("SCW_CACHE_DIR", keep.c_str(), 1);
}

bool SameTrack(const plant::Track& a, const plant::Track& b) {
  return a.length() == b.length() && a.size() == b.size() && a.s() == b.s() && a.x() == b.x() &&
         a.y() == b.y() && a.heading() == b.heading() && a.curvature() == b.curvature() &&
         a.width_left() == b.width_left() && a.width_right() == b.width_right() &&
         a.friction() == b.friction();
}

TEST(RacingLineKnownOffset, TheLineFromKnownOffsetsIsTheOptimisedLineBitForBit) {
  params::TrackParams oval;  // the schema's default: a small oval
  const plant::Track track = plant::Track::FromDefinition(oval, "oval");
  controller::planning::RacingLineOptions ro;
  const controller::planning::RacingLine optimised =
      controller::planning::MinimumCurvatureLine(track, ro);
  ASSERT_NE(optimised.status, "known");
  ASSERT_FALSE(optimised.offset.empty());
  controller::planning::RacingLineOptions known = ro;
  known.known_offset = &optimised.offset;
  const controller::planning::RacingLine rebuilt =
      controller::planning::MinimumCurvatureLine(track, known);
  EXPECT_EQ(rebuilt.status, "known");
  EXPECT_EQ(rebuilt.offset, optimised.offset);
  EXPECT_EQ(rebuilt.objective_final, optimised.objective_final);
  EXPECT_TRUE(SameTrack(rebuilt.line, optimised.line));
  // Offsets that do not fit (another node count, or outside the bounds) are not used.
  const std::vector<double> short_list(optimised.offset.begin(), optimised.offset.end() - 1);
  known.known_offset = &short_list;
  EXPECT_NE(controller::planning::MinimumCurvatureLine(track, known).status, "known");
  std::vector<double> outside = optimised.offset;
  outside[0] = 1e6;
  known.known_offset = &outside;
  EXPECT_NE(controller::planning::MinimumCurvatureLine(track, known).status, "known");
}

}  // namespace
}  // namespace scw::tuning
