#include "tuning/exec/parallel_for.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace scw::tuning::exec {
namespace {

// A job whose result depends only on its index (and takes a little time).
double Job(int i) {
  double acc = 0;
  for (int k = 1; k < 20000; ++k) acc += std::sin(i * 0.37 + k * 1e-3) / k;
  return acc;
}

TEST(ParallelTest, ResultsAreIdenticalForAnyThreadCount) {
  const int n = 37;
  std::vector<double> one(n), two(n), four(n);
  ParallelFor(n, 1, [&](int i) { one[i] = Job(i); });
  ParallelFor(n, 2, [&](int i) { two[i] = Job(i); });
  ParallelFor(n, 4, [&](int i) { four[i] = Job(i); });
  EXPECT_EQ(one, two);
  EXPECT_EQ(one, four);
}

TEST(ParallelTest, ExceptionOfLowestIndexIsRethrownAfterAllJobs) {
  std::vector<int> done(10, 0);
  try {
    ParallelFor(10, 2, [&](int i) {
      done[i] = 1;
      if (i == 3 || i == 7) throw std::runtime_error("job " + std::to_string(i));
    });
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "job 3");
  }
  for (int d : done) EXPECT_EQ(d, 1);
}

}  // namespace
}  // namespace scw::tuning::exec
