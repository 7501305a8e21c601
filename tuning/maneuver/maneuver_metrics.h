// The metrics of the standard maneuvers (tuning/maneuver/maneuver.h) as pure functions of
// sampled signals: time t_k [s] strictly increasing, a value y_k per sample. No plant, no state:
// a test computes each on synthetic signals and compares with values worked out by hand.
//
// Between samples every signal is linear (Interpolate); a time outside [t_0, t_last] has no value
// (NaN). Signs follow the signal (> 0 left for steering, yaw rate, lateral acceleration).
//
// Definitions (our words; FMVSS 126 S7.11 and UN R140 Annex 3 for the sine with dwell, ISO 7401
// for the step response, ISO 4138 for the understeer gradient):
//   beginning of steer (BOS)   the first time |δ_H| reaches 5 deg at the handwheel
//   completion of steer (COS)  the first time after the dwell that the steering angle returns to
//                              zero (crosses or reaches it)
//   peak yaw rate              the first local peak of the yaw rate in the direction of the
//                              second (dwell) half wave, after the steering reversal
//   yaw-rate ratio at Δt       ψ̇(COS + Δt) / ψ̇_peak [%]; limits 35 % at 1.00 s, 20 % at 1.75 s
//   lateral displacement       ∫∫ a_y dt dt from BOS (zero lateral speed and displacement there)
//                              to BOS + 1.07 s, in the direction of the first steer; limit
//                              ≥ 1.83 m for amplitudes of 5 A and above
//   A                          the steering angle at 0.3 g on the least-squares line δ(a_y)
//                              through the slowly increasing steer's samples with a_y between
//                              0.1 g and 0.375 g
#pragma once

#include <vector>

namespace scw::tuning {

/// g [m/s²], for the standards' lateral accelerations in g.
inline constexpr double kStandardGravity = 9.80665;

/// y at time `tq`, linear between samples; NaN outside [t.front(), t.back()] or for no samples.
double Interpolate(const std::vector<double>& t, const std::vector<double>& y, double tq);

/// The first time ≥ `from` at which |y| reaches `level` > 0 (linear between samples), or NaN.
double FirstReach(const std::vector<double>& t, const std::vector<double>& y, double level,
                  double from);

/// The first time > `after` at which y returns to zero: y changes sign between two samples (the
/// crossing interpolated), or y_k = 0 after a non-zero sample (the crossing where the line
/// through the two samples before meets zero, within (t_{k−1}, t_k]: a program that ends at zero
/// is sampled after it got there); NaN if it never does.
double ReturnToZero(const std::vector<double>& t, const std::vector<double>& y, double after);

struct Peak {
  double time = 0.0;   ///< [s]
  double value = 0.0;  ///< y at the peak (with its sign)
};

/// The first local peak of s·y (s = +1 or −1, `sign`) at or after `from` with s·y > 0: the first
/// sample that is at least its predecessor and greater than its successor. Without one before the
/// last sample, the largest s·y from `from` on (the last sample if that is where it grows to).
/// value is NaN when no sample lies at or after `from`.
Peak FirstPeak(const std::vector<double>& t, const std::vector<double>& y, double from,
               double sign);

/// ∫∫ y dt dt from `t0` (zero rate and displacement there) to `t0 + duration`, trapezoidal on
/// the samples (the ends interpolated). NaN when [t0, t0 + duration] is not covered.
double DoubleIntegral(const std::vector<double>& t, const std::vector<double>& y, double t0,
                      double duration);

struct LineFit {
  double intercept = 0.0;
  double slope = 0.0;
  int samples = 0;  ///< 0 or 1: no line (intercept and slope NaN)
};

/// Least-squares line y = intercept + slope·x through the samples with lo ≤ x ≤ hi.
LineFit FitLine(const std::vector<double>& x, const std::vector<double>& y, double lo, double hi);

/// The sine with dwell's metrics of one run.
struct SineWithDwellMetrics {
  double t_bos = 0.0;                 ///< [s] beginning of steer
  double t_cos = 0.0;                 ///< [s] completion of steer
  double peak_yaw_rate = 0.0;         ///< [rad/s] ψ̇_peak (sign of the second half wave)
  double t_peak = 0.0;                ///< [s]
  double ratio_1_00 = 0.0;            ///< [%] ψ̇(COS + 1.00 s) / ψ̇_peak
  double ratio_1_75 = 0.0;            ///< [%] ψ̇(COS + 1.75 s) / ψ̇_peak
  double lateral_displacement = 0.0;  ///< [m] at BOS + 1.07 s, > 0 towards the first steer
};

/// The metrics from the commanded road-wheel angle `steer` [rad], the yaw rate [rad/s] and the
/// lateral acceleration a_y [m/s²], all sampled at `t`. `bos_threshold` [rad] = 5 deg / steering
/// ratio; `dwell_end` [s] the program's end of dwell (COS is searched after it); `reversal` [s] the
/// program's zero crossing between the half waves (the peak is searched from it); `direction` +1
/// when the first half wave steers left, −1 right.
SineWithDwellMetrics ComputeSineWithDwell(const std::vector<double>& t,
                                          const std::vector<double>& steer,
                                          const std::vector<double>& yaw_rate,
                                          const std::vector<double>& a_y, double bos_threshold,
                                          double dwell_end, double reversal, double direction);

/// The step response of one output (ISO 7401), from the steering angle δ [rad] and the output y:
///   t_50       the first time |δ| reaches half its final value |δ_final| (δ at the last sample)
///   y_ss       the mean of y over the samples in [t_last − `steady_window`, t_last]
///   response   the first time after t_50 at which s·y reaches 0.9·|y_ss| (s = sign of y_ss),
///              minus t_50
///   peak       the largest s·y after t_50 and its time minus t_50 (peak response time)
///   overshoot  (|peak| − |y_ss|) / |y_ss| [%]
///   gain       y_ss / δ_final
struct StepResponse {
  double steady_state = 0.0;
  double response_time = 0.0;  ///< [s]
  double peak = 0.0;
  double peak_time = 0.0;  ///< [s]
  double overshoot_pct = 0.0;
  double gain = 0.0;
};
StepResponse ComputeStepResponse(const std::vector<double>& t, const std::vector<double>& steer,
                                 const std::vector<double>& y, double steady_window);

}  // namespace scw::tuning
