// MF5.2 invariants: symmetry, peak = mu Fz, combined slip inside the friction ellipse, finiteness.
#include "plant/tire/magic_formula.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "params/schema/vehicle_params.h"

namespace scw::plant {
namespace {

std::vector<params::Mf52Params> SymmetricSets() {
  const params::VehicleParams p;
  return {p.tires.front, p.tires.rear};
}

// The AV-21 fit has ply-steer/conicity shifts: used for finiteness only.
params::Mf52Params ShiftedSet() {
  params::Mf52Params t;
  t.fnomin = 3114;
  t.phx1 = -0.00058;
  t.phx2 = 0.00079;
  t.phy1 = 0.0039;
  t.phy2 = -0.00253;
  t.pvy1 = -0.01038;
  t.pvy2 = -0.1;
  t.pey3 = 0.26886;
  t.rhx1 = 0.00211;
  t.rby3 = -0.01179;
  t.rhy1 = 0.00667;
  t.rhy2 = 0.00207;
  t.rvy1 = 0.0426;
  t.rvy2 = 0.03077;
  t.rvy4 = 100;
  t.rvy5 = 2.2;
  t.rvy6 = 25;
  t.pex4 = 0.3;
  return t;
}

const std::vector<double> kLoads = {200.0, 1500.0, 3000.0, 6000.0, 9000.0};
const std::vector<double> kSlips = {0.001, 0.01, 0.03, 0.06, 0.1, 0.2, 0.5, 1.0};
const std::vector<double> kAngles = {0.001, 0.01, 0.03, 0.06, 0.1, 0.2, 0.5, 1.2};

TEST(MagicFormula, LateralForceIsOddInSlipAngle) {
  for (const auto& t : SymmetricSets())
    for (double fz : kLoads)
      for (double k : {0.0, 0.05, -0.1})
        for (double a : kAngles) {
          const TireForce p = TireForces({fz, k, a}, t);
          const TireForce n = TireForces({fz, k, -a}, t);
          EXPECT_DOUBLE_EQ(p.fy, -n.fy) << fz << " " << k << " " << a;
          EXPECT_DOUBLE_EQ(p.fx, n.fx);
          EXPECT_GT(p.fy, 0.0) << "alpha > 0 must push left";
        }
}

TEST(MagicFormula, LongitudinalForceIsOddInSlip) {
  for (const auto& t : SymmetricSets())
    for (double fz : kLoads)
      for (double a : {0.0, 0.05, -0.1})
        for (double k : kSlips) {
          const TireForce p = TireForces({fz, k, a}, t);
          const TireForce n = TireForces({fz, -k, a}, t);
          EXPECT_DOUBLE_EQ(p.fx, -n.fx);
          EXPECT_DOUBLE_EQ(p.fy, n.fy);
          EXPECT_GT(p.fx, 0.0) << "kappa > 0 must drive";
        }
}

// The pure-slip force peak equals mu * Fz (D), with and without friction scaling.
TEST(MagicFormula, PeakEqualsMuTimesLoad) {
  for (const auto& t : SymmetricSets())
    for (double fz : kLoads)
      for (double lambda : {1.0, 0.8, 0.5}) {
        double fx_max = 0.0, fy_max = 0.0;
        for (int i = 1; i <= 4000; ++i) {
          const double s = i * 2.5e-4;  // up to 1.0
          fx_max = std::max(fx_max, TireForces({fz, s, 0.0, lambda, lambda}, t).fx);
          fy_max = std::max(fy_max, TireForces({fz, 0.0, s, lambda, lambda}, t).fy);
        }
        const TirePeakFriction mu = PeakFriction(fz, lambda, lambda, t);
        EXPECT_NEAR(fx_max, mu.mu_x * fz, 1e-3 * mu.mu_x * fz) << fz << " " << lambda;
        EXPECT_NEAR(fy_max, mu.mu_y * fz, 1e-3 * mu.mu_y * fz) << fz << " " << lambda;
      }
}

TEST(MagicFormula, GripScalingScalesThePeak) {
  const params::Mf52Params t;
  const auto base = PeakFriction(3000, 1.0, 1.0, t);
  const auto low = PeakFriction(3000, 1.0, 0.8, t);
  EXPECT_DOUBLE_EQ(low.mu_y, 0.8 * base.mu_y);
  EXPECT_DOUBLE_EQ(low.mu_x, base.mu_x);
}

// A friction scaling on the whole curve (the same factor on the friction coefficient and the slip
// stiffness, params::TireSetParams::grip_scaling "curve") gives the nominal force times the factor
// at every slip, pure and combined; on the coefficient alone (peak) the slope at zero stays and
// the force at a small slip angle is nearly the nominal one.
TEST(MagicFormula, StiffnessScalingScalesTheWholeCurve) {
  const double f = 0.8;
  for (const auto& t : SymmetricSets())
    for (double fz : kLoads)
      for (double a : kAngles)
        for (double k : {0.0, 0.03, -0.1}) {
          const TireForce nominal = TireForces({fz, k, a, 1.0, 1.0}, t);
          TireInput in{fz, k, a, 1.0, f};
          in.stiffness_y = f;
          const TireForce curve = TireForces(in, t);
          EXPECT_NEAR(curve.fy, f * nominal.fy, 1e-9 * fz) << fz << " " << a << " " << k;
          EXPECT_NEAR(curve.fx, nominal.fx, 1e-9 * fz) << fz << " " << a << " " << k;
          TireInput inx{fz, k, a, f, 1.0};
          inx.stiffness_x = f;
          const TireForce curve_x = TireForces(inx, t);
          EXPECT_NEAR(curve_x.fx, f * nominal.fx, 1e-9 * fz) << fz << " " << a << " " << k;
        }
  const params::Mf52Params t;
  const double a = 0.002, fz = t.fnomin;
  const double peak_only = TireForces({fz, 0.0, a, 1.0, f}, t).fy;
  const double nominal = TireForces({fz, 0.0, a, 1.0, 1.0}, t).fy;
  EXPECT_NEAR(peak_only / nominal, 1.0, 0.01);
  // Factors of exactly 1 are the unscaled tyre bit for bit.
  TireInput one{fz, 0.05, 0.04, 0.9, 0.8};
  one.stiffness_x = one.stiffness_y = 1.0;
  EXPECT_EQ(TireForces(one, t).fy, TireForces({fz, 0.05, 0.04, 0.9, 0.8}, t).fy);
  EXPECT_EQ(TireForces(one, t).fx, TireForces({fz, 0.05, 0.04, 0.9, 0.8}, t).fx);
}

TEST(MagicFormula, CombinedSlipStaysInsideFrictionEllipse) {
  for (const auto& t : SymmetricSets())
    for (double fz : kLoads) {
      const TirePeakFriction mu = PeakFriction(fz, 1.0, 1.0, t);
      for (double k = -1.0; k <= 1.0; k += 0.01)
        for (double a = -0.6; a <= 0.6; a += 0.005) {
          const TireForce f = TireForces({fz, k, a}, t);
          const double ex = f.fx / (mu.mu_x * fz), ey = f.fy / (mu.mu_y * fz);
          ASSERT_LE(ex * ex + ey * ey, 1.0 + 1e-9)
              << "fz " << fz << " kappa " << k << " alpha " << a;
        }
    }
}

TEST(MagicFormula, FiniteForEveryInputIncludingZeroLoad) {
  auto sets = SymmetricSets();
  sets.push_back(ShiftedSet());
  const double big = 1e6;
  for (const auto& t : sets)
    for (double fz : {-100.0, 0.0, 1e-9, 1.0, 3000.0, 40000.0, big})
      for (double k : {-big, -1.5, -1.0, -1e-12, 0.0, 1e-12, 0.3, 1.5, big})
        for (double a : {-1.5707963, -0.7, -1e-12, 0.0, 1e-12, 0.4, 1.5707963, 10.0})
          for (double lambda : {0.05, 1.0, 2.0}) {
            const TireForce f = TireForces({fz, k, a, lambda, lambda}, t);
            ASSERT_TRUE(std::isfinite(f.fx) && std::isfinite(f.fy))
                << fz << " " << k << " " << a << " " << lambda;
            if (fz <= 0.0) {
              EXPECT_EQ(f.fx, 0.0);
              EXPECT_EQ(f.fy, 0.0);
            }
          }
}

TEST(MagicFormula, FourTyreCallIsBitIdenticalToSingleCalls) {
  const params::VehicleParams vp;
  const params::Mf52Params shifted = ShiftedSet();
  params::Mf52Params rear_holding = vp.tires.rear;  // with a fall-off beyond the peak
  rear_holding.falloff = 0.3;
  const std::array<const params::Mf52Params*, 4> sets = {&vp.tires.front, &shifted, &vp.tires.rear,
                                                         &rear_holding};
  for (double k : {-1.0, -0.05, 0.0, 0.02, 0.3})
    for (double a : {-0.5, -0.01, 0.0, 0.03, 0.2}) {
      // Different loads (one unloaded), slips and grip per tyre, as on the car.
      const std::array<TireInput, 4> in = {
          TireInput{3500.0, k, a, 1.0, 0.9}, TireInput{0.0, -k, a, 1.0, 1.0},
          TireInput{5200.0, 0.5 * k, -a, 0.8, 1.1}, TireInput{900.0, k, 2.0 * a, 1.2, 1.0}};
      std::array<TireForce, 4> out;
      TireForces4(in, sets, &out);
      for (std::size_t i = 0; i < 4; ++i) {
        const TireForce f = TireForces(in[i], *sets[i]);
        EXPECT_EQ(out[i].fx, f.fx) << i << " " << k << " " << a;
        EXPECT_EQ(out[i].fy, f.fy) << i << " " << k << " " << a;
      }
    }
}

TEST(MagicFormula, FalloffActsOnlyBeyondThePeakAndKeepsTheSymmetry) {
  const params::VehicleParams vp;
  const params::Mf52Params& fit = vp.tires.rear;
  for (double fz : kLoads) {
    const double dy = PeakFriction(fz, 1.0, 1.0, fit).mu_y * fz;
    double a_peak = 0.0, peak = 0.0;  // the fit's peak, scanned at 1 mrad
    for (int i = 1; i <= 1200; ++i)
      if (TireForces({fz, 0.0, 0.001 * i, 1.0, 1.0}, fit).fy > peak)
        peak = TireForces({fz, 0.0, 0.001 * i, 1.0, 1.0}, fit).fy, a_peak = 0.001 * i;
    for (double s : {0.0, 0.4, 1.7}) {
      params::Mf52Params t = fit;
      t.falloff = s;
      double best = 0.0;
      for (int i = 1; i <= 1200; ++i) {
        const double a = 0.001 * i;
        const double f = TireForces({fz, 0.0, a, 1.0, 1.0}, t).fy;
        const double g = TireForces({fz, 0.0, a, 1.0, 1.0}, fit).fy;
        EXPECT_EQ(TireForces({fz, 0.0, -a, 1.0, 1.0}, t).fy, -f);  // still odd
        if (a < a_peak - 0.001) {
          EXPECT_EQ(f, g) << s << " " << fz << " " << a;
        } else if (a > a_peak + 0.001) {
          EXPECT_NEAR(f, dy - s * (dy - g), 1e-9 * dy) << s << " " << fz << " " << a;
        }
        if (s == 0.0) {
          EXPECT_GE(f, best * (1.0 - 1e-12)) << fz << " " << a;  // holds its peak
        }
        best = std::max(best, f);
      }
      EXPECT_NEAR(best, peak, 1e-5 * dy) << s << " " << fz;  // peak on a 1 mrad grid
    }
  }
}

TEST(MagicFormula, StiffnessesMatchTheSlopeAtZero) {
  for (const auto& t : SymmetricSets())
    for (double fz : kLoads) {
      const double d = 1e-7;
      const double cy = TireForces({fz, 0.0, d}, t).fy / d;
      const double cx = TireForces({fz, d, 0.0}, t).fx / d;
      EXPECT_NEAR(cy, CorneringStiffness(fz, t), 1e-4 * cy);
      EXPECT_NEAR(cx, SlipStiffness(fz, t), 1e-4 * cx);
    }
}

}  // namespace
}  // namespace scw::plant
