// The planner's g-g-v table derived from the plant itself (issue 14; plant-and-track spec §6.3,
// the TUMRT approach on our reduced double track).
//
// For each speed v of the table (10 … 90 m/s, every 10 m/s) the quasi-steady double track of the
// plant (plant/vehicle/quasi_steady.h) gives
//   ay_max(v)          the largest lateral acceleration at constant speed (drag held by the
//                      rear tyres, steering lock respected),
//   D(v, r), B(v, r)   the largest net drive and brake acceleration at a_y = r ay_max(v) for
//                      r in kEnvelopeLevels (drive through the car's differential, brakes through
//                      the car's front bias),
// and per speed the law of controller/planning/ggv.h is fitted to D and B separately: the exponent
// p in [1, 2] and the peak a_x(0) ≤ D(v, 0) that maximise the area under the law subject to
// lying inside the plant's envelope at every level (the TUMRT diamond fit). So the planner never
// asks for a combination the plant cannot hold in quasi-steady state, up to the linear
// interpolation between speeds.
//
// Why planning includes the plant here: the envelope is the plant's own quasi-steady model
// evaluated offline, at preparation time; planning runs nowhere else (scw::stability, the car's
// controller, includes no planning), and an interface in between would repeat the model's five
// limit functions without removing the dependency.
#pragma once

#include <array>
#include <vector>

#include "controller/planning/ggv.h"
#include "params/schema/vehicle_params.h"

namespace scw::controller::planning {

inline constexpr std::array<double, 9> kEnvelopeLevels = {0.0,  0.25, 0.5,  0.65, 0.75,
                                                          0.85, 0.9,  0.95, 0.98};

/// The plant's combined envelope at one speed, as sampled (for reports and tests).
struct EnvelopeRow {
  double speed = 0.0;                      ///< [m/s]
  double ay_max = 0.0;                     ///< [m/s^2]
  std::array<double, 9> drive{}, brake{};  ///< at kEnvelopeLevels × ay_max [m/s^2]
};

std::vector<EnvelopeRow> SampleEnvelope(const params::VehicleParams& v, double brake_bias_front,
                                        const std::vector<double>& speeds);

/// Fits the planner's table to sampled rows (see the file comment).
GgvTable FitEnvelope(const std::vector<EnvelopeRow>& rows);

/// The planner's table: SampleEnvelope at 10, 20, …, 90 m/s and FitEnvelope give each speed's
/// exponents and the fitted peaks' share of the pure limits; the pure limits (ay_max, drive and
/// brake at a_y = 0) are sampled every 2 m/s, because the power limit (~1/v) and downforce
/// (~v^2) make them too curved for 10 m/s steps. Deterministic; ~1.5 s.
GgvTable PlantEnvelope(const params::VehicleParams& v, double brake_bias_front);

}  // namespace scw::controller::planning
