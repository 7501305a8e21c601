// The replacements of Ipopt's BLAS wrappers (controller/motion/nlp_solver.cc) against Ipopt's own
// (the library's definitions, found behind this program's with dlsym(RTLD_NEXT)): the same index,
// the same copied and scaled values bit for bit, on vectors with NaN, infinities, signed zeros,
// ties and strides.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <IpBlas.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace {

using Ipopt::Index;
using Ipopt::Number;

template <class F>
F Library(const char* mangled) {
  void* f = dlsym(RTLD_NEXT, mangled);
  return reinterpret_cast<F>(f);
}

// Vectors that exercise the reference semantics: ties of the largest magnitude with both signs,
// NaN first / inside / last, infinities, -0.
std::vector<std::vector<Number>> Cases() {
  const Number nan = std::numeric_limits<Number>::quiet_NaN();
  const Number inf = std::numeric_limits<Number>::infinity();
  std::vector<std::vector<Number>> c = {{},
                                        {3.0},
                                        {-0.0, 0.0},
                                        {1.0, -1.0},
                                        {nan, 5.0, 1.0},
                                        {1.0, nan, 3.0, -3.0},
                                        {2.0, 1.0, nan},
                                        {-inf, inf, 1.0},
                                        {0.5, -7.0, 7.0, 7.0, -7.0, 2.0, 1.0, 7.0, 0.0},
                                        {nan, nan},
                                        {0.0, -0.0, -0.0, 0.0, 0.0}};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<Number> u(-4.0, 4.0);
  for (std::size_t n = 1; n <= 41; ++n) {
    std::vector<Number> v(n);
    for (auto& x : v) x = std::round(u(rng));  // integers: many ties
    c.push_back(v);
    if (n > 3) {
      v[n / 3] = nan;
      c.push_back(v);
      for (auto& x : v) x = u(rng);
      c.push_back(v);
    }
  }
  return c;
}

bool SameBits(const std::vector<Number>& a, const std::vector<Number>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Number)) == 0);
}

TEST(IpoptBlasTest, IdamaxIsTheLibrarysIndex) {
  using Fn = Index (*)(Index, const Number*, Index);
  const Fn lib = Library<Fn>("_ZN5Ipopt12IpBlasIdamaxEiPKdi");
  ASSERT_NE(lib, nullptr);
  ASSERT_NE(lib, &Ipopt::IpBlasIdamax);  // ours is this program's, the library's is behind it
  for (const auto& v : Cases())
    for (Index inc : {1, 2, 3, 0, -1}) {
      const auto n = static_cast<Index>(inc > 0 ? (v.size() + inc - 1) / inc : v.size());
      for (Index m : {n, Index{0}, Index{1}, n > 2 ? n - 1 : n}) {
        if (inc <= 0 && m > 1) continue;  // the reference returns before reading: only sizes
        EXPECT_EQ(Ipopt::IpBlasIdamax(m, v.data(), inc), lib(m, v.data(), inc))
            << "size " << m << " of " << v.size() << ", increment " << inc;
      }
    }
}

TEST(IpoptBlasTest, DcopyAndDscalGiveTheLibrarysValues) {
  using Copy = void (*)(Index, const Number*, Index, Number*, Index);
  using Scal = void (*)(Index, Number, Number*, Index);
  const Copy lib_copy = Library<Copy>("_ZN5Ipopt11IpBlasDcopyEiPKdiPdi");
  const Scal lib_scal = Library<Scal>("_ZN5Ipopt11IpBlasDscalEidPdi");
  ASSERT_NE(lib_copy, nullptr);
  ASSERT_NE(lib_scal, nullptr);
  const Number nan = std::numeric_limits<Number>::quiet_NaN();
  for (const auto& v : Cases()) {
    const auto size = static_cast<Index>(v.size());
    // Copies: plain, strided, backwards into y, and Ipopt's fill (x's increment <= 0: every y_i
    // set to x_0). Overlapping copies are outside BLAS's contract (Fortran arguments never alias).
    for (const auto& [inc_x, inc_y] :
         {std::pair<Index, Index>{1, 1}, {2, 1}, {1, 2}, {1, -1}, {3, -2}, {0, 1}, {-1, 2}}) {
      const Index n = size / 2;
      std::vector<Number> a(2 * v.size() + 2, nan), b = a;
      std::vector<Number> x = v;
      x.resize(2 * v.size() + 2, 1.5);
      Ipopt::IpBlasDcopy(n, x.data(), inc_x, a.data(), inc_y);
      lib_copy(n, x.data(), inc_x, b.data(), inc_y);
      EXPECT_TRUE(SameBits(a, b)) << "copy of " << n << ", increments " << inc_x << ", " << inc_y;
    }
    for (Number alpha : {0.0, -0.0, 3.0, -0.1, nan, std::numeric_limits<Number>::infinity()})
      for (Index inc : {1, 2, 0, -1}) {
        std::vector<Number> a = v, b = v;
        const Index n = inc > 0 ? size / inc : size;
        Ipopt::IpBlasDscal(n, alpha, a.data(), inc);
        lib_scal(n, alpha, b.data(), inc);
        EXPECT_TRUE(SameBits(a, b)) << "scale by " << alpha << ", increment " << inc;
      }
  }
}

}  // namespace
