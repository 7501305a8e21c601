// FastAtan/FastSin/FastCos: accuracy against a long-double reference on dense grids, exact
// symmetry (the tyre model's odd/even invariants rest on it), special values, lane independence.
#include "plant/common/fast_math.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace scw::plant {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Linear grid over [-10, 10] (the slip and Magic Formula range, all three reduction rows) plus a
// logarithmic one over 1e-300 .. 1e300 of both signs.
std::vector<double> AtanGrid() {
  std::vector<double> g;
  for (double x = -10.0; x <= 10.0; x += 3.7e-5) g.push_back(x);
  for (double x = 1e-300; x < 1e300; x *= 1.0007) {
    g.push_back(x);
    g.push_back(-x);
  }
  return g;
}

TEST(FastMath, AtanMatchesTheReferenceOnADenseGrid) {
  long double max_abs = 0.0L, max_rel = 0.0L;
  for (double x : AtanGrid()) {
    const long double ref = std::atan(static_cast<long double>(x));
    const long double err = std::fabs(static_cast<long double>(FastAtan(x)) - ref);
    max_abs = std::max(max_abs, err);
    max_rel = std::max(max_rel, err / std::fabs(ref));
  }
  EXPECT_LE(max_abs, 4e-16L);
  EXPECT_LE(max_rel, 5e-16L);
}

TEST(FastMath, SinCosMatchTheReferenceOverTheMagicFormulaRange) {
  // |C atan(.)| <= 3 pi/2 for the schema's shape factors; RVY5 allows up to 5 pi.
  long double max_sin = 0.0L, max_cos = 0.0L;
  for (double x = -16.0; x <= 16.0; x += 1.1e-5) {
    const long double lx = x;
    max_sin = std::max(max_sin, std::fabs(FastSin(x) - std::sin(lx)));
    max_cos = std::max(max_cos, std::fabs(FastCos(x) - std::cos(lx)));
  }
  EXPECT_LE(max_sin, 3e-16L);
  EXPECT_LE(max_cos, 3e-16L);
}

TEST(FastMath, SymmetryIsBitExact) {
  for (double x : AtanGrid()) EXPECT_EQ(FastAtan(-x), -FastAtan(x)) << x;
  for (double x = 0.0; x <= 16.0; x += 1.3e-4) {
    EXPECT_EQ(FastSin(-x), -FastSin(x)) << x;
    EXPECT_EQ(FastCos(-x), FastCos(x)) << x;
  }
}

TEST(FastMath, SpecialValues) {
  EXPECT_EQ(FastAtan(kInf), std::atan(kInf));
  EXPECT_EQ(FastAtan(-kInf), -std::atan(kInf));
  EXPECT_TRUE(std::isnan(FastAtan(kNaN)));
  EXPECT_TRUE(std::signbit(FastAtan(-0.0)));
  EXPECT_EQ(FastAtan(1.0), std::atan(1.0));
  EXPECT_TRUE(std::signbit(FastSin(-0.0)));
  EXPECT_EQ(FastCos(0.0), 1.0);
  // Outside the inline range and non-finite: the std:: fallback.
  for (double x : {2e5, -3e7, 1e300}) {
    EXPECT_EQ(FastSin(x), std::sin(x)) << x;
    EXPECT_EQ(FastCos(x), std::cos(x)) << x;
  }
  for (double x : {kInf, -kInf, kNaN}) {
    EXPECT_TRUE(std::isnan(FastSin(x))) << x;
    EXPECT_TRUE(std::isnan(FastCos(x))) << x;
  }
}

TEST(FastMath, LanesAreIndependent) {
  const std::vector<double> xs = {0.0, 0.3, -0.7, 1.9, -4.2, 9.0, 1e-8, -2e3, kInf, kNaN};
  for (double x : xs)
    for (double y : xs) {
      const Double2 v = {x, y};
      const Double2 at = FastAtan(v), s = FastSin(v), c = FastCos(v);
      const auto same = [](double a, double b) {
        return a == b || (std::isnan(a) && std::isnan(b));
      };
      EXPECT_TRUE(same(at[0], FastAtan(x)) && same(at[1], FastAtan(y))) << x << " " << y;
      EXPECT_TRUE(same(s[0], FastSin(x)) && same(s[1], FastSin(y))) << x << " " << y;
      EXPECT_TRUE(same(c[0], FastCos(x)) && same(c[1], FastCos(y))) << x << " " << y;
    }
}

}  // namespace
}  // namespace scw::plant
