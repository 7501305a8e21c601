// Input programs of the standard open-loop maneuvers (tuning/maneuver/maneuver.h): what the
// driving robot commands, as pure functions of the time since the program began. No state, no
// plant: a test checks each program's shape (frequency, dwell, timing) on its own.
//
// Units: time [s], road-wheel angle [rad] (> 0 left), brake pressure [bar]. The standards state
// handwheel angles; the maneuvers convert them with the car's steering ratio
// (params/schema/maneuver_params.h), handwheel = ratio × road wheel.
//
// Sources (facts, in our words): FMVSS 126 S7.6-S7.9 and UN R140 Annex 3 (slowly increasing
// steer at 13.5 deg/s handwheel; sine with dwell of 0.7 Hz with a 500 ms dwell at the second
// peak; amplitudes 1.5 A, 2 A, ... up to 6.5 A or 270 deg, never beyond 300 deg); ISO 7401
// (step steer); ISO 4138 (steady-state circular, constant-speed method); ISO 7975 (braking in a
// turn); ISO 9816 (power-off in a turn); ISO 14512 (straight-line braking on split mu).
#pragma once

#include <vector>

#include "params/schema/per_wheel.h"
#include "params/schema/vehicle_params.h"

namespace scw::tuning {

/// The sine with dwell of amplitude `amplitude` [rad] (sign = direction of the first half wave)
/// and frequency f [Hz], dwell T_d [s]: with T = 1/f,
///   δ(t) = a·sin(2π f t)              for 0 ≤ t < 3T/4        (first half wave, then the second
///                                                             to its peak −a)
///   δ(t) = −a                         for 3T/4 ≤ t < 3T/4 + T_d   (the dwell)
///   δ(t) = a·sin(2π f (t − T_d))      for 3T/4 + T_d ≤ t < T + T_d (back to zero)
///   δ(t) = 0                          before 0 and from T + T_d on.
struct SineWithDwell {
  double amplitude = 0.0;  ///< [rad]
  double frequency = 0.7;  ///< [Hz]
  double dwell = 0.5;      ///< [s]

  double At(double t) const noexcept;
  /// [s] when the dwell begins (the second peak), 3/(4f).
  double DwellStart() const noexcept { return 0.75 / frequency; }
  /// [s] when the program returns to zero for good, 1/f + T_d (the ideal completion of steer).
  double Duration() const noexcept { return 1.0 / frequency + dwell; }
  /// [s] the steering reversal: the zero crossing between the half waves, 1/(2f).
  double Reversal() const noexcept { return 0.5 / frequency; }
};

/// A ramp from 0 to `amplitude` [rad] in `rise_time` [s] starting at t = 0, held after (the step
/// steer of ISO 7401, as a robot drives it): 0 before 0, a·t/t_r while rising, a after.
double StepSteer(double t, double amplitude, double rise_time) noexcept;

/// The slowly increasing steer: 0 before 0, rate·t after [rad].
double RampSteer(double t, double rate) noexcept;

/// The amplitude factors of a sine-with-dwell series: `factors` (multiples of A), then, when
/// `extend_to_270deg` and the last factor times A stays below 270 deg at the handwheel, further
/// factors in steps of 0.5 up to the first that reaches 270 deg; every factor whose angle exceeds
/// 300 deg is replaced by one run at exactly 300 deg (listed once, as 300 deg / A).
/// `a_handwheel_deg` = A at the handwheel [deg] > 0.
std::vector<double> SineWithDwellFactors(const std::vector<double>& factors, double a_handwheel_deg,
                                         bool extend_to_270deg);

/// Brake pressures [bar] per wheel that make the car decelerate at `decel` [m/s²] on level ground
/// when the tyres deliver the torques, with front share `front_share` of the force:
///   p_front = b·m·a·r_f / (2 k_f),  p_rear = (1 − b)·m·a·r_r / (2 k_r)
/// (m chassis mass, r wheel radius, k brake torque gain [N·m/bar]; aero drag left out, so the car
/// decelerates a little more than `decel` at speed).
PerWheel<double> BrakePressuresFor(double decel, double front_share,
                                   const params::VehicleParams& v) noexcept;

/// The longitudinal force [N] (braking < 0) that the brake pressures `p` [bar] ask the tyres
/// for: −Σ k_i p_i / r_i. The stability controller's long_fx input for a brake program.
double BrakeForceOf(const PerWheel<double>& p, const params::VehicleParams& v) noexcept;

}  // namespace scw::tuning
