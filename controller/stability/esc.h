// ESC: yaw-moment control by differential FRONT braking, oversteer only (stability-control spec
// §4). Signs: body frame x forward, y left; ψ̇ > 0 left turn; β = atan2(v_y, v_x) (< 0 in a
// left-hand oversteer slide); yaw moment M > 0 turns the car left (brakes the LEFT front more).
//
// Inputs (Esc::Input): v_x, v_y [m/s], ψ̇ [rad/s], steering request δ_req [rad] (uncorrected, never
// the countersteered angle), optional targets a_y,req [m/s²], ψ̇_req [rad/s], β_req [rad] (NaN =
// not provided), requested pressures p_in [bar], sanitised pad friction μ per wheel,
// slip_angle_valid.
//
// Per step:
//  1. v = hypot(v_x, v_y), β = atan2(v_y, v_x); E = ESC.enabled ∧ slip_angle_valid.
//  2. References (EscReferences): if ψ̇_req or β_req is missing, a curvature
//     κ = a_y,req/max(v, 3)² if a_y,req is given, else the linear single track in steady state
//     κ = δ_req / (l + m·v²·(l_r·c_r − l_f·c_f)/(c_f·c_r·l)).
//     ψ̇_ref = ψ̇_req or κ·v;  β_ref = β_req or κ·(l_r − l_f·m·v²/(c_r·l)).
//  3. Error filters (run every step, initial 0): e_ψ,f = LPF(tS_psi_dot)(ψ̇_ref − ψ̇),
//     e_β,f = LPF(tS_beta)(β_ref − β). The "tS" keys are POLES.
//  4. Phase (NextEscPhase), thresholds interpolated (and EXTRAPOLATED) over v:
//     Inactive → Active iff E ∧ v > v_min ∧ |β| > B_a(v) ∧ |e_β,f| > Eβ_a(v) ∧ |e_ψ,f| > Eψ_a(v)
//                          ∧ ψ̇·e_ψ,f < 0 ∧ β·e_β,f < 0 ∧ e_β,f·e_ψ,f < 0   (oversteer only)
//     Active → Inactive iff ¬E ∨ v < v_min ∨ (|β| < B_d ∧ |e_β,f| < Eβ_d ∧ |e_ψ,f| < Eψ_d)
//  5. Two PIDs (pid.h, PidFlags::Gated(active)) on u_ψ = e_ψ,f and u_β = −e_β,f, integrators
//     bounded by ±max_integrator_yaw_moment in PID units [rad/s²] (spec §10.2 #4);
//     M = I_z·(PID_ψ + PID_β) [N·m] when active, else 0.
//  6. Allocation (AllocateYawMoment): A = M·(2/tw)·k_wheel [bar·μ], tw =
//  vehicle.dimension.trackwidth,
//     k_wheel = r_FL/(r_pad·n_pad·π(d/2)²·1e5), p_max = max(ESC.max_brake_pressure, 0):
//       A > 0: Δ = min(p_FR, A/(2μ_FR)); p_FR −= Δ; p_FL += min((A − Δ·μ_FR)/μ_FL, max(0, p_max −
//       p_FL)) A ≤ 0: mirror (release FL, build FR).
//     Rears untouched. The allocation is skipped when M = 0 (identical result for non-negative
//     requests). The realised force difference is 2M/tw (moment M) unless head-room clips it.
//  7. ALL FOUR pressures clamped to [0, p_max] every step, active, inactive or disabled: a global
//     brake-pressure limiter (spec §10.2 #5, reproduced).
#pragma once

#include "controller/common/low_pass.h"
#include "controller/common/per_wheel_ops.h"
#include "controller/common/pid.h"
#include "params/schema/stability_params.h"

