#include "tuning/sim/run_observers.h"

#include <algorithm>
#include <cmath>

namespace scw::tuning {

// ---------------------------------------------------------------------------------------------
// LapCounter

bool LapCounter::Update(double t, double s) {
  const double prev_progress = progress_;
  const double prev_t = t_;
  if (started_) {
    double ds = s - s_;
    if (ds > 0.5 * length_) ds -= length_;
    if (ds < -0.5 * length_) ds += length_;
    progress_ += ds;
  }
  started_ = true;
  s_ = s;
  t_ = t;
  if (progress_ >= (laps_ + 1) * length_ && progress_ > prev_progress) {
    const double target = (laps_ + 1) * length_;
    const double t_cross =
        prev_t + (t - prev_t) * (target - prev_progress) / (progress_ - prev_progress);
    lap_times_.push_back(t_cross - lap_start_);
    lap_start_ = t_cross;
    ++laps_;
    return true;
  }
  return false;
}

void LapCounter::WriteTo(RunMetrics* m) const {
  m->time = t_;
  m->end_s = s_;
  m->end_lap = laps_;
  m->distance = std::max(0.0, progress_);
  m->lap_times = lap_times_;
}

// ---------------------------------------------------------------------------------------------
// MetricsAccumulator

void MetricsAccumulator::Add(const TickRecord& r, RunMetrics* m) noexcept {
  const double ts = ts_;
  m->max_abs_sideslip = std::max(m->max_abs_sideslip, std::abs(r.beta));
  m->max_abs_lateral_error = std::max(m->max_abs_lateral_error, std::abs(r.motion.lateral_error));
  m->max_abs_heading_error = std::max(m->max_abs_heading_error, std::abs(r.motion.heading_error));
  m->max_speed = std::max(m->max_speed, r.speed);
  m->max_esc_margin = std::max(m->max_esc_margin, r.output.esc_margin);
  const controller::EscActivationTerms& terms = r.output.esc_margin_terms;
  m->max_esc_beta_ratio = std::max(m->max_esc_beta_ratio, terms.beta);
  m->max_esc_beta_error_ratio = std::max(m->max_esc_beta_error_ratio, terms.beta_error);
  m->max_esc_yaw_rate_error_ratio = std::max(m->max_esc_yaw_rate_error_ratio, terms.yaw_rate_error);
  m->sideslip_excess_integral +=
      std::max(0.0, std::abs(r.beta) * kRadToDeg - sideslip_allowed_deg_) * ts;
  const controller::StabilityInput& in = r.input;
  // two first-order high-passes in series, each the input minus its low-pass
  const double a = steer_hf_a_;
  const double steer = in.steering_request;
  if (ticks_ == 0.0) steer_lp_ = steer;
  steer_lp_ += a * (steer - steer_lp_);
  const double h1 = steer - steer_lp_;
  steer_lp2_ += a * (h1 - steer_lp2_);
  const double h2 = h1 - steer_lp2_;
  ticks_ += 1.0;
  steer_hf_sq_ += h2 * h2 * ts;
  m->steer_hf_rms = std::sqrt(steer_hf_sq_ / (ticks_ * ts));
  const controller::StabilityOutput& out = r.output;
  for (std::size_t i = 0; i < 4; ++i) {
    const double slip_pct = 100.0 * r.plant.kappa[i];
    double& mx = IsFront(i) ? m->max_slip_front : m->max_slip_rear;
    mx = std::max(mx, std::abs(slip_pct));
    if (out.esc_active && IsFront(i))
      m->esc_brake_energy += std::max(0.0, out.brake_bar[i] - in.brake_request_bar[i]) *
                             brake_gain_[i] * std::abs(r.meas.wheel_speed[i]) * ts;
    if (out.abs_state[i] != controller::SlipPhase::kInactive)
      m->abs_pressure_released += std::max(0.0, in.brake_request_bar[i] - out.brake_bar[i]) * ts;
  }
  if (AnyActive(out.tc_state))
    m->tc_throttle_cut += std::max(0.0, in.throttle_request - out.throttle) * ts;
  esc_.Update(out.esc_active, ts, &m->esc_count, &m->esc_time);
  cs_.Update(out.cs_active, ts, &m->cs_count, &m->cs_time);
  abs_.Update(AnyActive(out.abs_state), ts, &m->abs_count, &m->abs_time);
  tc_.Update(AnyActive(out.tc_state), ts, &m->tc_count, &m->tc_time);
}

// ---------------------------------------------------------------------------------------------
// AbortMonitor

std::optional<RunStatus> AbortMonitor::Check(const TickRecord& r) noexcept {
  const params::AbortParams& ab = limits_;
  for (std::size_t i = 0; i < 4; ++i) {
    const double slip_pct = 100.0 * r.plant.kappa[i];
    lock_time_[i] = slip_pct < -ab.lock_slip_pct ? lock_time_[i] + ts_ : 0.0;
    spin_time_[i] = slip_pct > ab.spin_slip_pct ? spin_time_[i] + ts_ : 0.0;
  }
  if (std::abs(r.beta) * kRadToDeg > ab.max_sideslip_deg) return RunStatus::kSideslip;
  if (std::abs(r.motion.lateral_error) > ab.max_lateral_error) return RunStatus::kLateralError;
  if (ab.off_track && (r.n > track_->WidthLeftAt(r.s) || -r.n > track_->WidthRightAt(r.s)))
    return RunStatus::kOffTrack;
  bool locked = false, spun = false;
  for (std::size_t i = 0; i < 4; ++i) {
    locked = locked || lock_time_[i] > ab.slip_time;
    spun = spun || spin_time_[i] > ab.slip_time;
  }
  if (locked || spun) return locked ? RunStatus::kWheelLock : RunStatus::kWheelSpin;
  if (r.t > timeout_) return RunStatus::kTimeout;
  return std::nullopt;
}

}  // namespace scw::tuning
