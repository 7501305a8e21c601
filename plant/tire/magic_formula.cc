#include "plant/tire/magic_formula.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "plant/common/fast_math.h"

// The Double4 code below is inlined into the AVX2 function only (see plant/common/fast_math.h);
// GCC reports the 32-byte vectors' non-AVX ABI at the end of the file, hence file-wide.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace scw::plant {
namespace {

using fast_math_detail::kLanes;
using fast_math_detail::MaskOf;
using fast_math_detail::Select;
using fast_math_detail::Splat;

// The tyres of a call are evaluated side by side, one per vector lane (structure of arrays): two
// per Double2 on every x86-64 CPU, four per Double4 where the CPU has AVX2 (chosen at run time,
// TireForces4). Every scalar operation of the Magic Formula becomes one vector operation, with
// the same operands in the same order, so each lane's result is bit for bit that of the scalar
// formula at either width. Branches on a tyre's own values (a lifted wheel, D = 0, a clipped
// weight) become lane masks: both sides are computed and the lane takes the one the scalar code
// took. A tyre's four curves (pure slip F_x0, F_y0; combined-slip weights G_xa, G_yk) are
// independent atan -> atan -> sin/cos chains whose latency and count bound the model; they run
// as four vectors of chains side by side (plant/common/fast_math.h).
#define SCW_MF_INLINE SCW_FAST_MATH_INLINE

template <class V>
SCW_MF_INLINE V Max0(V v) noexcept {
  return Select<V>(Splat<V>(0.0) < v, v, Splat<V>(0.0));
}
template <class V>
SCW_MF_INLINE V Min1(V v) noexcept {
  return Select<V>(v < Splat<V>(1.0), v, Splat<V>(1.0));
}
// x > 0 -> 1, x < 0 -> -1, else 0 (NaN -> 0).
template <class V>
SCW_MF_INLINE V Sign(V x) noexcept {
  return Select<V>(x > Splat<V>(0.0), Splat<V>(1.0),
                   Select<V>(x < Splat<V>(0.0), Splat<V>(-1.0), Splat<V>(0.0)));
}
template <class V>
SCW_MF_INLINE V Sqrt(V v) noexcept {
  for (int i = 0; i < kLanes<V>; ++i) v[i] = std::sqrt(v[i]);
  return v;
}
template <class V>
SCW_MF_INLINE V Exp(V v) noexcept {
  for (int i = 0; i < kLanes<V>; ++i) v[i] = std::exp(v[i]);
  return v;
}
template <class V>
SCW_MF_INLINE bool Any(MaskOf<V> m) noexcept {
  std::int64_t any = 0;
  for (int i = 0; i < kLanes<V>; ++i) any |= m[i];
  return any != 0;
}
template <class V>
SCW_MF_INLINE bool All(MaskOf<V> m) noexcept {
  std::int64_t all = -1;
  for (int i = 0; i < kLanes<V>; ++i) all &= m[i];
  return all != 0;
}

// Magic Formula core C atan(B x - E (B x - atan(B x))).
template <class V>
SCW_MF_INLINE V MfArgument(V b, V c, V e, V x) noexcept {
  const V bx = b * x;
  return c * FastAtan(bx - e * (bx - FastAtan(bx)));
}

// Index of a coefficient among the doubles of Mf52Params (TireSet4's row).
inline std::size_t CoefficientIndex(double params::Mf52Params::*f) noexcept {
  static const params::Mf52Params probe{};
  return static_cast<std::size_t>(reinterpret_cast<const char*>(&(probe.*f)) -
                                  reinterpret_cast<const char*>(&probe)) /
         sizeof(double);
}

// The tyres of one vector: their inputs and coefficient sets, lane by lane. The coefficients
// come from four Mf52Params objects (p), or, when `set` is given, from the lanes
// [first, first + lanes) of a TireSet4.
template <class V>
struct Lanes {
  const TireInput* in;
  const params::Mf52Params* const* p;
  const TireSet4* set = nullptr;
  std::size_t first = 0;
  SCW_MF_INLINE V operator()(double params::Mf52Params::*f) const noexcept {
    V v;
    if (set != nullptr) {
      std::memcpy(&v, set->lanes(CoefficientIndex(f)) + first, sizeof(V));
    } else {
      for (int i = 0; i < kLanes<V>; ++i) v[i] = p[i]->*f;
    }
    return v;
  }
  SCW_MF_INLINE V operator()(double TireInput::*f) const noexcept {
    V v;
    for (int i = 0; i < kLanes<V>; ++i) v[i] = in[i].*f;
    return v;
  }
};

// One vector of tyres from Prepare to the chains' inputs. Curves: 0 pure slip F_x0, 1 pure slip
// F_y0, 2 weight G_xa, 3 weight G_yk.
template <class V>
struct Curves {
  MaskOf<V> loaded;  // F_z > 0; otherwise the force is zero
  MaskOf<V> has_x;   // D_x > 0 (else the F_x0 curve is unused and keeps B = 0)
  MaskOf<V> has_y;   // D_y > 0
  V fz, dfz, kappa, a, lmx, lmy, mu_y, dx, dy, shyk;
  V b[4], c[4], e[4], x[4];
};

template <class V>
SCW_MF_INLINE void Prepare(const Lanes<V>& P, Curves<V>* cv) noexcept {
  using params::Mf52Params;
  const V zero = Splat<V>(0.0), one = Splat<V>(1.0);
  const V fz = cv->fz = P(&TireInput::fz);
  cv->loaded = fz > zero;
  const V fz0 = P(&Mf52Params::fnomin);
  const V dfz = cv->dfz = (fz - fz0) / fz0;
  const V kappa = cv->kappa = P(&TireInput::kappa);
  const V a = cv->a = -P(&TireInput::alpha);  // MF-internal (TYDEX/ISO) slip angle

  // Pure longitudinal slip. With D_x = 0 the curve is unused (B_x = 0 keeps its lane finite).
  const V lmx = cv->lmx = P(&Mf52Params::lmux) * P(&TireInput::lambda_mu_x);
  const V mu_x = Max0((P(&Mf52Params::pdx1) + P(&Mf52Params::pdx2) * dfz) * lmx);
  const V dx = cv->dx = mu_x * fz;
  const V shx = P(&Mf52Params::phx1) + P(&Mf52Params::phx2) * dfz;
  const V kx = kappa + shx;
  cv->c[0] = P(&Mf52Params::pcx1);
  cv->x[0] = kx;
  cv->has_x = dx > zero;
  const V k_x = fz * (P(&Mf52Params::pkx1) + P(&Mf52Params::pkx2) * dfz) *
                Exp(P(&Mf52Params::pkx3) * dfz) * P(&Mf52Params::lkx) * P(&TireInput::stiffness_x);
  cv->b[0] = Select<V>(cv->has_x, k_x / (P(&Mf52Params::pcx1) * dx), zero);
  cv->e[0] = Select<V>(
      cv->has_x,
      Min1((P(&Mf52Params::pex1) + P(&Mf52Params::pex2) * dfz + P(&Mf52Params::pex3) * dfz * dfz) *
           (one - P(&Mf52Params::pex4) * Sign(kx))),
      zero);

  // Pure lateral slip.
  const V lmy = cv->lmy = P(&Mf52Params::lmuy) * P(&TireInput::lambda_mu_y);
  const V mu_y = cv->mu_y = Max0((P(&Mf52Params::pdy1) + P(&Mf52Params::pdy2) * dfz) * lmy);
  const V dy = cv->dy = mu_y * fz;
  const V shy = P(&Mf52Params::phy1) + P(&Mf52Params::phy2) * dfz;
  const V ay = a + shy;
  cv->c[1] = P(&Mf52Params::pcy1);
  cv->x[1] = ay;
  cv->has_y = dy > zero;
  const V u = fz / (P(&Mf52Params::pky2) * fz0);
  // sin(2 atan u) = 2u / (1 + u^2): exact, and PKY4 = 2 is the MF5.2 standard value.
  const V pky4 = P(&Mf52Params::pky4);
  const MaskOf<V> standard = pky4 == Splat<V>(2.0);
  V shape = Splat<V>(2.0) * u / (one + u * u);
  if (!All<V>(standard)) shape = Select<V>(standard, shape, FastSin(pky4 * FastAtan(u)));
  const V k_y =
      P(&Mf52Params::pky1) * fz0 * shape * P(&Mf52Params::lky) * P(&TireInput::stiffness_y);
  cv->b[1] = Select<V>(cv->has_y, k_y / (P(&Mf52Params::pcy1) * dy), zero);
  cv->e[1] = Select<V>(cv->has_y,
                       Min1((P(&Mf52Params::pey1) + P(&Mf52Params::pey2) * dfz) *
                            (one - P(&Mf52Params::pey3) * Sign(ay))),
                       zero);

  // Combined slip weights (numerators; shifted denominators in Finish). cos(atan(x)) =
  // 1/sqrt(1+x^2).
  const V rbx2k = P(&Mf52Params::rbx2) * kappa;
  cv->b[2] = P(&Mf52Params::rbx1) / Sqrt(one + rbx2k * rbx2k);
  cv->c[2] = P(&Mf52Params::rcx1);
  cv->e[2] = Min1(P(&Mf52Params::rex1) + P(&Mf52Params::rex2) * dfz);
  cv->x[2] = a + P(&Mf52Params::rhx1);
  const V rby2a = P(&Mf52Params::rby2) * (a - P(&Mf52Params::rby3));
  cv->b[3] = P(&Mf52Params::rby1) / Sqrt(one + rby2a * rby2a);
  cv->c[3] = P(&Mf52Params::rcy1);
  cv->e[3] = Min1(P(&Mf52Params::rey1) + P(&Mf52Params::rey2) * dfz);
  const V shyk = cv->shyk = P(&Mf52Params::rhy1) + P(&Mf52Params::rhy2) * dfz;
  cv->x[3] = kappa + shyk;
}

// Mf52Params::falloff: beyond the peak (|argument| > pi/2; the argument grows monotonically with
// the slip for E <= 1) sin is replaced by 1 - s (1 - |sin|) with the argument's sign, so that the
// force is D - s (D - F_MF); up to the peak nothing changes. Lanes with s = 1 keep their sine.
template <class V>
SCW_MF_INLINE V ScaleLossBeyondPeak(V argument, V sine, V s) noexcept {
  using fast_math_detail::Abs;
  const MaskOf<V> apply = (s != Splat<V>(1.0)) & (Abs(argument) > Splat<V>(M_PI / 2.0));
  const V v = Splat<V>(1.0) - s * (Splat<V>(1.0) - Abs(sine));
  return Select<V>(apply, Select<V>(argument > Splat<V>(0.0), v, -v), sine);
}

// Cosine weighting of combined slip normalised by its value at the shift (1 when shift = 0);
// `num` is the cosine at slip + shift.
template <class V>
SCW_MF_INLINE V Weight(V num, V b, V c, V e, V shift) noexcept {
  const MaskOf<V> unshifted = shift == Splat<V>(0.0);
  if (All<V>(unshifted)) return Max0(num);  // num / max(1, 1e-6) is num exactly
  const V den = Select<V>(unshifted, Splat<V>(1.0), FastCos(MfArgument(b, c, e, shift)));
  return Max0(num / Select<V>(den < Splat<V>(1e-6), Splat<V>(1e-6), den));
}

template <class V>
SCW_MF_INLINE void Finish(const Curves<V>& cv, V sin_x, V sin_y, V cos_x, V cos_y,
                          const Lanes<V>& P, TireForce* out) noexcept {
  using params::Mf52Params;
  const V zero = Splat<V>(0.0), one = Splat<V>(1.0);
  const V fz = cv.fz, dfz = cv.dfz, dx = cv.dx, dy = cv.dy;
  V fx0 = fz * (P(&Mf52Params::pvx1) + P(&Mf52Params::pvx2) * dfz) * cv.lmx;
  fx0 = Select<V>(cv.has_x, fx0 + dx * sin_x, fx0);
  V fy0 = fz * (P(&Mf52Params::pvy1) + P(&Mf52Params::pvy2) * dfz) * cv.lmy;
  fy0 = Select<V>(cv.has_y, fy0 + dy * sin_y, fy0);
  const V gxa = Weight(cos_x, cv.b[2], cv.c[2], cv.e[2], P(&Mf52Params::rhx1));
  const V gyk = Weight(cos_y, cv.b[3], cv.c[3], cv.e[3], cv.shyk);

  V svyk = zero;
  const V rvy1 = P(&Mf52Params::rvy1), rvy2 = P(&Mf52Params::rvy2);
  const MaskOf<V> vertical = (rvy1 != zero) | (rvy2 != zero);
  if (Any<V>(vertical)) {
    const V rvy4a = P(&Mf52Params::rvy4) * cv.a;
    const V dvyk = cv.mu_y * fz * (rvy1 + rvy2 * dfz) / Sqrt(one + rvy4a * rvy4a);
    svyk = Select<V>(
        vertical, dvyk * FastSin(P(&Mf52Params::rvy5) * FastAtan(P(&Mf52Params::rvy6) * cv.kappa)),
        zero);
  }
  V fx = gxa * fx0, fy = gyk * fy0 + svyk;
  // Friction-ellipse cap: the cosine weighting does not bound the resultant (the AV-21 combined
  // coefficients overshoot by up to 8 % at high load); project back onto the ellipse of the
  // pure-slip peaks. Inactive in pure slip without vertical shifts.
  const V ex = fx / dx, ey = fy / dy;
  const V r2 = ex * ex + ey * ey;
  const MaskOf<V> cap = cv.has_x & cv.has_y & (r2 > one);
  if (Any<V>(cap)) {
    const V s = one / Sqrt(r2);
    fx = Select<V>(cap, fx * s, fx);
    fy = Select<V>(cap, fy * s, fy);
  }
  fx = Select<V>(cv.loaded, fx, zero);
  fy = Select<V>(cv.loaded, fy, zero);
  for (int i = 0; i < kLanes<V>; ++i) out[i] = {fx[i], fy[i]};
}

// kGroups vectors of tyres (kGroups * lanes tyres): tyre i with inputs in[i] and coefficients
// *p[i].
template <class V, std::size_t kGroups>
SCW_MF_INLINE void EvaluateTires(const TireInput* in, const params::Mf52Params* const* p,
                                 const TireSet4* set, TireForce* out) noexcept {
  constexpr std::size_t kL = static_cast<std::size_t>(kLanes<V>);
  Lanes<V> lanes[kGroups];
  Curves<V> cv[kGroups];
  for (std::size_t q = 0; q < kGroups; ++q) {
    lanes[q] = set != nullptr ? Lanes<V>{in + kL * q, nullptr, set, kL * q}
                              : Lanes<V>{in + kL * q, p + kL * q};
    Prepare(lanes[q], &cv[q]);
  }
  // Stage by stage over all chains: C atan(B x - E (B x - atan(B x))), then sin (pure slip) and
  // cos (weights).
  V bx[kGroups][4], arg[kGroups][4];
  for (std::size_t q = 0; q < kGroups; ++q)
    for (std::size_t k = 0; k < 4; ++k) bx[q][k] = cv[q].b[k] * cv[q].x[k];
  for (std::size_t q = 0; q < kGroups; ++q)
    for (std::size_t k = 0; k < 4; ++k) arg[q][k] = FastAtan(bx[q][k]);
  for (std::size_t q = 0; q < kGroups; ++q)
    for (std::size_t k = 0; k < 4; ++k)
      arg[q][k] = cv[q].c[k] * FastAtan(bx[q][k] - cv[q].e[k] * (bx[q][k] - arg[q][k]));
  V val[kGroups][4];
  for (std::size_t q = 0; q < kGroups; ++q) {
    val[q][0] = FastSin(arg[q][0]);
    val[q][1] = FastSin(arg[q][1]);
    val[q][2] = FastCos(arg[q][2]);
    val[q][3] = FastCos(arg[q][3]);
  }
  for (std::size_t q = 0; q < kGroups; ++q) {
    const V s = lanes[q](&params::Mf52Params::falloff);
    if (!All<V>(s == Splat<V>(1.0))) {
      val[q][0] = ScaleLossBeyondPeak(arg[q][0], val[q][0], s);
      val[q][1] = ScaleLossBeyondPeak(arg[q][1], val[q][1], s);
    }
  }
  for (std::size_t q = 0; q < kGroups; ++q)
    Finish(cv[q], val[q][0], val[q][1], val[q][2], val[q][3], lanes[q], out + kL * q);
}

void EvaluateFourSse2(const TireInput* in, const TireSet4& set, TireForce* out) noexcept {
  EvaluateTires<Double2, 2>(in, nullptr, &set, out);
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// The same for AVX2 CPUs, four tyres per Double4: the helpers above are always inlined and so
// compiled for AVX2 here. AVX2 only (no FMA): every operation rounds as in the SSE2 path.
__attribute__((target("avx2"))) void EvaluateFourAvx2(const TireInput* in, const TireSet4& set,
                                                      TireForce* out) noexcept {
  EvaluateTires<Double4, 1>(in, nullptr, &set, out);
}

bool HasAvx2() noexcept {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}
const bool kHasAvx2 = HasAvx2();
#else
constexpr bool kHasAvx2 = false;
void EvaluateFourAvx2(const TireInput* in, const TireSet4& set, TireForce* out) noexcept {
  EvaluateFourSse2(in, set, out);
}
#endif

}  // namespace

TireForce TireForces(const TireInput& in, const params::Mf52Params& p) noexcept {
  // One tyre in both lanes (a lane's result never depends on the other's).
  const TireInput two[2] = {in, in};
  const params::Mf52Params* pp[2] = {&p, &p};
  TireForce f[2];
  EvaluateTires<Double2, 1>(two, pp, nullptr, f);
  return f[0];
}

TireSet4::TireSet4(const std::array<const params::Mf52Params*, 4>& p) noexcept {
  static_assert(sizeof(params::Mf52Params) % sizeof(double) == 0 &&
                    std::is_trivially_copyable_v<params::Mf52Params>,
                "TireSet4 copies Mf52Params as an array of doubles");
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t k = 0; k < kCoefficients; ++k)
      std::memcpy(&lanes_[k][i], reinterpret_cast<const char*>(p[i]) + k * sizeof(double),
                  sizeof(double));
}

