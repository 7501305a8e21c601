// Tyre parameters of the plant: Magic Formula 5.2 force coefficients (one set per axle), slip
// kinematics and relaxation, and the friction scaling that scenarios use ("rear lateral grip -20
// %", mu-split, wet track).
//
// Coefficient names follow the MF5.2 .tir convention (TYDEX/ISO C-axis system: tan(alpha) =
// v_y/v_x of the contact point, so a tyre sliding to the left has alpha > 0 and pushes to the
// right; that is why PKY1 is negative). Camber is zero in the reduced plant, so camber coefficients
// (PDX3, PDY3, PEY4/5, PKY3/5/6/7, PVY3/4, RBX3, RBY4, RVY3) are not part of the schema. Aligning
// moment, overturning and rolling moments, turn slip and inflation pressure are not modelled.
// Equations: ../shared/spec/plant-and-track.md §2.3 (Pacejka, Tire and Vehicle Dynamics, 2006).
//
// Default values (in-class) are the EAV24/25-class front tyre; see VehicleParams for the sets.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "params/schema/field.h"

namespace scw::params {

struct Mf52Params;

/// What bounds a tyre's fall-off (Mf52Params::falloff): the shape factor, PCY1 or PCX1, that
/// admits the smaller fall-off before its sliding force D (1 - falloff (1 - sin(C pi/2))) reaches
/// zero, or the first of them without a force peak with a positive sliding force (C outside
/// (1, 2)), where only a fall-off of 1 is accepted.
struct FalloffBound {
  const char* name = "";
  double c = 0.0;
  bool has_peak = true;
  double limit = 0.0;  ///< feasible: 0 <= falloff < limit
};
inline FalloffBound FalloffBoundOf(const Mf52Params& tire);

/// Magic Formula 5.2 combined-slip force coefficients of one tyre (one axle).
struct Mf52Params {
  double fnomin = 3000.0;  ///< FNOMIN: nominal load [N]
  // Pure longitudinal slip.
  double pcx1 = 1.933;
  double pdx1 = 2.284;
  double pdx2 = -0.32356;
  double pex1 = 0.4743;
  double pex2 = 0.0;
  double pex3 = 0.0;
  double pex4 = 0.0;
  double pkx1 = 48.05;
  double pkx2 = 0.0;
  double pkx3 = 0.4773;
  double phx1 = 0.0;
  double phx2 = 0.0;
  double pvx1 = 0.0;
  double pvx2 = 0.0;
  // Pure lateral slip.
  double pcy1 = 1.531;
  double pdy1 = 1.9156;
  double pdy2 = -0.4091;
  double pey1 = -0.09074;
  double pey2 = 0.0;
  double pey3 = 0.0;
  double pky1 = -37.766;
  double pky2 = 1.6747;
  double pky4 = 2.0;
  double phy1 = 0.0;
  double phy2 = 0.0;
  double pvy1 = 0.0;
  double pvy2 = 0.0;
  // Combined slip (cosine weighting functions).
  double rbx1 = 17.406;
  double rbx2 = 18.243;
  double rcx1 = 0.7119;
  double rex1 = -10.0;
  double rex2 = 0.0;
  double rhx1 = 0.0;
  double rby1 = 35.304;
  double rby2 = 15.666;
  double rby3 = 0.0;
  double rcy1 = 1.018;
  double rey1 = 0.35475;
  double rey2 = 0.01966;
  double rhy1 = 0.0;
  double rhy2 = 0.0;
  double rvy1 = 0.0;
  double rvy2 = 0.0;
  double rvy4 = 0.0;
  double rvy5 = 0.0;
  double rvy6 = 0.0;
  // Scaling of the fit itself (the .tir file's LMUX/LMUY/LKX/LKY): lab drum to track surface.
  double lmux = 0.665;
  double lmuy = 0.78;
  double lkx = 0.83125;
  double lky = 0.8;
  // Not a .tir coefficient: the force beyond the peak (see the field's doc).
  double falloff = 1.0;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.fnomin,
            {.key = "fnomin",
             .unit = "N",
             .lo = 100.0,
             .hi = 20000.0,
             .doc = "FNOMIN, nominal wheel load of the fit; dfz = (Fz - FNOMIN)/FNOMIN."});
    v.Field(s.pcx1,
            {.key = "pcx1", .lo = 0.5, .hi = 3.0, .doc = "PCX1, longitudinal shape factor C_x."});
    v.Field(s.pdx1, {.key = "pdx1",
                     .lo = 0.1,
                     .hi = 4.0,
                     .doc = "PDX1, longitudinal friction coefficient at FNOMIN (before LMUX)."});
    v.Field(s.pdx2, {.key = "pdx2",
                     .lo = -2.0,
                     .hi = 2.0,
                     .doc = "PDX2, load dependency of the longitudinal friction (per dfz)."});
    v.Field(s.pex1,
            {.key = "pex1", .lo = -20.0, .hi = 1.0, .doc = "PEX1, longitudinal curvature."});
    v.Field(s.pex2,
            {.key = "pex2", .lo = -20.0, .hi = 20.0, .doc = "PEX2, curvature variation with dfz."});
    v.Field(
        s.pex3,
        {.key = "pex3", .lo = -20.0, .hi = 20.0, .doc = "PEX3, curvature variation with dfz^2."});
    v.Field(s.pex4, {.key = "pex4",
                     .lo = -1.0,
                     .hi = 1.0,
                     .doc = "PEX4, curvature asymmetry drive/brake (0 keeps F_x odd in slip)."});
    v.Field(s.pkx1, {.key = "pkx1",
                     .lo = 1.0,
                     .hi = 200.0,
                     .doc = "PKX1, slip stiffness K_x/Fz at FNOMIN [N per unit slip per N]."});
    v.Field(s.pkx2, {.key = "pkx2",
                     .lo = -100.0,
                     .hi = 100.0,
                     .doc = "PKX2, variation of slip stiffness with dfz."});
    v.Field(s.pkx3, {.key = "pkx3",
                     .lo = -5.0,
                     .hi = 5.0,
                     .doc = "PKX3, exponent of the slip stiffness variation with dfz."});
    v.Field(s.phx1, {.key = "phx1",
                     .lo = -0.1,
                     .hi = 0.1,
                     .doc = "PHX1, horizontal shift in slip (0 keeps F_x odd)."});
    v.Field(s.phx2, {.key = "phx2",
                     .lo = -0.1,
                     .hi = 0.1,
                     .doc = "PHX2, variation of the horizontal shift with dfz."});
    v.Field(s.pvx1, {.key = "pvx1",
                     .lo = -0.5,
                     .hi = 0.5,
                     .doc = "PVX1, vertical shift (rolling-resistance-like offset) / Fz."});
    v.Field(s.pvx2, {.key = "pvx2",
                     .lo = -0.5,
                     .hi = 0.5,
                     .doc = "PVX2, variation of the vertical shift with dfz."});
    v.Field(s.pcy1,
            {.key = "pcy1", .lo = 0.5, .hi = 3.0, .doc = "PCY1, lateral shape factor C_y."});
    v.Field(s.pdy1, {.key = "pdy1",
                     .lo = 0.1,
                     .hi = 4.0,
                     .doc = "PDY1, lateral friction coefficient at FNOMIN (before LMUY)."});
    v.Field(s.pdy2, {.key = "pdy2",
                     .lo = -2.0,
                     .hi = 2.0,
                     .doc = "PDY2, load dependency of the lateral friction (per dfz)."});
    v.Field(s.pey1, {.key = "pey1", .lo = -20.0, .hi = 1.0, .doc = "PEY1, lateral curvature."});
    v.Field(s.pey2, {.key = "pey2",
                     .lo = -20.0,
                     .hi = 20.0,
                     .doc = "PEY2, lateral curvature variation with dfz."});
    v.Field(s.pey3, {.key = "pey3",
                     .lo = -1.0,
                     .hi = 1.0,
                     .doc = "PEY3, curvature asymmetry in alpha (0 keeps F_y odd)."});
    v.Field(s.pky1,
            {.key = "pky1",
             .lo = -200.0,
             .hi = -1.0,
             .doc = "PKY1, peak cornering stiffness K_y/FNOMIN (negative: TYDEX/ISO sign)."});
    v.Field(s.pky2, {.key = "pky2",
                     .lo = 0.1,
                     .hi = 20.0,
                     .doc = "PKY2, load (in FNOMIN) at which K_y peaks for PKY4 = 2."});
    v.Field(s.pky4, {.key = "pky4",
                     .lo = 0.5,
                     .hi = 4.0,
                     .doc = "PKY4, shape of K_y over load (MF5.2 standard value 2)."});
    v.Field(s.phy1, {.key = "phy1",
                     .lo = -0.1,
                     .hi = 0.1,
                     .doc = "PHY1, horizontal shift (ply steer/conicity) [rad]; 0 keeps F_y odd."});
    v.Field(s.phy2, {.key = "phy2",
                     .lo = -0.1,
                     .hi = 0.1,
                     .doc = "PHY2, variation of the horizontal shift with dfz [rad]."});
    v.Field(s.pvy1, {.key = "pvy1",
                     .lo = -0.5,
                     .hi = 0.5,
                     .doc = "PVY1, vertical shift S_Vy/Fz; 0 keeps F_y odd."});
    v.Field(s.pvy2, {.key = "pvy2",
                     .lo = -0.5,
                     .hi = 0.5,
                     .doc = "PVY2, variation of the vertical shift with dfz."});
    v.Field(s.rbx1, {.key = "rbx1",
                     .lo = 0.0,
                     .hi = 100.0,
                     .doc = "RBX1, slope of the F_x reduction with slip angle (combined slip)."});
    v.Field(s.rbx2, {.key = "rbx2",
                     .lo = 0.0,
                     .hi = 100.0,
                     .doc = "RBX2, variation of that slope with longitudinal slip."});
    v.Field(s.rcx1, {.key = "rcx1",
                     .lo = 0.1,
                     .hi = 3.0,
                     .doc = "RCX1, shape of the F_x reduction (combined slip)."});
    v.Field(s.rex1, {.key = "rex1",
                     .lo = -50.0,
                     .hi = 1.0,
                     .doc = "REX1, curvature of the F_x reduction (combined slip)."});
    v.Field(s.rex2, {.key = "rex2",
                     .lo = -50.0,
                     .hi = 50.0,
                     .doc = "REX2, variation of that curvature with dfz."});
    v.Field(s.rhx1, {.key = "rhx1",
                     .lo = -0.1,
                     .hi = 0.1,
                     .doc = "RHX1, slip-angle shift of the F_x reduction [rad]."});
    v.Field(s.rby1, {.key = "rby1",
                     .lo = 0.0,
                     .hi = 100.0,
                     .doc = "RBY1, slope of the F_y reduction with longitudinal slip."});
    v.Field(s.rby2, {.key = "rby2",
                     .lo = 0.0,
                     .hi = 100.0,
                     .doc = "RBY2, variation of that slope with slip angle."});
    v.Field(s.rby3, {.key = "rby3",
                     .lo = -0.1,
                     .hi = 0.1,
                     .doc = "RBY3, slip-angle shift in that slope [rad]; 0 keeps F_y odd."});
    v.Field(s.rcy1, {.key = "rcy1",
                     .lo = 0.1,
                     .hi = 3.0,
                     .doc = "RCY1, shape of the F_y reduction (combined slip)."});
    v.Field(s.rey1, {.key = "rey1",
                     .lo = -50.0,
                     .hi = 1.0,
                     .doc = "REY1, curvature of the F_y reduction (combined slip)."});
    v.Field(s.rey2, {.key = "rey2",
                     .lo = -50.0,
                     .hi = 50.0,
                     .doc = "REY2, variation of that curvature with dfz."});
    v.Field(
        s.rhy1,
        {.key = "rhy1", .lo = -0.1, .hi = 0.1, .doc = "RHY1, slip shift of the F_y reduction."});
    v.Field(
        s.rhy2,
        {.key = "rhy2", .lo = -0.1, .hi = 0.1, .doc = "RHY2, variation of that shift with dfz."});
    v.Field(s.rvy1, {.key = "rvy1",
                     .lo = -1.0,
                     .hi = 1.0,
                     .doc = "RVY1, slip-induced side force S_Vyk / (mu_y Fz); 0 disables it."});
    v.Field(s.rvy2, {.key = "rvy2",
                     .lo = -1.0,
                     .hi = 1.0,
                     .doc = "RVY2, variation of the slip-induced side force with dfz."});
    v.Field(s.rvy4, {.key = "rvy4",
                     .lo = 0.0,
                     .hi = 500.0,
                     .doc = "RVY4, slip-angle dependency of the slip-induced side force."});
    v.Field(s.rvy5, {.key = "rvy5",
                     .lo = 0.0,
                     .hi = 10.0,
                     .doc = "RVY5, shape of the slip-induced side force over slip."});
    v.Field(s.rvy6, {.key = "rvy6",
                     .lo = 0.0,
                     .hi = 200.0,
                     .doc = "RVY6, slope of the slip-induced side force over slip."});
    v.Field(s.lmux,
            {.key = "lmux",
             .lo = 0.05,
             .hi = 2.0,
             .doc = "LMUX, longitudinal friction scaling of the fit (drum to track). "
                    "EAV24: front 0.665, rear 0.695, chosen with LMUY so that (1) the "
                    "fit's own mu_x > mu_y survives (mu_x/mu_y at nominal load 1.02 front, "
                    "1.01 rear; real slicks, issue 14: 1.0-1.25) and (2) `scw vehicle gg` "
                    "lies within 10 % of the public EAV g-g-v fit (spec §4.4: braking ~15 "
                    "m/s^2 at low speed, 34.2 at 60 m/s). The team's own scaling was 0.8."});
    v.Field(s.lmuy, {.key = "lmuy",
                     .lo = 0.05,
                     .hi = 2.0,
                     .doc = "LMUY, lateral friction scaling of the fit. EAV24: 0.78 on both "
                            "axles, for the public EAV g-g-v fit's lateral limit (spec §4.4: 22.5 "
                            "m/s^2 at 40 m/s, 26.4 at 58 m/s; within 10 %). The paper's 29.5 "
                            "m/s^2 real-car maximum then lies inside the envelope (reached at "
                            "about 70 m/s)."});
    v.Field(s.lkx, {.key = "lkx",
                    .lo = 0.05,
                    .hi = 5.0,
                    .doc = "LKX, slip-stiffness scaling. EAV24: LMUX/0.8 (front 0.83125, rear "
                           "0.86875), so that the slip at the force peak stays that of the team's "
                           "fit with its scaling 0.8 (matters to ABS/TC slip thresholds)."});
    v.Field(s.lky, {.key = "lky",
                    .lo = 0.05,
                    .hi = 5.0,
                    .doc = "LKY, cornering-stiffness scaling. EAV24: front 0.8, rear 1.0. "
                           "Assumption: the effective front-axle cornering stiffness of a car is "
                           "lower than the tyre's by steering-system and suspension compliance "
                           "(not modelled otherwise); 0.8 gives a linear understeer gradient of "
                           "+0.4 ... +0.7 mrad/(m/s^2) over 10-70 m/s (`scw vehicle balance`), "
                           "inside the +0.3 ... +1.0 that a race car is set up with (issue 14). "
                           "With 1.0 the plant is neutral to oversteering."});
    v.Field(s.falloff,
            {.key = "falloff",
             .lo = 0.0,
             .hi = 3.0,
             .doc = "Scale of the force loss beyond the peak (not a .tir coefficient; pure slip, "
                    "longitudinal and lateral): beyond the slip of the peak the force is "
                    "D - falloff (D - F_MF), F_MF the Magic Formula's, so the curve up to the "
                    "peak, the peak D and the slip stiffness are the fit's. 1 = the Magic "
                    "Formula (sliding force D sin(C pi/2)), 0 = the force holds its peak. Needs "
                    "a force peak (1 < PCX1, PCY1 < 2) unless 1; the sliding force must stay "
                    "positive (falloff < 1/(1 - sin(C pi/2))).",
             .optional = true,
             .omit_default = true});
  }
  static void CrossCheck(const Mf52Params& p, Problems& pr) {
    if (p.falloff == 1.0) return;
    const FalloffBound b = FalloffBoundOf(p);
    if (!b.has_peak)
      pr.Add("falloff", std::string("needs a force peak with a positive sliding force (") + b.name +
                            " in (1, 2)); " + b.name + " is " + FormatNumber(b.c) +
                            ", so only 1 is accepted");
    else if (!(p.falloff < b.limit))
      pr.Add("falloff", FormatNumber(p.falloff) + " would make the sliding force zero or less (" +
                            b.name + " " + FormatNumber(b.c) + ": falloff < " +
                            FormatNumber(std::floor(b.limit * 100.0) / 100.0) + ")");
  }
};

