// Slip estimation (stability-control spec §2): reference speed, longitudinal slips with the
// low-speed fade, slip angles, engine-speed based virtual slips and vertical loads.
//
// Inputs (SlipEstimator::Input): CoG velocity v_x, v_y [m/s] (body frame), yaw rate ψ̇ [rad/s],
// a_x, a_y [m/s²] (0 when unavailable), steering δ [rad] (measured if available, else the request,
// §2.1), wheel speeds ω_i [rad/s], the largest measured FRONT brake pressure [bar] (0 if
// unavailable), engaged gear (int), engine speed [rad/s], optional external loads Fz [N].
//
// Equations (per step, in this order):
//  1. r_i(v) = r_20,i·interp(v; velocity_scaling) — fronts use tires.front_left, rears
//     tires.rear_left radius_20mps; all four use the front_left velocity scaling (the node file has
//     no rear scaling key). Evaluated at v_x (step 2) and at v_ref (step 5).
//  2. Front-wheel speed estimate: v_x,w,i = (ω_i·r_i(v_x) − sin δ·v_y,f)/cos δ (fronts),
//     v_front = ½ Σ_{FL,FR} (v_x,w,i − Δ_i). Without valid wheel speeds v_front := v_x (workspace
//     choice; the reference keeps stale values).
//  3. Blend f = max(clamp(p_front,max/5 bar, 0, 1), clamp(−(a_x,f + 5), 0, 1),
//     clamp(max(|λ_FL|, |λ_FR|)_{k−1}/5 − 1, 0, 1)), a_x,f = LPF(0.8)(a_x) (initial 0),
//     f_filt = LPF(0.8)(f) (initial 1). v_ref = f_filt·v_x + (1 − f_filt)·v_front.
//  4. Fade s = clamp(max(v_ref − max(v_min − 2, 0), 0)⁸ / 2⁸, 0, 1), v_min =
//     P_VDC_MinVelSlipCalc_mps (Appendix B: 0 at ≤ 3, 0.0039 at 4, 0.10 at 4.5, 1 at 5 m/s).
//  5. Tyre velocities from (v_ref, v_y, ψ̇, δ) (vehicle_model.h);
//     λ_i = 100·s·clamp((ω_i·r_i(v_ref) − v_x,t,i)/max(3, v_x,t,i), −1, 1) [%] (λ < 0 braking);
//     α_i = s·(−atan2(v_y,t,i, max(1, v_x,t,i))) [rad].
//  6. Virtual slips (§2.5): g = max(0, gear − 1); ω_rear = ω_engine/(i_fd·i_gear[g]);
//     ω_virt,RL/RR = ω_rear + Δ_RL/RR / r_RL/RR(v_x); fronts = measured ω. If g is out of range,
//     i_fd·i_gear[g] ≈ 0 or a rear radius ≈ 0, all four virtual wheel speeds are 0 (reference
//     behaviour). λ_virt with the formula of step 5. Wheel speeds invalid → λ = 0 and
//     λ_virt,front = 0; engine speed invalid → λ_virt,front = λ_front and λ_virt,rear = 0.
//  7. Fz = the external loads when all four are finite, else the quasi-static model
//     (vehicle_model.h) at (v_x, a_x, a_y).
//
// State: a_x filter output, blend filter output, previous front slips. Step is noexcept and
// allocation-free.
#pragma once

#include "controller/stability/vehicle_model.h"
#include "params/schema/stability_params.h"

namespace scw::controller {

class SlipEstimator {
 public:
  struct Input {
    double v_x = 0.0;       ///< [m/s]
    double v_y = 0.0;       ///< [m/s]
    double yaw_rate = 0.0;  ///< [rad/s]
    double a_x = 0.0;       ///< [m/s²], 0 when unavailable
    double a_y = 0.0;       ///< [m/s²], 0 when unavailable
    double steering = 0.0;  ///< δ [rad]
    Wheels wheel_speed{};   ///< ω [rad/s]
    bool wheel_speeds_valid = true;
    double front_pressure_max_bar = 0.0;  ///< max measured front pressure [bar]
    int gear = 0;                         ///< engaged gear (0 = neutral)
    double engine_speed = 0.0;            ///< [rad/s]
    bool engine_speed_valid = false;
    Wheels fz_external{};  ///< [N], used when fz_external_valid
    bool fz_external_valid = false;
  };

  struct Output {
    Wheels slip_pct{};          ///< λ [%]
    Wheels virtual_slip_pct{};  ///< λ_virt [%]
    Wheels slip_angle{};        ///< α (faded) [rad]
    Wheels fz{};                ///< vertical loads [N]
    double v_ref = 0.0;         ///< reference speed [m/s]
    double blend = 1.0;         ///< f_filt [–] (1: state estimate, 0: front wheels)
    double fade = 0.0;          ///< s [–]
  };

  struct State {
    double ax_filtered = 0.0;
    double blend_filtered = 1.0;
    double prev_slip_fl = 0.0;  ///< [%]
    double prev_slip_fr = 0.0;  ///< [%]

    /// Every member once (controller/common/state_visit.h).
    template <class Self, class V>
    static void Visit(Self& s, V& v) {
      v.Real(s.ax_filtered);
      v.Real(s.blend_filtered);
      v.Real(s.prev_slip_fl);
      v.Real(s.prev_slip_fr);
    }
  };

  /// Throws ConfigError if `p` is invalid.
  explicit SlipEstimator(const params::StabilityParams& p);

  Output Step(const Input& in, State* s) const noexcept;

  /// s(v_ref) of step 4.
  static double LowSpeedFade(double v_ref, double v_min) noexcept;
  /// λ = 100·s·clamp((ω·r − v_x,t)/max(3, v_x,t), −1, 1) [%].
  static double LongitudinalSlipPct(double omega, double radius, double v_tyre_x,
                                    double fade) noexcept;

  const LoadModel& load_model() const noexcept { return load_model_; }
  const ChassisGeometry& geometry() const noexcept { return geometry_; }
  /// Dynamic radius of wheel i at speed v [m].
  double Radius(std::size_t wheel, double speed) const noexcept;

 private:
  ChassisGeometry geometry_;
  LoadModel load_model_;
  double radius_front_;
  double radius_rear_;
  params::VelocityScaling scaling_;
  double v_min_;
  double final_drive_;
  std::vector<double> gear_ratios_;
};

}  // namespace scw::controller
