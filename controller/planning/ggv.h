// The g-g-v table of the driving stack: the acceleration limits the planner and the motion
// controllers respect (plant-and-track spec §6.1, §6.3: TUM forward-backward solver and the TUMRT
// "diamond" representation). The one table of the project; the velocity profile
// (controller/planning/velocity_profile.h) and the MPCs (controller/motion) use it.
//
// At speed v the admissible accelerations (a_x along the path, a_y lateral, [m/s^2]) are
//   |a_y| ≤ ay_max(v)
//   a_x  ≤ ax_drive_max(v) · C(|a_y| / ay_max(v), p_drive(v))      (driving)
//   −a_x ≤ ax_brake_max(v) · C(|a_y| / ay_max(v), p_brake(v))      (braking)
//   C(r, p) = (1 − r^p)^(1/p) for r in [0, 1), 0 for r ≥ 1
// with every column linearly interpolated over `speed` and held constant outside it. Drive and
// brake have their own exponent per speed (1 = diamond, 2 = ellipse): a rear-driven car loses its
// drive capacity with lateral load much faster than its braking capacity, so one exponent for both
// cannot describe it. The drive limit is NET of aero drag and rolling resistance (what the car can
// gain), the braking limit INCLUDES them (drag helps braking). Callers scale the table (GG, track
// friction): Scaled() multiplies ay and both a_x columns.
//
// Where the numbers come from: controller/planning/envelope.h derives the table from quasi-steady
// evaluations of the plant itself (plant/vehicle/quasi_steady.h), drive and brake separately,
// with each exponent fitted so that the law lies inside the plant's combined envelope.
//
// Plain data; `Visit` lists the six columns once (key, unit, description), and everything that
// handles the columns as a whole (emptying, the preparation cache's arrays) goes through it;
// `Validate` throws scw::ConfigError listing every problem.
#pragma once

#include <string>
#include <vector>

#include "params/schema/field.h"

namespace scw::controller::planning {

struct GgvTable {
  std::vector<double> speed{0.0, 100.0};         ///< [m/s], strictly ascending, ≥ 1 entry
  std::vector<double> ay_max{15.0, 15.0};        ///< max lateral acceleration [m/s^2] (> 0)
  std::vector<double> ax_drive_max{8.0, 8.0};    ///< max forward acceleration [m/s^2] (≥ 0)
  std::vector<double> ax_brake_max{15.0, 15.0};  ///< max deceleration, positive [m/s^2] (> 0)
  std::vector<double> drive_exponent{2.0, 2.0};  ///< p of the drive law per speed, in [1, 10]
  std::vector<double> brake_exponent{2.0, 2.0};  ///< p of the brake law per speed, in [1, 10]

  /// Every column once, in this order (the order of the preparation cache's arrays), as
  /// `v.Field(self.column, {.key = ..., ...})` (params::Meta). The rules on the values are those of
  /// Validate.
  template <class Self, class V>
  static void Visit(Self& self, V& v) {
    v.Field(self.speed, {.key = "speed", .unit = "m/s", .doc = "Speeds of the rows."});
    v.Field(self.ay_max, {.key = "ay_max", .unit = "m/s^2", .doc = "Lateral limit."});
    v.Field(self.ax_drive_max,
            {.key = "ax_drive_max", .unit = "m/s^2", .doc = "Pure drive limit, net of drag."});
    v.Field(self.ax_brake_max,
            {.key = "ax_brake_max", .unit = "m/s^2", .doc = "Pure braking limit (positive)."});
    v.Field(self.drive_exponent, {.key = "drive_exponent", .doc = "Exponent p of the drive law."});
    v.Field(self.brake_exponent, {.key = "brake_exponent", .doc = "Exponent p of the brake law."});
  }

  /// A table with every column empty (to be filled row by row).
  static GgvTable Empty();
  /// One-row table (speed-independent limits, one exponent p for drive and brake).
  static GgvTable Constant(double ay, double ax_drive, double ax_brake, double p = 2.0);
  /// Sets every drive and brake exponent to p.
  void SetExponent(double p);
  /// The same table with ay_max, ax_drive_max and ax_brake_max multiplied by `factor`.
  GgvTable Scaled(double factor) const;

  /// Throws scw::ConfigError(`source`, …) listing every invalid entry.
  void Validate(const std::string& source = "ggv") const;

  double AyMax(double v) const noexcept;
  double AxDriveMax(double v) const noexcept;
  double AxBrakeMax(double v) const noexcept;
  double DriveExponent(double v) const noexcept;
  double BrakeExponent(double v) const noexcept;

  /// Drive and brake factors C(|a_y| / ay_limit, p(v)) in [0, 1]; ay_limit is the caller's
  /// (possibly friction-scaled) lateral limit at v.
  double DriveFactor(double ay_abs, double ay_limit, double v) const noexcept;
  double BrakeFactor(double ay_abs, double ay_limit, double v) const noexcept;

  /// C(r, p) = (1 − r^p)^(1/p), 0 for r ≥ 1, 1 for r ≤ 0.
  static double Combine(double r, double p) noexcept;

  bool operator==(const GgvTable&) const = default;
};

}  // namespace scw::controller::planning