inline FalloffBound FalloffBoundOf(const Mf52Params& tire) {
  const auto limit = [](double c) { return 1.0 / (1.0 - std::sin(c * M_PI / 2.0)); };
  const FalloffBound shapes[] = {{"PCY1", tire.pcy1}, {"PCX1", tire.pcx1}};
  for (FalloffBound b : shapes)
    if (!(b.c > 1.0 && b.c < 2.0)) return {b.name, b.c, false, 0.0};
  FalloffBound b = shapes[limit(tire.pcy1) <= limit(tire.pcx1) ? 0 : 1];
  b.limit = limit(b.c);
  return b;
}

/// Slip kinematics, relaxation and low-speed behaviour, common to all four tyres.
struct TireKinematicsParams {
  double relaxation_length_long = 0.3;
  double relaxation_length_lat = 0.2;
  double relaxation_speed_min = 10.0;
  double slip_speed_min_long = 3.0;
  double slip_speed_min_lat = 1.0;
  double slip_limit = 1.0;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.relaxation_length_long,
            {.key = "relaxation_length_long",
             .unit = "m",
             .lo = 0.01,
             .hi = 2.0,
             .doc = "Longitudinal relaxation length sigma_k: the slip state lags the kinematic "
                    "slip with T = sigma_k / max(|v_x,tyre|, relaxation_speed_min). 0.3 m as in "
                    "Open Car Dynamics (Pacejka 2006 eq. 7.18)."});
    v.Field(s.relaxation_length_lat,
            {.key = "relaxation_length_lat",
             .unit = "m",
             .lo = 0.01,
             .hi = 2.0,
             .doc = "Lateral relaxation length sigma_a of the slip-angle state; 0.2 m as in Open "
                    "Car Dynamics."});
    v.Field(s.relaxation_speed_min,
            {.key = "relaxation_speed_min",
             .unit = "m/s",
             .lo = 0.5,
             .hi = 50.0,
             .doc = "Speed floor of the relaxation time constants: below it the lag is constant "
                    "(sigma / floor), which keeps standstill well damped."});
    v.Field(s.slip_speed_min_long,
            {.key = "slip_speed_min_long",
             .unit = "m/s",
             .lo = 0.1,
             .hi = 20.0,
             .doc = "Denominator floor of the kinematic longitudinal slip (omega r - v)/max(|v|, "
                    "floor). Below it slip acts like a stiff damper that holds the car at rest "
                    "without NaN or chatter (3 m/s as in Open Car Dynamics)."});
    v.Field(s.slip_speed_min_lat,
            {.key = "slip_speed_min_lat",
             .unit = "m/s",
             .lo = 0.1,
             .hi = 20.0,
             .doc = "Denominator floor of the kinematic slip angle atan(v_y/max(|v_x|, floor))."});
    v.Field(s.slip_limit,
            {.key = "slip_limit",
             .lo = 0.1,
             .hi = 5.0,
             .doc = "Clamp of the kinematic longitudinal slip fed to the tyre (|kappa| <= "
                    "limit), the validity range of the fit."});
  }
};

