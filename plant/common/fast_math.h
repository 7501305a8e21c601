// Inline, branch-free atan, sin and cos for the plant's hot path (Magic Formula, slip angles),
// on two lanes at once.
//
// Why: a plant step evaluates ~36 atan and ~20 sin/cos. Through glibc these were out-of-line
// calls whose latency chains (atan -> atan -> sin in every Magic Formula curve) bounded the step.
// Here the functions are inlined, choose their range-reduction row with masks instead of
// data-dependent branches (those mispredict: the slips change range from step to step), and work
// on a Double2 (two doubles in one SSE2/NEON register, GCC/Clang vector extension) so that two
// independent curves cost about as much as one. The accuracy is that of libm, so the physics is
// unchanged to rounding level.
//
// Contract (each lane independently; the scalar overloads are lane 0 of the vector version)
//   FastAtan(x):  atan(x) for every double. |error| <= 2.3e-16 absolute and <= 3.4e-16 relative
//                 (test/plant/common/fast_math_test.cc); FastAtan(-x) == -FastAtan(x) bit-exactly
//                 (the Magic Formula relies on it for F_y odd in alpha); +-inf -> +-pi/2,
//                 NaN -> NaN.
//   FastSin(x), FastCos(x): for |x| <= kFastTrigMaxArg (the Magic Formula's arguments are bounded
//                 by C pi/2 <= 5 pi) a Cody-Waite reduction to [-pi/4, pi/4] and the fdlibm
//                 kernels: |error| <= 1.5e-16 absolute. Larger, infinite or NaN inputs fall back to
//                 std::sin/std::cos (correct, just slower). FastSin is exactly odd, FastCos exactly
//                 even.
//   Deterministic: no FMA contraction (top-level CMakeLists), no dependence on the libm in use.
//
// Sources: polynomial kernels of fdlibm (Sun Microsystems; s_atan.c aT[], k_sin.c, k_cos.c), valid
// on |t| <= 7/16 (atan) and |r| <= pi/4 (sin, cos); the pi/2 split of fdlibm e_rem_pio2.c.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace scw::plant {

/// Two doubles processed together (one SSE2/NEON register).
using Double2 = double __attribute__((vector_size(16)));

/// Largest |x| handled inline by FastSin/FastCos; beyond it they call std::sin/std::cos.
inline constexpr double kFastTrigMaxArg = 1.0e5;

