// The plant's input from the world around the car (the road under each wheel and the wind), apart
// from the actuator requests.
#pragma once

#include "params/schema/per_wheel.h"

namespace scw::plant {

/// What the road and the air do to the car during a step.
///
/// mu: the friction factor of the surface under each wheel (1 = the track's nominal surface; a wet
/// patch 0.6, an oily one 0.4). It multiplies the tyre's friction scaling (lambda_mu_x and
/// lambda_mu_y, after the vehicle's grip factors), so force and its peak slip follow the surface
/// the wheel is on. The closed loop fills it from the track at every step
/// (plant/track/road_surface.h); the plant reads no track itself.
///
/// wind_x, wind_y: the velocity of the air over the ground in the world frame (the direction the
/// air moves *to*: a wind from the left of a car heading along +x has wind_y < 0). The aero forces
/// follow the car's velocity relative to the air (plant/vehicle/vehicle.h, "Aero"). Exactly zero
/// (the default) is still air: the step is then bit for bit the one without wind.
struct Environment {
  PerWheel<double> mu{1.0, 1.0, 1.0, 1.0};  ///< [-] per wheel, > 0
  double wind_x = 0.0, wind_y = 0.0;        ///< [m/s] air velocity over the ground, world frame
};

}  // namespace scw::plant