void TireForces4(const std::array<TireInput, 4>& in, const TireSet4& set,
                 std::array<TireForce, 4>* out) noexcept {
  if (kHasAvx2)
    EvaluateFourAvx2(in.data(), set, out->data());
  else
    EvaluateFourSse2(in.data(), set, out->data());
}

void TireForces4(const std::array<TireInput, 4>& in,
                 const std::array<const params::Mf52Params*, 4>& p,
                 std::array<TireForce, 4>* out) noexcept {
  TireForces4(in, TireSet4(p), out);
}

TirePeakFriction PeakFriction(double fz, double lambda_mu_x, double lambda_mu_y,
                              const params::Mf52Params& p) noexcept {
  const double dfz = (std::max(fz, 0.0) - p.fnomin) / p.fnomin;
  return {std::max(0.0, (p.pdx1 + p.pdx2 * dfz) * p.lmux * lambda_mu_x),
          std::max(0.0, (p.pdy1 + p.pdy2 * dfz) * p.lmuy * lambda_mu_y)};
}

double CorneringStiffness(double fz, const params::Mf52Params& p) noexcept {
  if (!(fz > 0.0)) return 0.0;
  const double u = fz / (p.pky2 * p.fnomin);
  return -p.pky1 * p.fnomin * std::sin(p.pky4 * std::atan(u)) * p.lky;
}

double SlipStiffness(double fz, const params::Mf52Params& p) noexcept {
  if (!(fz > 0.0)) return 0.0;
  const double dfz = (fz - p.fnomin) / p.fnomin;
  return fz * (p.pkx1 + p.pkx2 * dfz) * std::exp(p.pkx3 * dfz) * p.lkx;
}

}  // namespace scw::plant
