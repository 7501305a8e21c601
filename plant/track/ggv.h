// g-g-v limits of a point-mass vehicle model for the velocity profile (plant-and-track spec §6.1,
// §6.3: TUM forward-backward solver and the TUMRT "diamond" representation).
//
// At speed v the admissible accelerations (a_x longitudinal, a_y lateral, [m/s^2]) are
//   |a_y| ≤ g·μ·ay_max(v)
//   a_x ≤  g·ax_drive_max(v) · (1 − (|a_y| / (g·μ·ay_max(v)))^p)^(1/p)      (driving)
//   −a_x ≤ g·μ·ax_brake_max(v) · (1 − (|a_y| / (g·μ·ay_max(v)))^p)^(1/p)    (braking)
// with g = gg_scale (the paper's acceleration scaling GG), μ the local friction scale of the track
// and p = `exponent` (1 = diamond, 2 = ellipse). Tables are linearly interpolated over `speed` and
// held constant outside it. All accelerations are specific forces along the path: the drive limit
// is NET of aero drag and rolling resistance (what the car can gain), the braking limit INCLUDES
// them (drag helps braking) — as plant::ComputeGgv (plant/vehicle/ggv.h) reports them, so its
// GgvPoint table fills this struct directly (lateral_max → ay_max, traction_max → ax_drive_max,
// braking_max → ax_brake_max). The drive limit is a power/traction limit and is not scaled by μ.
//
// Plain data; `Validate` throws scw::ConfigError listing every problem.
#pragma once

#include <string>
#include <vector>

namespace scw::plant {

struct GgvLimits {
  std::vector<double> speed{0.0, 100.0};         ///< [m/s], strictly ascending, ≥ 1 entry
  std::vector<double> ay_max{15.0, 15.0};        ///< max lateral acceleration [m/s^2] (> 0)
  std::vector<double> ax_drive_max{8.0, 8.0};    ///< max forward acceleration [m/s^2] (≥ 0)
  std::vector<double> ax_brake_max{15.0, 15.0};  ///< max deceleration, positive [m/s^2] (> 0)
  double exponent = 2.0;                         ///< p of the combination law, in [1, 10]

  /// One-row table (speed-independent limits).
  static GgvLimits Constant(double ay, double ax_drive, double ax_brake, double p = 2.0);

  /// Throws scw::ConfigError(`source`, …) listing every invalid entry.
  void Validate(const std::string& source = "ggv") const;

  double AyMax(double v) const noexcept;
  double AxDriveMax(double v) const noexcept;
  double AxBrakeMax(double v) const noexcept;

  /// (1 − r^p)^(1/p) for r = |a_y| / ay_limit, clamped to [0, 1]; 0 when |a_y| ≥ ay_limit.
  double Combine(double ay_abs, double ay_limit) const noexcept;
};

}  // namespace scw::plant
