// A program that uses the car's stability controller and links scw::stability alone (no Ipopt,
// no YAML, no NLopt, no threads): proof that the code that ships to the car builds on its own.
// It drives the controller through a power-on oversteer moment with the shipped defaults and
// exits 0 only if the controller stays finite and intervenes (ESC, TC or countersteer).
#include <cmath>
#include <cstdio>

#include "controller/stability/stability_controller.h"

int main() {
  using scw::controller::StabilityController;
  const scw::params::StabilityParams params;  // the node's shipped defaults
  const StabilityController controller(params);
  StabilityController::State state;
  StabilityController::Input in;
  in.gear = in.gear_request = 4;
  bool intervened = false, finite = true;
  for (int k = 0; k < 300; ++k) {
    in.t = 0.01 * k;
    in.v_x = 40.0;
    in.steering_request = 0.05;  // left turn
    const bool slide = k >= 100;
    in.yaw_rate = slide ? 1.2 : 0.35;  // rotating far faster than the steering asks
    in.v_y = slide ? -6.0 : 0.0;       // rear stepping out: large sideslip
    in.throttle_request = 1.0;
    const double rear = slide ? 1.25 : 1.0;  // rear wheels spinning up under power
    const double omega = in.v_x / 0.31;
    in.wheel_speed = {omega, omega, omega * rear, omega * rear};
    const auto out = controller.Step(in, &state);
    finite = finite && std::isfinite(out.steering) && std::isfinite(out.throttle);
    for (double p : out.brake_bar) finite = finite && std::isfinite(p);
    intervened = intervened || out.esc_active || out.cs_active || out.slip_control_active;
  }
  std::printf("stability_alone: finite %s, intervened %s\n", finite ? "yes" : "no",
              intervened ? "yes" : "no");
  return finite && intervened ? 0 : 1;
}
