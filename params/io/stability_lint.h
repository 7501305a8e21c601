// Engineering warnings about a stability parameter set that is valid but probably not what the
// engineer meant (stability-control spec §4.4, §10.2 items 2 and 12): the car interpolates the
// velocity-scheduled thresholds with LINEAR EXTRAPOLATION outside the breakpoints, so a threshold
// can become ≤ 0 (the condition is then always true) or grow large within the speed range.
#pragma once

#include <string>
#include <vector>

#include "params/schema/field.h"
#include "params/schema/stability_params.h"

namespace scw::params {

struct LintOptions {
  double v_min = 0.0;  ///< speed range checked [m/s]
  double v_max = 90.0;
  double growth = 2.0;  ///< warn when a threshold exceeds growth × its largest breakpoint value
};

/// Warnings (path + sentence). Empty for a set without surprises.
std::vector<Problem> LintStability(const StabilityParams& p, const LintOptions& o = {});

/// The smallest value the car's node uses of the velocity-scheduled ESC threshold array `key`
/// (ESC.beta_threshold_activate, ESC.psi_dot_error_threshold_activate,
/// ESC.beta_error_threshold_activate): the minimum of its piecewise-linear interpolation over
/// ESC.threshold_velocities, outer segments extended, between max(o.v_min,
/// ESC.min_activation_velocity) and o.v_max — the speeds at which LintStability checks the
/// hysteresis. A deactivation threshold below it never meets the inverted-hysteresis warning. NaN
/// for another key, an array that does not match the breakpoints, or a minimum ≤ 0.
double ScheduledMinimum(const StabilityParams& p, const std::string& key,
                        const LintOptions& o = {});

}  // namespace scw::params
