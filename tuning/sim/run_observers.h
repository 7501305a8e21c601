// The observers of a closed-loop run (tuning/sim/closed_loop.h): each watches the control ticks
// (TickRecord, tuning/sim/tick_record.h) for one purpose and knows nothing of the controllers or
// the plant that produced them.
//
//   LapCounter          unwrapped progress along the track → laps, lap times, where the run ended
//   MetricsAccumulator  extremes, integrals and intervention counts of RunMetrics
//   AbortMonitor        the abort rules of the scenario (params/schema/scenario_params.h)
//
// The trace is the fourth observer (TraceRecorder, tuning/sim/trace_schema.h).
//
// Each observer is fed once per control tick, in tick order, with the tick period tS fixed for
// the run. Accumulations run in the order and with the expressions the closed loop always used
// (results are compared bit for bit across versions: test/golden). Nothing allocates per tick
// (LapCounter appends once per lap). Not thread-safe: one set of observers per run.
#pragma once

#include <optional>
#include <vector>

#include "params/schema/per_wheel.h"
#include "params/schema/scenario_params.h"
#include "plant/track/track.h"
#include "tuning/sim/metrics.h"
#include "tuning/sim/tick_record.h"

namespace scw::tuning {

/// Laps from the unwrapped progress along a closed track of length L, robust to a start just
/// before the line (that start counts the crossing as the end of lap 1 only after a full L).
///
/// Per tick with track position s_k ∈ [0, L) at time t_k:
///   Δs_k = s_k − s_{k−1}, shifted by ∓L when |Δs_k| > L/2 (the car crossed the start line), and
///   progress_k = progress_{k−1} + Δs_k (progress_0 = 0: the first tick only sets s).
/// Lap j + 1 is complete when progress_k ≥ (j + 1)·L while progress grows; its end is
/// interpolated linearly within the tick,
///   t_cross = t_{k−1} + (t_k − t_{k−1})·((j + 1)·L − progress_{k−1}) / (progress_k −
///   progress_{k−1}),
/// (t_{−1} = 0) and its lap time is t_cross minus the previous crossing (0 for lap 1: the flying
/// start). At most one lap completes per tick.
class LapCounter {
 public:
  /// `length` [m] > 0: the track length L.
  explicit LapCounter(double length) noexcept : length_(length) {}

  /// Feeds one tick: time `t` [s] (increasing) and the projected arc length `s` [m] in [0, L).
  /// Returns whether this tick completed a lap.
  bool Update(double t, double s);

  /// Laps completed [-].
  int laps() const noexcept { return laps_; }
  /// Unwrapped distance driven along the track since the first tick [m] (negative while the car
  /// is still behind its start point).
  double progress() const noexcept { return progress_; }
  /// Track position of the last tick [m] (0 before the first).
  double s() const noexcept { return s_; }
  /// Time of the last tick [s] (0 before the first).
  double time() const noexcept { return t_; }
  /// [s] duration of each completed lap.
  const std::vector<double>& lap_times() const noexcept { return lap_times_; }

  /// Where the run ended, as of the last tick: RunMetrics::time, end_s, end_lap, lap_times and
  /// distance = max(0, progress) [m]. Leaves every other field alone.
  void WriteTo(RunMetrics* m) const;

 private:
  double length_;
  bool started_ = false;
  double s_ = 0.0, t_ = 0.0;
  double progress_ = 0.0;
  double lap_start_ = 0.0;  ///< [s] time the current lap began
  int laps_ = 0;
  std::vector<double> lap_times_;
};

/// Rising edges and active time of one on/off intervention signal sampled every tick: an
/// activation is a tick that is on after one that was off (the tick before the first counts as
/// off); each tick that is on adds the tick period.
class InterventionCounter {
 public:
  /// Feeds one tick of length `dt` [s]: ++*count on a rising edge, *time += dt while `active`.
  void Update(bool active, double dt, int* count, double* time) noexcept {
    if (active && !before_) ++*count;
    if (active) *time += dt;
    before_ = active;
  }