namespace fast_math_detail {

// Per-lane all-ones/all-zeros masks, as produced by vector comparisons.
using Mask2 = std::int64_t __attribute__((vector_size(16)));

inline Mask2 Bits(Double2 v) noexcept { return std::bit_cast<Mask2>(v); }
inline Double2 FromBits(Mask2 m) noexcept { return std::bit_cast<Double2>(m); }
inline constexpr Mask2 kSignBit = {INT64_MIN, INT64_MIN};

// Constants as whole registers: a scalar operand would be re-broadcast at every use.
constexpr Double2 Splat(double v) noexcept { return Double2{v, v}; }

// m ? a : b per lane, without a branch.
inline Double2 Select(Mask2 m, Double2 a, Double2 b) noexcept {
  return FromBits((m & Bits(a)) | (~m & Bits(b)));
}
inline Double2 Abs(Double2 v) noexcept { return FromBits(Bits(v) & ~kSignBit); }
// |magnitude| with the sign bit of `sign`.
inline Double2 CopySign(Double2 magnitude, Double2 sign) noexcept {
  return FromBits((Bits(magnitude) & ~kSignBit) | (Bits(sign) & kSignBit));
}

// atan(t) for |t| <= 7/16 (fdlibm s_atan.c, error < 1 ulp): t - t (z S_odd(z^2) + z^2 S_even(z^2))
// with z = t^2; the even/odd split halves the dependency chain of a plain Horner scheme.
inline Double2 AtanKernel(Double2 t) noexcept {
  constexpr Double2 kAt0 = Splat(3.33333333333329318027e-01),
                    kAt1 = Splat(-1.99999999998764832476e-01),
                    kAt2 = Splat(1.42857142725034663711e-01),
                    kAt3 = Splat(-1.11111104054623557880e-01),
                    kAt4 = Splat(9.09088713343650656196e-02),
                    kAt5 = Splat(-7.69187620504482999495e-02),
                    kAt6 = Splat(6.66107313738753120669e-02),
                    kAt7 = Splat(-5.83357013379057348645e-02),
                    kAt8 = Splat(4.97687799461593236017e-02),
                    kAt9 = Splat(-3.65315727442169155270e-02),
                    kAt10 = Splat(1.62858201153657823623e-02);
  const Double2 z = t * t;
  const Double2 w = z * z;
  const Double2 s1 = z * (kAt0 + w * (kAt2 + w * (kAt4 + w * (kAt6 + w * (kAt8 + w * kAt10)))));
  const Double2 s2 = w * (kAt1 + w * (kAt3 + w * (kAt5 + w * (kAt7 + w * kAt9))));
  return t - t * (s1 + s2);
}

// sin(r), cos(r) for |r| <= pi/4 (fdlibm k_sin.c / k_cos.c polynomials; without fdlibm's tail
// correction for cos, which costs latency and buys less than 1e-16 the plant does not need).
inline Double2 SinKernel(Double2 r) noexcept {
  constexpr Double2 kS1 = Splat(-1.66666666666666324348e-01),
                    kS2 = Splat(8.33333333332248946124e-03),
                    kS3 = Splat(-1.98412698298579493134e-04),
                    kS4 = Splat(2.75573137070700676789e-06),
                    kS5 = Splat(-2.50507602534068634195e-08),
                    kS6 = Splat(1.58969099521155010221e-10);
  const Double2 z = r * r;
  const Double2 p = kS2 + z * (kS3 + z * (kS4 + z * (kS5 + z * kS6)));
  return r + r * z * (kS1 + z * p);
}

inline Double2 CosKernel(Double2 r) noexcept {
  constexpr Double2 kC1 = Splat(4.16666666666666019037e-02),
                    kC2 = Splat(-1.38888888888741095749e-03),
                    kC3 = Splat(2.48015872894767294178e-05),
                    kC4 = Splat(-2.75573143513906633035e-07),
                    kC5 = Splat(2.08757232129817482790e-09),
                    kC6 = Splat(-1.13596475577881948265e-11);
  const Double2 z = r * r;
  const Double2 p = z * (kC1 + z * (kC2 + z * (kC3 + z * (kC4 + z * (kC5 + z * kC6)))));
  return Splat(1.0) - (Splat(0.5) * z - z * p);
}

// sin(a + phase pi/2) for 0 <= a <= kFastTrigMaxArg; phase 0 gives sin, phase 1 gives cos (an
// exact quadrant shift, no rounding). With a = k pi/2 + r, |r| <= pi/4, the result is
// +-sin r or +-cos r by (k + phase) mod 4; both kernels run and the lanes pick by mask. Other a
// (huge, inf, NaN) give a meaningless but harmless value (no float -> int conversion, no UB) that
// FixOutOfRange replaces.
inline Double2 SinShifted(Double2 a, std::int64_t phase) noexcept {
  constexpr Double2 kTwoOverPi = Splat(6.36619772367581382433e-01);
  constexpr Double2 kPio2Hi = Splat(1.57079632673412561417e+00);  // 33 bits: k kPio2Hi exact
  constexpr Double2 kPio2Lo = Splat(6.07710050650619224932e-11);  // pi/2 - kPio2Hi
  // Round to nearest by the 1.5 * 2^52 shift (no libm call); the shifted value's low mantissa
  // bits are k itself, which gives the quadrant without a float -> int conversion.
  constexpr Double2 kShift = Splat(6755399441055744.0);
  const Double2 shifted = a * kTwoOverPi + kShift;
  const Double2 k = shifted - kShift;
  const Double2 r = (a - k * kPio2Hi) - k * kPio2Lo;
  const Mask2 q = Bits(shifted) + Mask2{phase, phase};
  const Mask2 zero = {0, 0}, one = {1, 1}, two = {2, 2};
  const Double2 v = Select((q & one) != zero, CosKernel(r), SinKernel(r));
  return FromBits(Bits(v) ^ (((q & two) != zero) & kSignBit));
}

// Lanes outside the inline range (or NaN) take f = std::sin/std::cos; the others keep their
// inline value, so a lane's result never depends on its neighbour.
template <class F>
inline Double2 FixOutOfRange(Double2 x, Double2 inline_value, F f) noexcept {
  const Mask2 inside = Abs(x) <= Splat(kFastTrigMaxArg);  // false for NaN
  if (inside[0] & inside[1]) [[likely]]
    return inline_value;
  for (int i = 0; i < 2; ++i)
    if (!inside[i]) inline_value[i] = f(x[i]);
  return inline_value;
}

}  // namespace fast_math_detail