namespace scw::controller {

enum class EscPhase : std::uint8_t { kInactive = 0, kActive = 1 };

struct EscSignals {
  bool enabled = false;   ///< E
  double speed = 0.0;     ///< v [m/s]
  double beta = 0.0;      ///< β [rad]
  double yaw_rate = 0.0;  ///< ψ̇ [rad/s]
  double e_psi = 0.0;     ///< e_ψ,f [rad/s]
  double e_beta = 0.0;    ///< e_β,f [rad]
};

/// Thresholds evaluated at the current speed.
struct EscThresholds {
  double beta_activate = 0.0;
  double psi_dot_error_activate = 0.0;
  double beta_error_activate = 0.0;
  double beta_deactivate = 0.0;
  double psi_dot_error_deactivate = 0.0;
  double beta_error_deactivate = 0.0;
  double min_velocity = 0.0;
};

/// Interpolated activation thresholds at speed v (extrapolated) plus the scalar ones.
EscThresholds EscThresholdsAt(double speed, const params::EscParams& p) noexcept;

EscPhase NextEscPhase(EscPhase phase, const EscSignals& s, const EscThresholds& th) noexcept;

/// The three magnitude terms of ESC's activation condition, each its signal over its activation
/// threshold: |β|/B_a, |e_β,f|/Eβ_a, |e_ψ,f|/Eψ_a. A diagnostic, not part of the controller's
/// behaviour, computed whether or not ESC is enabled (E ignored): all 0 unless v > v_min and the
/// three oversteer sign conditions hold; a non-positive (extrapolated) threshold counts as met
/// (kMaxEscMargin); each capped at kMaxEscMargin. A term whose largest value over a run stays
/// below 1 kept ESC off in that run, whatever the other two did.
struct EscActivationTerms {
  double beta = 0.0;            ///< |β|/B_a
  double beta_error = 0.0;      ///< |e_β,f|/Eβ_a
  double yaw_rate_error = 0.0;  ///< |e_ψ,f|/Eψ_a
};
EscActivationTerms EscActivationRatios(const EscSignals& s, const EscThresholds& th) noexcept;
inline constexpr double kMaxEscMargin = 10.0;

/// How close the activation condition of an inactive ESC is: the smallest of the three
/// EscActivationRatios (0 unless the sign conditions hold). Above 1 the condition holds (with E,
/// ESC activates).
double EscActivationMargin(const EscSignals& s, const EscThresholds& th) noexcept;

struct EscReference {
  double yaw_rate = 0.0;   ///< ψ̇_ref [rad/s]
  double beta = 0.0;       ///< β_ref [rad]
  double curvature = 0.0;  ///< κ [1/m] (0 if both targets are given)
};

/// The linear single track (constant cornering stiffnesses) behind the step-2 references.
struct EscReferenceModel {
  double mass = 800.0;                ///< m [kg]
  double wheelbase = 2.971;           ///< l [m]
  double l_front = 1.724;             ///< [m]
  double l_rear = 1.247;              ///< [m]
  double stiffness_front = 100000.0;  ///< c_f [N/rad]
  double stiffness_rear = 200000.0;   ///< c_r [N/rad]
};

/// Step 2. Optional targets are NaN when not provided.
EscReference EscReferences(double speed, double steering_request, double ay_request,
                           double yaw_rate_request, double beta_request,
                           const EscReferenceModel& m) noexcept;

/// Step 6 without the final clamp. `pressure_per_force` = k_wheel [bar/N], `track_width` [m].
Wheels AllocateYawMoment(double yaw_moment, const Wheels& pressure, const Wheels& mu,
                         double pressure_per_force, double track_width,
                         double max_pressure) noexcept;

class Esc {
 public:
  struct Input {
    double v_x = 0.0;
    double v_y = 0.0;
    double yaw_rate = 0.0;
    double steering_request = 0.0;
    double ay_request = std::numeric_limits<double>::quiet_NaN();
    double yaw_rate_request = std::numeric_limits<double>::quiet_NaN();
    double beta_request = std::numeric_limits<double>::quiet_NaN();
    Wheels pressure_in{};  ///< [bar]
    Wheels mu{0.35, 0.35, 0.35, 0.35};
    bool slip_angle_valid = true;
  };

  struct State {
    EscPhase phase = EscPhase::kInactive;
    double e_psi_filtered = 0.0;
    double e_beta_filtered = 0.0;
    PidState pid_psi{};
    PidState pid_beta{};

    /// Every member once (controller/common/state_visit.h).
    template <class Self, class V>
    static void Visit(Self& s, V& v) {
      v.Discrete(s.phase);
      v.Real(s.e_psi_filtered);
      v.Real(s.e_beta_filtered);
      v.Nested(s.pid_psi);
      v.Nested(s.pid_beta);
    }
  };

  struct Output {
    Wheels pressure{};        ///< [bar], clamped to [0, p_max]
    double yaw_moment = 0.0;  ///< M [N·m]
    bool active = false;
    EscReference reference{};
    double e_psi_filtered = 0.0;
    double e_beta_filtered = 0.0;
    double activation_margin = 0.0;         ///< EscActivationMargin of this step (diagnostic)
    EscActivationTerms activation_terms{};  ///< EscActivationRatios of this step (diagnostic)
  };

  /// Throws ConfigError if `p` is invalid.
  explicit Esc(const params::StabilityParams& p);

  Output Step(const Input& in, State* s) const noexcept;

  double pressure_per_force() const noexcept { return k_wheel_; }
  double max_pressure() const noexcept { return max_pressure_; }

 private:
  params::EscParams p_;
  EscReferenceModel model_;
  LowPass psi_filter_;
  LowPass beta_filter_;
  Pid pid_psi_;
  Pid pid_beta_;
  double yaw_inertia_;
  double track_width_;
  double k_wheel_;
  double max_pressure_;
  bool thresholds_usable_;
};

}  // namespace scw::controller
