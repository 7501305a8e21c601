#include "plant/sensors/sensor_noise.h"

#include <cmath>

namespace scw::plant {

double NormalSource::Uniform() noexcept {
  // 53 random bits -> (0, 1): never 0, so log() below is finite.
  return (static_cast<double>(rng_() >> 11) + 0.5) * 0x1.0p-53;
}

double NormalSource::Next() noexcept {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  const double u1 = Uniform();
  const double u2 = Uniform();
  const double r = std::sqrt(-2.0 * std::log(u1));
  const double phi = 6.283185307179586 * u2;
  spare_ = r * std::sin(phi);
  has_spare_ = true;
  return r * std::cos(phi);
}

void AddSensorNoise(const params::SensorParams& p, Measurement* m, SensorNoiseState* s) noexcept {
  if (!p.noise || s == nullptr) return;
  auto add = [s](double* x, double sd) {
    if (sd > 0.0) *x += sd * s->normal.Next();
  };
  add(&m->x, p.position_std);
  add(&m->y, p.position_std);
  add(&m->psi, p.heading_std);
  add(&m->v_x, p.velocity_std);
  add(&m->v_y, p.velocity_std);
  add(&m->yaw_rate, p.yaw_rate_std);
  add(&m->a_x, p.acceleration_std);
  add(&m->a_y, p.acceleration_std);
  for (double& w : m->wheel_speed) add(&w, p.wheel_speed_std);
  add(&m->steering_angle, p.steering_std);
  for (double& b : m->brake_pressure) add(&b, p.pressure_std);
  add(&m->engine_speed, p.engine_speed_std);
}

}  // namespace scw::plant
