// The plant's input from the world around the car (the road under each wheel), apart from the
// actuator requests.
#pragma once

#include "params/schema/per_wheel.h"

namespace scw::plant {

/// What the road does to the car during a step: the friction factor of the surface under each
/// wheel (1 = the track's nominal surface; a wet patch 0.6, an oily one 0.4). It multiplies the
/// tyre's friction scaling (lambda_mu_x and lambda_mu_y, after the vehicle's grip factors), so
/// force and its peak slip follow the surface the wheel is on. The closed loop fills it from the
/// track at every step (plant/track/road_surface.h); the plant reads no track itself.
struct Environment {
  PerWheel<double> mu{1.0, 1.0, 1.0, 1.0};  ///< [-] per wheel, > 0
};

}  // namespace scw::plant
