#include "controller/common/pid.h"

namespace scw::controller {

double Pid::Step(double u, const PidFlags& flags, PidState* s) const noexcept {
  const double use_pd = flags.use_pd ? 1.0 : 0.0;
  double d_term = 0.0;
  if (flags.update_pd) {
    const double a = gains_.derivative_filter_pole;
    s->filtered = a * s->filtered + (1.0 - a) * u;
    d_term = gains_.kd * (s->filtered - s->filtered_prev) / gains_.sample_time * use_pd;
    s->filtered_prev = s->filtered;
  }
  const double p_term = gains_.kp * s->filtered * use_pd;
  if (flags.reset_i) s->integrator = 0.0;
  const double candidate =
      s->integrator + gains_.ki * u * gains_.sample_time * (flags.update_i ? 1.0 : 0.0);
  if (gains_.integrator_min < candidate && candidate < gains_.integrator_max) {
    s->integrator = candidate;
  }
  return p_term + s->integrator * (flags.use_i ? 1.0 : 0.0) + d_term;
}

}  // namespace scw::controller