/// Friction scaling used by scenarios: total factor on lambda_mu of wheel i is
///   mu * axle_mu_{x,y}(axle of i) * wheel_mu_{x,y}[i].
/// So "rear lateral grip -20 %" is rear_mu_y = 0.8 and a mu-split is wheel_mu_x = wheel_mu_y =
/// [1, 0.5, 1, 0.5].
struct GripParams {
  double mu = 1.0;
  double front_mu_x = 1.0;
  double front_mu_y = 1.0;
  double rear_mu_x = 1.0;
  double rear_mu_y = 1.0;
  std::vector<double> wheel_mu_x = {1.0, 1.0, 1.0, 1.0};
  std::vector<double> wheel_mu_y = {1.0, 1.0, 1.0, 1.0};

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.mu, {.key = "mu",
                   .lo = 0.05,
                   .hi = 2.0,
                   .doc = "Global road friction scaling (1 = dry track the car was calibrated "
                          "on); multiplies lambda_mu_x and lambda_mu_y of every tyre."});
    v.Field(s.front_mu_x, {.key = "front_mu_x",
                           .lo = 0.05,
                           .hi = 2.0,
                           .doc = "Front-axle longitudinal friction scaling lambda_mu_x."});
    v.Field(s.front_mu_y, {.key = "front_mu_y",
                           .lo = 0.05,
                           .hi = 2.0,
                           .doc = "Front-axle lateral friction scaling lambda_mu_y."});
    v.Field(s.rear_mu_x, {.key = "rear_mu_x",
                          .lo = 0.05,
                          .hi = 2.0,
                          .doc = "Rear-axle longitudinal friction scaling lambda_mu_x."});
    v.Field(s.rear_mu_y, {.key = "rear_mu_y",
                          .lo = 0.05,
                          .hi = 2.0,
                          .doc = "Rear-axle lateral friction scaling lambda_mu_y (0.8 = the "
                                 "'rear lateral grip -20 %' scenario)."});
    v.Field(s.wheel_mu_x, {.key = "wheel_mu_x",
                           .lo = 0.05,
                           .hi = 2.0,
                           .doc = "Per-wheel longitudinal friction scaling [FL, FR, RL, RR] "
                                  "(mu-split, a wet patch)."});
    v.Field(s.wheel_mu_y, {.key = "wheel_mu_y",
                           .lo = 0.05,
                           .hi = 2.0,
                           .doc = "Per-wheel lateral friction scaling [FL, FR, RL, RR]."});
  }
  static void CrossCheck(const GripParams& p, Problems& pr) {
    if (p.wheel_mu_x.size() != 4) pr.Add("wheel_mu_x", "needs exactly 4 values (FL, FR, RL, RR)");
    if (p.wheel_mu_y.size() != 4) pr.Add("wheel_mu_y", "needs exactly 4 values (FL, FR, RL, RR)");
  }
};

/// The EAV24/25-class rear tyre (360/620R13), the third-party A2RL team's fit of the official .tir
/// file (spec §4.4). Only the reduced coefficient set is public; the remaining pure-slip
/// coefficients are 0 (MF5.2 neutral values, PKY4 = 2) and the combined-slip shape coefficients are
/// the AV-21 ones (spec §4.1) with their offsets set to 0, an assumption that keeps the tyre odd.
inline Mf52Params Eav24RearTire() {
  Mf52Params t;
  t.fnomin = 4000.0;
  t.pcx1 = 1.6144;
  t.pdx1 = 2.2345;
  t.pdx2 = -0.25554;
  t.pex1 = 0.2833;
  t.pkx1 = 51.67;
  t.pkx3 = 0.2546;
  t.pcy1 = 1.5998;
  t.pdy1 = 1.9745;
  t.pdy2 = -0.4787;
  t.pey1 = -0.17632;
  t.pky1 = -44.68;
  t.pky2 = 2.269;
  t.lmux = 0.695;
  t.lmuy = 0.78;
  t.lkx = 0.86875;
  t.lky = 1.0;
  return t;
}

}  // namespace scw::params
