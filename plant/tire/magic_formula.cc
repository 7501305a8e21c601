#include "plant/tire/magic_formula.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "plant/common/fast_math.h"

namespace scw::plant {
namespace {

// Magic Formula core C atan(B x - E (B x - atan(B x))); T = double, or Double2 for two curves at
// once (one per lane).
template <class T>
inline T MfArgument(T b, T c, T e, T x) noexcept {
  const T bx = b * x;
  return c * FastAtan(bx - e * (bx - FastAtan(bx)));
}

inline double Sign(double x) noexcept { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); }

// Cosine weighting of combined slip normalised by its value at the shift (1 when shift = 0);
// `num` is the cosine at slip + shift.
inline double Weight(double num, double b, double c, double e, double shift) noexcept {
  const double den = shift == 0.0 ? 1.0 : FastCos(MfArgument(b, c, e, shift));
  return std::max(0.0, num / std::max(den, 1e-6));
}

// Mf52Params::falloff: beyond the peak (|argument| > pi/2; the argument grows monotonically with
// the slip for E <= 1) sin is replaced by 1 - s (1 - |sin|) with the argument's sign, so that the
// force is D - s (D - F_MF); up to the peak nothing changes.
inline Double2 ScaleLossBeyondPeak(Double2 argument, Double2 sine, double s) noexcept {
  for (int j = 0; j < 2; ++j) {
    if (std::abs(argument[j]) > M_PI / 2.0) {
      const double v = 1.0 - s * (1.0 - std::abs(sine[j]));
      sine[j] = argument[j] > 0.0 ? v : -v;
    }
  }
  return sine;
}

}  // namespace

