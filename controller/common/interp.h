// Piecewise-linear interpolation with LINEAR EXTRAPOLATION, as the reference's helper does
// (stability-control spec §0.2, Appendix A, §10.2 #2). The reference's comment claims it clamps;
// it does not, and the car runs the extrapolating version, so the workspace keeps it:
//
//   i = index of the segment [xp_i, xp_{i+1}] containing x, with the first segment used for
//       x ≤ xp_1 and the last for x > xp_{n−2} (ends extended linearly);
//   f(x) = fp_i + (x − xp_i)·(fp_{i+1} − fp_i)/(xp_{i+1} − xp_i).
//
// Preconditions (validated by the parameter schema, never checked per call beyond the cheap
// cases below): xp strictly ascending. Unlike the reference (throws / undefined behaviour) this
// function is total and noexcept: unequal lengths or empty arrays → NaN, one element → fp_0.
// Used for ESC activation thresholds, brake-bias shift, dynamic tyre radius and the brake friction
// map.
#pragma once

#include <span>

namespace scw::controller {

double Interp(double x, std::span<const double> xp, std::span<const double> fp) noexcept;

}  // namespace scw::controller
