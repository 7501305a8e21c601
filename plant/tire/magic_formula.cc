#include "plant/tire/magic_formula.h"

#include <algorithm>
#include <cmath>

namespace scw::plant {
namespace {

// sin/cos-type Magic Formula core: C atan(B x - E (B x - atan(B x))).
inline double MfArgument(double b, double c, double e, double x) noexcept {
  const double bx = b * x;
  return c * std::atan(bx - e * (bx - std::atan(bx)));
}

inline double Sign(double x) noexcept { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); }

// Cosine weighting of combined slip, normalised by its value at the shift (1 when shift = 0).
inline double Weight(double b, double c, double e, double slip, double shift) noexcept {
  const double num = std::cos(MfArgument(b, c, e, slip + shift));
  const double den = shift == 0.0 ? 1.0 : std::cos(MfArgument(b, c, e, shift));
  return std::max(0.0, num / std::max(den, 1e-6));
}

}  // namespace

TireForce TireForces(const TireInput& in, const params::Mf52Params& p) noexcept {
  const double fz = in.fz;
  if (!(fz > 0.0)) return {};
  const double fz0 = p.fnomin;
  const double dfz = (fz - fz0) / fz0;
  const double kappa = in.kappa;
  const double a = -in.alpha;  // MF-internal (TYDEX/ISO) slip angle

  // Pure longitudinal slip.
  const double lmx = p.lmux * in.lambda_mu_x;
  const double mu_x = std::max(0.0, (p.pdx1 + p.pdx2 * dfz) * lmx);
  const double dx = mu_x * fz;
  const double shx = p.phx1 + p.phx2 * dfz;
  const double kx = kappa + shx;
  double fx0 = fz * (p.pvx1 + p.pvx2 * dfz) * lmx;
  if (dx > 0.0) {
    const double k_x = fz * (p.pkx1 + p.pkx2 * dfz) * std::exp(p.pkx3 * dfz) * p.lkx;
    const double bx = k_x / (p.pcx1 * dx);
    const double ex =
        std::min(1.0, (p.pex1 + p.pex2 * dfz + p.pex3 * dfz * dfz) * (1.0 - p.pex4 * Sign(kx)));
    fx0 += dx * std::sin(MfArgument(bx, p.pcx1, ex, kx));
  }

  // Pure lateral slip.
  const double lmy = p.lmuy * in.lambda_mu_y;
  const double mu_y = std::max(0.0, (p.pdy1 + p.pdy2 * dfz) * lmy);
  const double dy = mu_y * fz;
  const double shy = p.phy1 + p.phy2 * dfz;
  const double ay = a + shy;
  double fy0 = fz * (p.pvy1 + p.pvy2 * dfz) * lmy;
  if (dy > 0.0) {
    const double u = fz / (p.pky2 * fz0);
    // sin(2 atan u) = 2u / (1 + u^2): exact, and PKY4 = 2 is the MF5.2 standard value.
    const double shape = p.pky4 == 2.0 ? 2.0 * u / (1.0 + u * u) : std::sin(p.pky4 * std::atan(u));
    const double k_y = p.pky1 * fz0 * shape * p.lky;
    const double by = k_y / (p.pcy1 * dy);
    const double ey = std::min(1.0, (p.pey1 + p.pey2 * dfz) * (1.0 - p.pey3 * Sign(ay)));
    fy0 += dy * std::sin(MfArgument(by, p.pcy1, ey, ay));
  }

  // Combined slip. cos(atan(x)) = 1/sqrt(1 + x^2).
  const double rbx2k = p.rbx2 * kappa;
  const double bxa = p.rbx1 / std::sqrt(1.0 + rbx2k * rbx2k);
  const double exa = std::min(1.0, p.rex1 + p.rex2 * dfz);
  const double gxa = Weight(bxa, p.rcx1, exa, a, p.rhx1);

  const double rby2a = p.rby2 * (a - p.rby3);
  const double byk = p.rby1 / std::sqrt(1.0 + rby2a * rby2a);
  const double eyk = std::min(1.0, p.rey1 + p.rey2 * dfz);
  const double shyk = p.rhy1 + p.rhy2 * dfz;
  const double gyk = Weight(byk, p.rcy1, eyk, kappa, shyk);

  double svyk = 0.0;
  if (p.rvy1 != 0.0 || p.rvy2 != 0.0) {
    const double rvy4a = p.rvy4 * a;
    const double dvyk = mu_y * fz * (p.rvy1 + p.rvy2 * dfz) / std::sqrt(1.0 + rvy4a * rvy4a);
    svyk = dvyk * std::sin(p.rvy5 * std::atan(p.rvy6 * kappa));
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
