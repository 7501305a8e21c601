// Countersteer: steering correction when the rear axle slides more than the front
// (stability-control spec §5). Independent of ESC.
//
// Inputs (Countersteer::Input): v_x, v_y [m/s], ψ̇ [rad/s] (raw state estimate), steering angle δ
// used for the slip angles [rad] (measured if available, else the request), steering request
// δ_req [rad], vertical loads Fz [N] (quasi-static estimate or external), slip_angle_valid.
// Output: steering δ_out [rad] (> 0 left), active flag, filtered axle slip angles.
//
// Per step:
//  1. α_i = −atan2(v_y,t,i, max(1, v_x,t,i)) from the raw v_x (no low-speed fade, no speed gate).
//  2. If ¬slip_angle_valid, or an axle load sum Fz_L + Fz_R is non-finite or ≤ 1e-6: filters not
//     updated, δ_out = clamp(δ_req), inactive.
//  3. α_F = (Fz_FL·α_FL + Fz_FR·α_FR)/(Fz_FL + Fz_FR), α_R likewise.
//  4. ᾱ_F = LPF(a)(α_F), ᾱ_R = LPF(a)(α_R), a = exp(−T_s/max(T, 1e-6)), T =
//     countersteer_system.slip_angle_filter_Ts (a TIME CONSTANT; 0.15 s → 0.9355). Initial 0.
//     The filters run also when countersteer is disabled.
//  5. If enabled ∧ |ᾱ_R| > |ᾱ_F| ∧ |ᾱ_R| > α_en: δ_out = δ_req − k·(ᾱ_R − ᾱ_F) (k =
//     steering_factor), active; else δ_out = δ_req. Magnitudes are compared regardless of sign.
//  6. δ_out = clamp(δ_out, vehicle.steering.min_angle, max_angle) ALWAYS (also when disabled).
#pragma once

#include "controller/common/low_pass.h"
#include "controller/stability/vehicle_model.h"
#include "params/schema/stability_params.h"

namespace scw::controller {

/// Steps 5–6 for given filtered axle slip angles [rad]; sets *active.
double CountersteerCommand(double steering_request, double alpha_front, double alpha_rear,
                           const params::CountersteerParams& cs,
                           const params::VehicleSteering& limits, bool* active) noexcept;

class Countersteer {
 public:
  struct Input {
    double v_x = 0.0;
    double v_y = 0.0;
    double yaw_rate = 0.0;
    double steering = 0.0;          ///< δ for the slip angles [rad]
    double steering_request = 0.0;  ///< δ_req [rad]
    Wheels fz{};                    ///< [N]
    bool slip_angle_valid = true;
  };

  struct State {
    double alpha_front_filtered = 0.0;
    double alpha_rear_filtered = 0.0;

    /// Every member once (controller/common/state_visit.h).
    template <class Self, class V>
    static void Visit(Self& s, V& v) {
      v.Real(s.alpha_front_filtered);
      v.Real(s.alpha_rear_filtered);
    }
  };

  struct Output {
    double steering = 0.0;  ///< δ_out [rad]
    bool active = false;
    double alpha_front_filtered = 0.0;  ///< ᾱ_F [rad]
    double alpha_rear_filtered = 0.0;   ///< ᾱ_R [rad]
  };

  /// Throws ConfigError if `p` is invalid.
  explicit Countersteer(const params::StabilityParams& p);

  Output Step(const Input& in, State* s) const noexcept;

  double filter_pole() const noexcept { return filter_.pole(); }

 private:
  params::CountersteerParams cs_;
  params::VehicleSteering limits_;
  ChassisGeometry geometry_;
  LowPass filter_;
};

}  // namespace scw::controller
