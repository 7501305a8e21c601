// Longitudinal controller (stability-control spec §6.2): a_x request → total force request F
// (the stability controller's long_fx) → throttle through the inverted engine map, or per-wheel
// brake pressures through the brake bias.
//
//   FF = k_rot·m·a_x,req + ½ρ·c_D·A·v² + c_rr·(m·g + ½ρ·(−c_L)·A·v²)
//   FB = LPF_Tfb( clamp(k_p·e_a, ±F_lim) + LPF_Td(k_d·ė_a) ),  e_a = a_x,req − a_x
//   F  = sat( ratelimit( FF + FB·[¬slip_control_active] ) )     (feedback frozen while ABS/TC act)
//   option hold_during_esc (not the car): while ESC acts, FB left out too and F ≤ the last F
//   F ≥ F_eb (engine drag at closed throttle): throttle with engine torque F·r_r/(i_g·i_fd·η)
//   F <  F_eb: throttle 0; brake force F_b = F − F_eb split front b / rear 1 − b:
//              p_front = b·|F_b|·r_f/(2·k_f), p_rear = (1 − b)·|F_b|·r_r/(2·k_r) per wheel [bar]
// Deviations from the car's controller (docs/quirks.md §10.2 #20): rolling-resistance feed-forward
// counted once (the car doubles it), the rate limiter keeps the saturated value, no brake-pressure
// PID (disabled on the car), no throttle PID or warm-up logic.
// Units: SI, pressures in bar, throttle [0..1], engine speed [rad/s].
#pragma once

#include <vector>

#include "controller/common/low_pass.h"
#include "params/schema/longitudinal_params.h"
#include "params/schema/per_wheel.h"

namespace scw::controller::motion {

/// The controller's knowledge of the car (from the vehicle configuration).
struct LongitudinalModel {
  double mass = 720.0;                               ///< [kg]
  double air_density = 1.2;                          ///< [kg/m³]
  double drag_area = 1.27;                           ///< c_D·A [m²]
  double downforce_area = 4.06;                      ///< −c_L·A [m²] (> 0: downforce)
  double rolling_resistance = 0.015;                 ///< c_rr [-]
  double radius_front = 0.307, radius_rear = 0.307;  ///< [m]
  std::vector<double> gear_ratios{3.083, 2.286, 1.7647, 1.421, 1.19, 1.036};
  double final_drive = 2.818;
  double efficiency = 0.92;                                ///< gearbox × final drive
  std::vector<double> map_speed;                           ///< engine map speed breakpoints [rad/s]
  std::vector<double> map_throttle;                        ///< throttle breakpoints [-]
  std::vector<double> map_torque;                          ///< row-major [N·m]
  double brake_gain_front = 25.0, brake_gain_rear = 25.0;  ///< [N·m/bar] per wheel
  double max_pressure = 120.0;                             ///< [bar]
};

struct LongitudinalInput {
  double ax_request = 0.0;    ///< [m/s²]
  double a_x = 0.0;           ///< measured [m/s²]
  double speed = 0.0;         ///< [m/s]
  double engine_speed = 0.0;  ///< [rad/s]
  int gear = 1;               ///< engaged gear (1-based)
  bool slip_control_active = false;
  bool esc_active = false;  ///< ESC active at the previous step (used with hold_during_esc)
};

struct LongitudinalOutput {
  double force = 0.0;  ///< F = long_fx [N], drive > 0
  double throttle = 0.0;
  PerWheel<double> brake_bar{};
};

class LongitudinalController {
 public:
  struct State {
    double force = 0.0;  ///< last F (rate limiter)
    double fb = 0.0;     ///< filtered feedback
    double d = 0.0;      ///< filtered derivative term
    double e_prev = 0.0;
    bool initialised = false;
  };

  /// Throws ConfigError on invalid parameters or an inconsistent engine map.
  LongitudinalController(const params::LongitudinalParams& p, LongitudinalModel model,
                         double sample_time);

  LongitudinalOutput Step(const LongitudinalInput& in, State* s) const noexcept;

  /// Crankshaft torque of the model map [N·m] (bilinear, clamped at the map edges).
  double EngineTorque(double omega_e, double throttle) const noexcept;
  /// Smallest throttle giving `torque` at omega_e (0 or 1 at the ends).
  double ThrottleFor(double omega_e, double torque) const noexcept;
  /// Force at the rear wheels [N] the model expects from `throttle` at omega_e in `gear`
  /// (1-based, clamped): EngineTorque · i_g · i_fd · η / r_r. The inverse of the throttle path
  /// of Step (a request that overrides the throttle reports this as its long_fx).
  double DriveForce(double omega_e, int gear, double throttle) const noexcept;

 private:
  params::LongitudinalParams p_;
  LongitudinalModel m_;
  double ts_;
  LowPass fb_filter_, d_filter_;
};

}  // namespace scw::controller::motion
