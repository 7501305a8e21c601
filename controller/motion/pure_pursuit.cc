#include "controller/motion/pure_pursuit.h"

#include <algorithm>
#include <cmath>

namespace scw::controller::motion {

PurePursuit::PurePursuit(const params::TrackingParams& p, std::shared_ptr<const Path> path,
                         PurePursuitOptions options)
    : p_(p),
      path_(std::move(path)),
      options_(options),
      vel_lag_(p.vel_error_filter_time_constant, p.tS),
      kappa_filter_(LowPass::FromTimeConstant(p.curvature_filter_Ts, p.tS)) {
  params::ValidateOrThrow(p_, "tracking parameters");
  if (!path_)
    throw ConfigError("pure pursuit", "path",
                      "is missing (the controller follows a reference path)");
}

std::unique_ptr<MotionState> PurePursuit::MakeState() const { return std::make_unique<State>(); }

MotionOutput PurePursuit::Step(const MotionInput& in, MotionState* base) const noexcept {
  auto* st = static_cast<State*>(base);
  MotionOutput out;
  const Path& path = *path_;
  const double v_x = std::isfinite(in.v_x) ? in.v_x : 0.0;
  const double cos_psi = std::cos(in.psi), sin_psi = std::sin(in.psi);  // used twice below

  // Path matching of the CoG, and of the longitudinal preview point.
  const PathProjection here = MatchOnPath(path, in, options_.projection_window, st, &out);
  const double preview = std::max(v_x, 3.0) * p_.lookahead_time_long_ff_s;
  const PathProjection ahead = path.Project(in.x + preview * cos_psi, in.y + preview * sin_psi,
                                            in.psi, here.s + preview, options_.projection_window);
  const PathPoint target = path.Sample(ahead.s);
  out.v_target = target.v;

  // Longitudinal: feed-forward a_x plus filtered speed-error feedback.
  const double e_v = vel_lag_.Step(target.v - v_x, &st->vel_error);
  double ax = target.a_x + p_.velocity_p_gain * e_v;
  if (target.v < 0.05) ax = std::min(ax, -4.5);
  out.ax_request = ax;

  // Lateral: pure pursuit on a speed-dependent lookahead.
  const double curvature_term =
      std::min(p_.curvature_lookahead_gain / std::max(std::abs(target.kappa), 1e-8),
               options_.max_curvature_lookahead);
  const double lookahead = std::max(
      p_.min_lookahead_distance_lat_m + p_.lookahead_time_lat_s * v_x + curvature_term, 1e-6);
  const PathPoint goal = path.Sample(here.s + lookahead);
  const double dx = goal.x - in.x, dy = goal.y - in.y;
  const double d_lat = -sin_psi * dx + cos_psi * dy;
  const double kappa_raw = 2.0 * d_lat / (lookahead * lookahead);
  const double kappa_pp = kappa_filter_.Step(kappa_raw, &st->kappa_filtered);
  const double l = p_.vehicle.wheelbase_m;
  const double delta_fb = std::atan(l * kappa_pp);
  const double kappa_ff = path.Sample(here.s + v_x * p_.lookahead_time_lat_ff_s).kappa;
  const double delta_ff = p_.enable_lat_feedforward_perc * std::atan(l * kappa_ff);
  double delta = delta_ff + delta_fb + p_.P_VDC_SteeringOvalComp_rad;
  if (!std::isfinite(delta)) delta = 0.0;
  out.steering_request = std::clamp(delta, p_.vehicle.min_angle, p_.vehicle.max_angle);
  const double kappa_req =
      options_.esc_target == EscTarget::kTotal ? std::tan(delta_ff + delta_fb) / l : kappa_pp;
  out.ay_request = kappa_req * v_x * v_x;
  if (!std::isfinite(out.ay_request)) out.ay_request = 0.0;
  if (!std::isfinite(out.ax_request)) out.ax_request = 0.0;
  return out;
}

}  // namespace scw::controller::motion
