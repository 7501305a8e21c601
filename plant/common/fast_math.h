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

#include <cmath>
#include <cstdint>

namespace scw::plant {

/// Two doubles processed together (one SSE2/NEON register).
using Double2 = double __attribute__((vector_size(16)));
/// Four doubles processed together (one AVX register). The functions below accept it as well;
/// code that uses it must be compiled for AVX (a function with __attribute__((target("avx2"))),
/// chosen at run time): the functions are always inlined, so they take the caller's instruction
/// set. Each lane's result is the same bit for bit at either width.
using Double4 = double __attribute__((vector_size(32)));

/// Largest |x| handled inline by FastSin/FastCos; beyond it they call std::sin/std::cos.
inline constexpr double kFastTrigMaxArg = 1.0e5;

#define SCW_FAST_MATH_INLINE inline __attribute__((always_inline))

// The Double4 forms are only ever inlined into AVX code, so the ABI of passing a 32-byte vector
// to a non-AVX function (what -Wpsabi warns about) never arises.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

namespace fast_math_detail {

// Per-lane all-ones/all-zeros masks, as produced by vector comparisons.
using Mask2 = std::int64_t __attribute__((vector_size(16)));
using Mask4 = std::int64_t __attribute__((vector_size(32)));
template <class V>
using MaskOf = decltype(V{} < V{});
template <class V>
inline constexpr int kLanes = static_cast<int>(sizeof(V) / sizeof(double));

template <class V>
SCW_FAST_MATH_INLINE MaskOf<V> Bits(V v) noexcept {
  return __builtin_bit_cast(MaskOf<V>, v);
}
template <class M>
struct VecOfMask;
template <>
struct VecOfMask<Mask2> {
  using type = Double2;
};
template <>
struct VecOfMask<Mask4> {
  using type = Double4;
};
template <class M>
SCW_FAST_MATH_INLINE typename VecOfMask<M>::type FromBits(M m) noexcept {
  return __builtin_bit_cast(typename VecOfMask<M>::type, m);
}
template <class M>
constexpr SCW_FAST_MATH_INLINE M MaskSplat(std::int64_t v) noexcept {
  if constexpr (sizeof(M) == sizeof(Mask2))
    return M{v, v};
  else
    return M{v, v, v, v};
}
template <class V>
constexpr SCW_FAST_MATH_INLINE MaskOf<V> SignBit() noexcept {
  return MaskSplat<MaskOf<V>>(INT64_MIN);
}

// Constants as whole registers: a scalar operand would be re-broadcast at every use.
template <class V = Double2>
constexpr SCW_FAST_MATH_INLINE V Splat(double v) noexcept {
  if constexpr (sizeof(V) == sizeof(Double2))
    return V{v, v};
  else
    return V{v, v, v, v};
}

// m ? a : b per lane, without a branch.
template <class V>
SCW_FAST_MATH_INLINE V Select(MaskOf<V> m, V a, V b) noexcept {
  return FromBits((m & Bits(a)) | (~m & Bits(b)));
}
template <class V>
SCW_FAST_MATH_INLINE V Abs(V v) noexcept {
  return FromBits(Bits(v) & ~SignBit<V>());
}
// |magnitude| with the sign bit of `sign`.
template <class V>
SCW_FAST_MATH_INLINE V CopySign(V magnitude, V sign) noexcept {
  return FromBits((Bits(magnitude) & ~SignBit<V>()) | (Bits(sign) & SignBit<V>()));
}

// atan(t) for |t| <= 7/16 (fdlibm s_atan.c, error < 1 ulp): t - t (z S_odd(z^2) + z^2 S_even(z^2))
// with z = t^2; the even/odd split halves the dependency chain of a plain Horner scheme.
template <class V>
SCW_FAST_MATH_INLINE V AtanKernel(V t) noexcept {
  constexpr V kAt0 = Splat<V>(3.33333333333329318027e-01),
              kAt1 = Splat<V>(-1.99999999998764832476e-01),
              kAt2 = Splat<V>(1.42857142725034663711e-01),
              kAt3 = Splat<V>(-1.11111104054623557880e-01),
              kAt4 = Splat<V>(9.09088713343650656196e-02),
              kAt5 = Splat<V>(-7.69187620504482999495e-02),
              kAt6 = Splat<V>(6.66107313738753120669e-02),
              kAt7 = Splat<V>(-5.83357013379057348645e-02),
              kAt8 = Splat<V>(4.97687799461593236017e-02),
              kAt9 = Splat<V>(-3.65315727442169155270e-02),
              kAt10 = Splat<V>(1.62858201153657823623e-02);
  const V z = t * t;
  const V w = z * z;
  const V s1 = z * (kAt0 + w * (kAt2 + w * (kAt4 + w * (kAt6 + w * (kAt8 + w * kAt10)))));
  const V s2 = w * (kAt1 + w * (kAt3 + w * (kAt5 + w * (kAt7 + w * kAt9))));
  return t - t * (s1 + s2);
}

// sin(r), cos(r) for |r| <= pi/4 (fdlibm k_sin.c / k_cos.c polynomials; without fdlibm's tail
// correction for cos, which costs latency and buys less than 1e-16 the plant does not need).
template <class V>
SCW_FAST_MATH_INLINE V SinKernel(V r) noexcept {
  constexpr V kS1 = Splat<V>(-1.66666666666666324348e-01),
              kS2 = Splat<V>(8.33333333332248946124e-03),
              kS3 = Splat<V>(-1.98412698298579493134e-04),
              kS4 = Splat<V>(2.75573137070700676789e-06),
              kS5 = Splat<V>(-2.50507602534068634195e-08),
              kS6 = Splat<V>(1.58969099521155010221e-10);
  const V z = r * r;
  const V p = kS2 + z * (kS3 + z * (kS4 + z * (kS5 + z * kS6)));
  return r + r * z * (kS1 + z * p);
}

template <class V>
SCW_FAST_MATH_INLINE V CosKernel(V r) noexcept {
  constexpr V kC1 = Splat<V>(4.16666666666666019037e-02),
              kC2 = Splat<V>(-1.38888888888741095749e-03),
              kC3 = Splat<V>(2.48015872894767294178e-05),
              kC4 = Splat<V>(-2.75573143513906633035e-07),
              kC5 = Splat<V>(2.08757232129817482790e-09),
              kC6 = Splat<V>(-1.13596475577881948265e-11);
  const V z = r * r;
  const V p = z * (kC1 + z * (kC2 + z * (kC3 + z * (kC4 + z * (kC5 + z * kC6)))));
  return Splat<V>(1.0) - (Splat<V>(0.5) * z - z * p);
}

// sin(a + phase pi/2) for 0 <= a <= kFastTrigMaxArg; phase 0 gives sin, phase 1 gives cos (an
// exact quadrant shift, no rounding). With a = k pi/2 + r, |r| <= pi/4, the result is
// +-sin r or +-cos r by (k + phase) mod 4; both kernels run and the lanes pick by mask. Other a
// (huge, inf, NaN) give a meaningless but harmless value (no float -> int conversion, no UB) that
// FixOutOfRange replaces.
template <class V>
SCW_FAST_MATH_INLINE V SinShifted(V a, std::int64_t phase) noexcept {
  using M = MaskOf<V>;
  constexpr V kTwoOverPi = Splat<V>(6.36619772367581382433e-01);
  constexpr V kPio2Hi = Splat<V>(1.57079632673412561417e+00);  // 33 bits: k kPio2Hi exact
  constexpr V kPio2Lo = Splat<V>(6.07710050650619224932e-11);  // pi/2 - kPio2Hi
  // Round to nearest by the 1.5 * 2^52 shift (no libm call); the shifted value's low mantissa
  // bits are k itself, which gives the quadrant without a float -> int conversion.
  constexpr V kShift = Splat<V>(6755399441055744.0);
  const V shifted = a * kTwoOverPi + kShift;
  const V k = shifted - kShift;
  const V r = (a - k * kPio2Hi) - k * kPio2Lo;
  const M q = Bits(shifted) + MaskSplat<M>(phase);
  constexpr M zero = MaskSplat<M>(0), one = MaskSplat<M>(1), two = MaskSplat<M>(2);
  const V v = Select<V>((q & one) != zero, CosKernel(r), SinKernel(r));
  return FromBits(Bits(v) ^ (((q & two) != zero) & SignBit<V>()));
}

// Lanes outside the inline range (or NaN) take f = std::sin/std::cos; the others keep their
// inline value, so a lane's result never depends on its neighbour.
template <class V, class F>
SCW_FAST_MATH_INLINE V FixOutOfRange(V x, V inline_value, F f) noexcept {
  const MaskOf<V> inside = Abs(x) <= Splat<V>(kFastTrigMaxArg);  // false for NaN
  std::int64_t all = -1;
  for (int i = 0; i < kLanes<V>; ++i) all &= inside[i];
  if (all != 0) [[likely]]
    return inline_value;
  for (int i = 0; i < kLanes<V>; ++i)
    if (!inside[i]) inline_value[i] = f(x[i]);
  return inline_value;
}

}  // namespace fast_math_detail

/// atan(x) per lane, branch-free, exactly odd; see the file contract.
template <class V>
SCW_FAST_MATH_INLINE V FastAtan(V x) noexcept {
  using namespace fast_math_detail;
  using M = MaskOf<V>;
  constexpr V kPi2 = Splat<V>(1.57079632679489655800e+00);  // pi/2 rounded
  constexpr V kPi4 = Splat<V>(7.85398163397448278999e-01);  // pi/4 rounded
  constexpr V kTanPi8 = Splat<V>(0.41421356237309503);      // sqrt(2) - 1
  constexpr V kTan3Pi8 = Splat<V>(2.41421356237309503);     // sqrt(2) + 1
  constexpr V kZero = Splat<V>(0.0), kOne = Splat<V>(1.0), kMinusOne = Splat<V>(-1.0);
  const V a = Abs(x);
  // atan(a) = c + atan(t), t = (a - tan c)/(1 + a tan c) with c = 0, pi/4, pi/2 below tan(pi/8),
  // below tan(3 pi/8) and beyond, so that |t| <= tan(pi/8) < 7/16: one division. NaN compares
  // false and takes the c = 0 row; a = inf gives t = -0, c = pi/2.
  const M big = a > kTan3Pi8;
  const M mid = a > kTanPi8;
  const V num = Select<V>(big, kMinusOne, Select<V>(mid, a - kOne, a));
  const V den = Select<V>(big, a, Select<V>(mid, a + kOne, kOne));
  const V c = Select<V>(big, kPi2, Select<V>(mid, kPi4, kZero));
  return CopySign(c + AtanKernel(num / den), x);
}

/// sin(x) per lane; inline for |x| <= kFastTrigMaxArg, exactly odd; see the file contract.
template <class V>
SCW_FAST_MATH_INLINE V FastSin(V x) noexcept {
  using namespace fast_math_detail;
  // sin(-a) = -sin(a): the reduction runs on |x| and the sign is applied last.
  const V v = FromBits(Bits(SinShifted(Abs(x), 0)) ^ (Bits(x) & SignBit<V>()));
  return FixOutOfRange(x, v, [](double y) { return std::sin(y); });
}

/// cos(x) per lane; inline for |x| <= kFastTrigMaxArg, exactly even; see the file contract.
template <class V>
SCW_FAST_MATH_INLINE V FastCos(V x) noexcept {
  using namespace fast_math_detail;
  return FixOutOfRange(x, SinShifted(Abs(x), 1), [](double y) { return std::cos(y); });
}

#pragma GCC diagnostic pop

/// Scalar forms (lane 0 of the vector version: same cost, same results).
inline double FastAtan(double x) noexcept { return FastAtan<Double2>(Double2{x, 0.0})[0]; }
inline double FastSin(double x) noexcept { return FastSin<Double2>(Double2{x, 0.0})[0]; }
inline double FastCos(double x) noexcept { return FastCos<Double2>(Double2{x, 0.0})[0]; }

}  // namespace scw::plant