namespace {

// One tyre's four Magic Formula curves are independent atan -> atan -> sin/cos chains, and their
// latency, not their instruction count, bounds the tyre model. So the evaluation is split: Prepare
// collects each curve's coefficients (scalar algebra), then the curves of all tyres of a call run
// stage by stage as Double2 lanes (pure slip F_x0, F_y0 in one, the combined-slip weights G_xa,
// G_yk in the other; see plant/common/fast_math.h) so that the CPU overlaps the chains, and
// Finish combines the results. The arithmetic is the same whether 1 or 4 tyres share a call.
struct Curves {
  bool loaded = false;  // F_z > 0; otherwise the force is zero
  double fz = 0.0, dfz = 0.0, kappa = 0.0, a = 0.0, lmx = 0.0, lmy = 0.0, mu_y = 0.0, dx = 0.0,
         dy = 0.0, shyk = 0.0;
  // [0]: pure slip (lanes F_x0, F_y0); [1]: combined-slip weights (lanes G_xa, G_yk). Unused
  // curves keep B = 0, which keeps their lanes finite.
  Double2 b[2] = {}, c[2] = {}, e[2] = {}, x[2] = {};
};

Curves Prepare(const TireInput& in, const params::Mf52Params& p) noexcept {
  Curves cv;
  const double fz = cv.fz = in.fz;
  if (!(fz > 0.0)) return cv;  // unloaded: all lanes zero, Finish is not called
  cv.loaded = true;
  const double fz0 = p.fnomin;
  const double dfz = cv.dfz = (fz - fz0) / fz0;
  const double kappa = cv.kappa = in.kappa;
  const double a = cv.a = -in.alpha;  // MF-internal (TYDEX/ISO) slip angle

  // Pure longitudinal slip. With D_x = 0 the curve is unused (B_x = 0 keeps its lane finite).
  const double lmx = cv.lmx = p.lmux * in.lambda_mu_x;
  const double mu_x = std::max(0.0, (p.pdx1 + p.pdx2 * dfz) * lmx);
  const double dx = cv.dx = mu_x * fz;
  const double shx = p.phx1 + p.phx2 * dfz;
  const double kx = kappa + shx;
  cv.c[0][0] = p.pcx1;
  cv.x[0][0] = kx;
  if (dx > 0.0) {
    const double k_x =
        fz * (p.pkx1 + p.pkx2 * dfz) * std::exp(p.pkx3 * dfz) * p.lkx * in.stiffness_x;
    cv.b[0][0] = k_x / (p.pcx1 * dx);
    cv.e[0][0] =
        std::min(1.0, (p.pex1 + p.pex2 * dfz + p.pex3 * dfz * dfz) * (1.0 - p.pex4 * Sign(kx)));
  }

  // Pure lateral slip.
  const double lmy = cv.lmy = p.lmuy * in.lambda_mu_y;
  const double mu_y = cv.mu_y = std::max(0.0, (p.pdy1 + p.pdy2 * dfz) * lmy);
  const double dy = cv.dy = mu_y * fz;
  const double shy = p.phy1 + p.phy2 * dfz;
  const double ay = a + shy;
  cv.c[0][1] = p.pcy1;
  cv.x[0][1] = ay;
  if (dy > 0.0) {
    const double u = fz / (p.pky2 * fz0);
    // sin(2 atan u) = 2u / (1 + u^2): exact, and PKY4 = 2 is the MF5.2 standard value.
    const double shape = p.pky4 == 2.0 ? 2.0 * u / (1.0 + u * u) : FastSin(p.pky4 * FastAtan(u));
    const double k_y = p.pky1 * fz0 * shape * p.lky * in.stiffness_y;
    cv.b[0][1] = k_y / (p.pcy1 * dy);
    cv.e[0][1] = std::min(1.0, (p.pey1 + p.pey2 * dfz) * (1.0 - p.pey3 * Sign(ay)));
  }

  // Combined slip weights (numerators; shifted denominators below). cos(atan(x)) = 1/sqrt(1+x^2).
  const double rbx2k = p.rbx2 * kappa;
  cv.b[1][0] = p.rbx1 / std::sqrt(1.0 + rbx2k * rbx2k);
  cv.c[1][0] = p.rcx1;
  cv.e[1][0] = std::min(1.0, p.rex1 + p.rex2 * dfz);
  cv.x[1][0] = a + p.rhx1;
  const double rby2a = p.rby2 * (a - p.rby3);
  cv.b[1][1] = p.rby1 / std::sqrt(1.0 + rby2a * rby2a);
  cv.c[1][1] = p.rcy1;
  cv.e[1][1] = std::min(1.0, p.rey1 + p.rey2 * dfz);
  const double shyk = cv.shyk = p.rhy1 + p.rhy2 * dfz;
  cv.x[1][1] = kappa + shyk;

  return cv;
}

TireForce Finish(const Curves& cv, Double2 pure_sin, Double2 comb_cos,
                 const params::Mf52Params& p) noexcept {
  const double fz = cv.fz, dfz = cv.dfz, a = cv.a, kappa = cv.kappa;
  const double lmx = cv.lmx, lmy = cv.lmy, mu_y = cv.mu_y, dx = cv.dx, dy = cv.dy;
  double fx0 = fz * (p.pvx1 + p.pvx2 * dfz) * lmx;
  if (dx > 0.0) fx0 += dx * pure_sin[0];
  double fy0 = fz * (p.pvy1 + p.pvy2 * dfz) * lmy;
  if (dy > 0.0) fy0 += dy * pure_sin[1];
  const double gxa = Weight(comb_cos[0], cv.b[1][0], cv.c[1][0], cv.e[1][0], p.rhx1);
  const double gyk = Weight(comb_cos[1], cv.b[1][1], cv.c[1][1], cv.e[1][1], cv.shyk);

  double svyk = 0.0;
  if (p.rvy1 != 0.0 || p.rvy2 != 0.0) {
    const double rvy4a = p.rvy4 * a;
    const double dvyk = mu_y * fz * (p.rvy1 + p.rvy2 * dfz) / std::sqrt(1.0 + rvy4a * rvy4a);
    svyk = dvyk * FastSin(p.rvy5 * FastAtan(p.rvy6 * kappa));
  }
  TireForce f{gxa * fx0, gyk * fy0 + svyk};
  // Friction-ellipse cap: the cosine weighting does not bound the resultant (the AV-21 combined
  // coefficients overshoot by up to 8 % at high load); project back onto the ellipse of the
  // pure-slip peaks. Inactive in pure slip without vertical shifts.
  if (dx > 0.0 && dy > 0.0) {
    const double ex = f.fx / dx, ey = f.fy / dy;
    const double r2 = ex * ex + ey * ey;
    if (r2 > 1.0) {
      const double s = 1.0 / std::sqrt(r2);
      f.fx *= s;
      f.fy *= s;
    }
  }
  return f;
}

template <std::size_t N>
void EvaluateTires(const TireInput* in, const params::Mf52Params* const* p,
                   TireForce* out) noexcept {
  Curves cv[N];
  for (std::size_t i = 0; i < N; ++i) cv[i] = Prepare(in[i], *p[i]);
  // Stage by stage over all curves (see Curves): C atan(B x - E (B x - atan(B x))), sin/cos.
  Double2 bx[N][2], arg[N][2];
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = 0; j < 2; ++j) bx[i][j] = cv[i].b[j] * cv[i].x[j];
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = 0; j < 2; ++j) arg[i][j] = FastAtan(bx[i][j]);
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = 0; j < 2; ++j)
      arg[i][j] = cv[i].c[j] * FastAtan(bx[i][j] - cv[i].e[j] * (bx[i][j] - arg[i][j]));
  Double2 pure_arg[N];  // kept for the fall-off beyond the peak
  for (std::size_t i = 0; i < N; ++i) pure_arg[i] = arg[i][0];
  for (std::size_t i = 0; i < N; ++i) {
    arg[i][0] = FastSin(arg[i][0]);
    arg[i][1] = FastCos(arg[i][1]);
  }
  for (std::size_t i = 0; i < N; ++i)
    if (p[i]->falloff != 1.0)
      arg[i][0] = ScaleLossBeyondPeak(pure_arg[i], arg[i][0], p[i]->falloff);
  for (std::size_t i = 0; i < N; ++i)
    out[i] = cv[i].loaded ? Finish(cv[i], arg[i][0], arg[i][1], *p[i]) : TireForce{};
}

}  // namespace

TireForce TireForces(const TireInput& in, const params::Mf52Params& p) noexcept {
  const params::Mf52Params* pp = &p;
  TireForce f;
  EvaluateTires<1>(&in, &pp, &f);
  return f;
}

void TireForces4(const std::array<TireInput, 4>& in,
                 const std::array<const params::Mf52Params*, 4>& p,
                 std::array<TireForce, 4>* out) noexcept {
  EvaluateTires<4>(in.data(), p.data(), out->data());
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
