// Magic Formula 5.2 tyre forces with combined slip (forces only), as a pure function.
//
// Contract
//   Inputs (TireInput):
//     fz     vertical load [N], >= 0 (negative is treated as 0: wheel lifted)
//     kappa  longitudinal slip [-], (omega r_e - v_x,tyre) / |v_x,tyre|; > 0 drives, < 0 brakes
//     alpha  slip angle [rad], alpha = -atan(v_y,tyre / |v_x,tyre|) (single-track convention:
//            alpha > 0 gives F_y > 0 to the left, F_y ~ C_alpha alpha for small alpha)
//     lambda_mu_x, lambda_mu_y  friction scaling of this wheel (road, axle and wheel factors,
//            params::GripParams), multiplying the fit's own LMUX/LMUY
//   Output (TireForce): F_x, F_y [N] in the tyre frame (x along the wheel heading, y left).
//
//   Equations (Pacejka 2006, MF5.2 without camber; spec plant-and-track.md §2.3). With
//   dfz = (F_z - FNOMIN)/FNOMIN and the MF-internal slip angle a = -alpha (TYDEX/ISO sign):
//     F_x0 = D_x sin(C_x atan(B_x k - E_x (B_x k - atan(B_x k)))) + S_Vx,  k = kappa + S_Hx
//       D_x = (PDX1 + PDX2 dfz) LMUX l_x F_z,  K_x = F_z (PKX1 + PKX2 dfz) exp(PKX3 dfz) LKX,
//       B_x = K_x / (C_x D_x)
//     F_y0 = D_y sin(C_y atan(B_y a_y - E_y (B_y a_y - atan(B_y a_y)))) + S_Vy, a_y = a + S_Hy
//       D_y = (PDY1 + PDY2 dfz) LMUY l_y F_z,
//       K_y = PKY1 FNOMIN sin(PKY4 atan(F_z / (PKY2 FNOMIN))) LKY,  B_y = K_y / (C_y D_y)
//     F_x = G_xa F_x0,  G_xa = cos(RCX1 atan(B_xa a_s - E_xa(...))) / (same at a_s = RHX1)
//       B_xa = RBX1 cos(atan(RBX2 kappa)),  E_xa = REX1 + REX2 dfz,  a_s = a + RHX1
//     F_y = G_yk F_y0 + S_Vyk,  G_yk = cos(RCY1 atan(B_yk k_s - E_yk(...))) / (same at S_Hyk)
//       B_yk = RBY1 cos(atan(RBY2 (a - RBY3))),  E_yk = REY1 + REY2 dfz,  k_s = kappa + S_Hyk
//       S_Vyk = mu_y F_z (RVY1 + RVY2 dfz) cos(atan(RVY4 a)) sin(RVY5 atan(RVY6 kappa))
//   Fall-off (Mf52Params::falloff = s, 1 by default): beyond the peak of a pure-slip curve (its
//   argument C atan(...) past pi/2) the force is D - s (D - F_MF) instead of F_MF: 0 holds the
//   peak, 2 doubles the loss; up to the peak the curve is the fit's.
//   Friction-ellipse cap: (F_x/D_x)^2 + (F_y/D_y)^2 <= 1 is enforced by scaling both components
//   when the cosine weighting overshoots it (it does by up to 8 % in resultant at high loads with
//   the AV-21 combined-slip coefficients); pure slip without vertical shifts is unaffected.
//   The slip angle enters as the angle (not tan alpha) so that the input range is bounded.
//   Guards: F_z <= 0 -> zero force; friction coefficients are clipped at >= 0 (extreme loads),
//   curvature factors at <= 1, weighting functions at >= 0. The result is finite for every finite
//   input. With zero shift coefficients (PHX*, PVX*, PHY*, PVY*, PEX4, PEY3, RHX1, RBY3, RHY*,
//   RVY*) F_x is odd in kappa and F_y odd in alpha.
//
// atan/sin/cos come from plant/common/fast_math.h (libm accuracy, exactly odd/even, so the
// symmetries above hold bit-exactly). Thread-safe, allocation-free, noexcept.
#pragma once

#include <array>

#include "params/schema/tire_params.h"

namespace scw::plant {

struct TireInput {
  double fz = 0.0;     ///< vertical load [N]
  double kappa = 0.0;  ///< longitudinal slip [-]
  double alpha = 0.0;  ///< slip angle [rad], > 0 -> F_y > 0 (left)
  double lambda_mu_x = 1.0;
  double lambda_mu_y = 1.0;
  /// Factors on the slip stiffnesses K_x, K_y (1 = the fit's own). A friction scaling that acts
  /// on the whole force curve (params::TireSetParams::grip_scaling "curve") passes the wheel's
  /// lambda_mu here as well, so that B = K/(C D) stays and F(slip) is the nominal curve times it.
  double stiffness_x = 1.0;
  double stiffness_y = 1.0;
};

struct TireForce {
  double fx = 0.0;  ///< [N] along the wheel heading
  double fy = 0.0;  ///< [N] to the left of the wheel heading
};

/// Combined-slip MF5.2 forces of one tyre.
TireForce TireForces(const TireInput& in, const params::Mf52Params& p) noexcept;

/// The same for four tyres (tyre i with coefficient set *p[i]): bit-identical to four TireForces
/// calls, and faster, because the four tyres' atan/sin/cos dependency chains overlap.
void TireForces4(const std::array<TireInput, 4>& in,
                 const std::array<const params::Mf52Params*, 4>& p,
                 std::array<TireForce, 4>* out) noexcept;

/// The coefficient sets of TireForces4's four tyres, laid out for its vector evaluation (one
/// array of four lanes per coefficient). Made once by whoever evaluates the same four sets at
/// every step (plant::Vehicle); the values are copies, so the sets need not outlive it.
class TireSet4 {
 public:
  TireSet4() = default;
  explicit TireSet4(const std::array<const params::Mf52Params*, 4>& p) noexcept;
  /// Coefficient `k` (the k-th double of Mf52Params) of the four tyres.
  const double* lanes(std::size_t k) const noexcept { return lanes_[k]; }

 private:
  static constexpr std::size_t kCoefficients = sizeof(params::Mf52Params) / sizeof(double);
  alignas(32) double lanes_[kCoefficients][4] = {};
};

/// TireForces4 with the coefficient sets of `set`: the same forces bit for bit, without
/// gathering the coefficients from four objects at every call.
void TireForces4(const std::array<TireInput, 4>& in, const TireSet4& set,
                 std::array<TireForce, 4>* out) noexcept;

/// Pure-slip peak friction coefficients D/F_z at load fz (incl. the lambda scalings): the bound
/// |F_x| <= mu_x F_z, |F_y| <= mu_y F_z (without vertical shifts).
struct TirePeakFriction {
  double mu_x = 0.0;
  double mu_y = 0.0;
};
TirePeakFriction PeakFriction(double fz, double lambda_mu_x, double lambda_mu_y,
                              const params::Mf52Params& p) noexcept;

/// Cornering stiffness dF_y/dalpha at alpha = 0, kappa = 0 [N/rad] (positive), and longitudinal
/// slip stiffness dF_x/dkappa at kappa = 0 [N]. Used by the linear single-track comparisons.
double CorneringStiffness(double fz, const params::Mf52Params& p) noexcept;
double SlipStiffness(double fz, const params::Mf52Params& p) noexcept;

}  // namespace scw::plant