 private:
  bool before_ = false;
};

/// Accumulates the RunMetrics of a run tick by tick (all rectangle rule, tick period tS):
///   max_abs_sideslip       max |β| [rad]
///   max_abs_lateral_error  max |lateral error| [m];  max_abs_heading_error  max |heading error|
///   max_speed              max speed [m/s]
///   max_esc_margin         max of the stability output's esc_margin
///   max_esc_*_ratio        max of each of its terms (esc_margin_terms)
///   steer_hf_rms           √(Σ h₂² · tS / (ticks · tS)) [rad], the steering request's
///                          second-order high-pass: h₁ = δ_req − y₁, h₂ = h₁ − y₂, with the
///                          first-order low-passes y₁ += a(δ_req − y₁), y₂ += a(h₁ − y₂),
///                          a = tS/(τ + tS), τ = kSteerHfTau (y₁ = δ_req, y₂ = 0 before the
///                          first tick): a steady steering rate leaves nothing
///   sideslip_excess_integral  Σ max(0, |β|·180/π − β_allowed) · tS [deg·s]
///   max_slip_front/rear    max |100 κ_i| over the axle's wheels [%] (the plant's slips)
///   esc_brake_energy       Σ over the front wheels while ESC acts of
///                          max(0, p_out,i − p_req,i) · k_b,i · |ω_i| · tS [J]
///                          (k_b [N·m/bar] the brake torque gain, ω_i the measured wheel speed)
///   abs_pressure_released  Σ over the wheels whose ABS phase is not inactive of
///                          max(0, p_req,i − p_out,i) · tS [bar·s]
///   tc_throttle_cut        Σ while any TC wheel acts of max(0, throttle_req − throttle_out)·tS [s]
///   esc/cs/abs/tc _count, _time   activations and active time (InterventionCounter; ABS and TC
///                          are active when any wheel is)
/// Other fields of RunMetrics are left alone.
class MetricsAccumulator {
 public:
  /// `ts` [s] the tick period; `sideslip_allowed_deg` [deg] β_allowed; `brake_gain` [N·m/bar]
  /// per wheel, the plant's brake torque per pressure.
  MetricsAccumulator(double ts, double sideslip_allowed_deg,
                     const PerWheel<double>& brake_gain) noexcept
      : ts_(ts),
        steer_hf_a_(ts / (kSteerHfTau + ts)),
        sideslip_allowed_deg_(sideslip_allowed_deg),
        brake_gain_(brake_gain) {}

  /// Adds tick `r` to `*m`.
  void Add(const TickRecord& r, RunMetrics* m) noexcept;

  /// [s] the time constant of each of steer_hf_rms's two high-passes: corner 1/(2π τ) ≈ 1.6 Hz,
  /// between a racing line's steering (below 1 Hz) and a limit cycle of the steering loop
  /// (2.5-5 Hz measured, docs/plant-calibration.md).
  static constexpr double kSteerHfTau = 0.1;

 private:
  double ts_;
  double steer_hf_a_;         ///< a = tS/(τ + tS) of both low-passes (steer_hf_rms)
  double steer_lp_ = 0.0;     ///< [rad] y₁, low-pass of the steering request (steer_hf_rms)
  double steer_lp2_ = 0.0;    ///< [rad] y₂, low-pass of its first high-pass
  double steer_hf_sq_ = 0.0;  ///< [rad²·s] Σ h₂² · tS so far
  double ticks_ = 0.0;        ///< ticks added so far
  double sideslip_allowed_deg_;
  PerWheel<double> brake_gain_;
  InterventionCounter esc_, cs_, abs_, tc_;
};

/// The abort rules of a run, checked once per tick in this order (the first that holds wins):
///   1. kSideslip      |β|·180/π > max_sideslip_deg
///   2. kLateralError  |lateral error| > max_lateral_error
///   3. kOffTrack      (off_track only) n > w_left(s) or −n > w_right(s) (the track's widths)
///   4. kWheelLock     a wheel's slip 100 κ_i < −lock_slip_pct held for longer than slip_time
///      kWheelSpin     a wheel's slip 100 κ_i > spin_slip_pct held for longer than slip_time
///                     (lock wins when both hold). Held time: + tS per tick the condition holds,
///                     back to 0 on a tick it does not, so it fires on the first tick at which
///                     the sum of tS exceeds slip_time.
///   5. kTimeout       t > timeout
/// Non-finite values and the completed run are the closed loop's own business.
class AbortMonitor {
 public:
  /// `limits`: the scenario's abort block; `timeout` [s]; `ts` [s] the tick period; `track` for
  /// its widths (must outlive the monitor).
  AbortMonitor(const params::AbortParams& limits, double timeout, double ts,
               const plant::Track& track) noexcept
      : limits_(limits), timeout_(timeout), ts_(ts), track_(&track) {}

  /// Feeds one tick (updates the held times) and returns the status of the first rule that
  /// holds, or nullopt when the run goes on.
  std::optional<RunStatus> Check(const TickRecord& r) noexcept;

  /// [s] how long each wheel has been locked / spinning, as of the last tick.
  const PerWheel<double>& lock_time() const noexcept { return lock_time_; }
  const PerWheel<double>& spin_time() const noexcept { return spin_time_; }

 private:
  params::AbortParams limits_;
  double timeout_;
  double ts_;
  const plant::Track* track_;
  PerWheel<double> lock_time_{}, spin_time_{};
};

}  // namespace scw::tuning
