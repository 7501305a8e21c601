// The fuzz targets of test/fuzz as regression tests: every file of the committed seed corpus
// (test/fuzz/corpus/<target>/) and every input that once made a fuzzer fail
// (test/fuzz/regressions/<target>/, one file per finding, named after it) runs through exactly
// the code the fuzzer runs (test/fuzz/fuzz_<target>.cc). An input passes when the loader either
// accepts it with all promised properties or refuses it with scw::ConfigError.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <ostream>
#include <string>
#include <vector>

#include "test/fuzz/fuzz_targets.h"

namespace scw::fuzz {

// Test names in ctest: the target's name, not the bytes of the struct.
void PrintTo(const FuzzTarget& t, std::ostream* os) { *os << t.name; }

namespace {

namespace fs = std::filesystem;

std::vector<fs::path> Inputs(const std::string& target) {
  std::vector<fs::path> out;
  for (const char* kind : {"corpus", "regressions"}) {
    const fs::path dir = fs::path(SCW_SOURCE_DIR) / "test/fuzz" / kind / target;
    if (!fs::is_directory(dir)) continue;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file()) out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

class FuzzRegressionTest : public ::testing::TestWithParam<FuzzTarget> {};

TEST_P(FuzzRegressionTest, EveryCorpusAndRegressionInputPasses) {
  const FuzzTarget& t = GetParam();
  const auto inputs = Inputs(t.name);
  ASSERT_FALSE(inputs.empty()) << "no seed corpus for " << t.name;
  for (const auto& path : inputs) {
    SCOPED_TRACE(path.string());
    std::ifstream in(path, std::ios::binary);
    const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    try {
      EXPECT_EQ(t.run(reinterpret_cast<const std::uint8_t*>(data.data()), data.size()), 0);
    } catch (const std::exception& e) {
      ADD_FAILURE() << "escaped: " << e.what();
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Targets, FuzzRegressionTest, ::testing::ValuesIn(kFuzzTargets),
                         [](const ::testing::TestParamInfo<FuzzTarget>& i) {
                           return std::string(i.param.name);
                         });

}  // namespace
}  // namespace scw::fuzz