/// atan(x) per lane, branch-free, exactly odd; see the file contract.
inline Double2 FastAtan(Double2 x) noexcept {
  using namespace fast_math_detail;
  constexpr Double2 kPi2 = Splat(1.57079632679489655800e+00);  // pi/2 rounded
  constexpr Double2 kPi4 = Splat(7.85398163397448278999e-01);  // pi/4 rounded
  constexpr Double2 kTanPi8 = Splat(0.41421356237309503);      // sqrt(2) - 1
  constexpr Double2 kTan3Pi8 = Splat(2.41421356237309503);     // sqrt(2) + 1
  constexpr Double2 kZero = Splat(0.0), kOne = Splat(1.0), kMinusOne = Splat(-1.0);
  const Double2 a = Abs(x);
  // atan(a) = c + atan(t), t = (a - tan c)/(1 + a tan c) with c = 0, pi/4, pi/2 below tan(pi/8),
  // below tan(3 pi/8) and beyond, so that |t| <= tan(pi/8) < 7/16: one division. NaN compares
  // false and takes the c = 0 row; a = inf gives t = -0, c = pi/2.
  const Mask2 big = a > kTan3Pi8;
  const Mask2 mid = a > kTanPi8;
  const Double2 num = Select(big, kMinusOne, Select(mid, a - kOne, a));
  const Double2 den = Select(big, a, Select(mid, a + kOne, kOne));
  const Double2 c = Select(big, kPi2, Select(mid, kPi4, kZero));
  return CopySign(c + AtanKernel(num / den), x);
}

/// sin(x) per lane; inline for |x| <= kFastTrigMaxArg, exactly odd; see the file contract.
inline Double2 FastSin(Double2 x) noexcept {
  using namespace fast_math_detail;
  // sin(-a) = -sin(a): the reduction runs on |x| and the sign is applied last.
  const Double2 v = FromBits(Bits(SinShifted(Abs(x), 0)) ^ (Bits(x) & kSignBit));
  return FixOutOfRange(x, v, [](double y) { return std::sin(y); });
}

/// cos(x) per lane; inline for |x| <= kFastTrigMaxArg, exactly even; see the file contract.
inline Double2 FastCos(Double2 x) noexcept {
  using namespace fast_math_detail;
  return FixOutOfRange(x, SinShifted(Abs(x), 1), [](double y) { return std::cos(y); });
}

/// Scalar forms (lane 0 of the vector version: same cost, same results).
inline double FastAtan(double x) noexcept { return FastAtan(Double2{x, 0.0})[0]; }
inline double FastSin(double x) noexcept { return FastSin(Double2{x, 0.0})[0]; }
inline double FastCos(double x) noexcept { return FastCos(Double2{x, 0.0})[0]; }

}  // namespace scw::plant
