// Piecewise definition of a closed track: a sequence of segments whose curvature is linear in arc
// length (plant/track/track.h integrates it to x, y, heading).
//
//   segment k, local arc length σ ∈ [0, length[k]]:
//     κ(σ) = curvature_start[k] + (curvature_end[k] − curvature_start[k]) · σ / length[k]
//   straight: both curvatures 0; arc: equal, non-zero; clothoid: different.
//   ψ(s) = start_heading + ∫κ ds,  x(s) = start_x + ∫cos ψ ds,  y(s) = start_y + ∫sin ψ ds.
//
// Sign convention: curvature > 0 turns LEFT (anticlockwise), [1/m]. Widths are distances from the
// centre line to the left/right edge [m], both positive, given at the START of each segment and
// blended linearly to the next segment's start value. `friction_scale` is a per-segment friction
// multiplier (same blending), or a single value for the whole track.
//
// Closure: a closed loop needs total turning ±2π and end point = start point. The integrated
// turning must be within `heading_tolerance` of ±2π and the end gap within `closure_tolerance`;
// the builder then scales every curvature by 2π/turning and removes the remaining gap by a shift
// that grows linearly with s (documented in plant/track/track.h).
#pragma once

#include <string>
#include <vector>

#include "params/schema/field.h"
#include "params/schema/friction_patch_params.h"

namespace scw::params {

struct TrackParams {
  std::string name = "oval";
  double start_x = 0.0;
  double start_y = 0.0;
  double start_heading = 0.0;
  // Default: a valid 200 m × R 50 m oval (so that a default-constructed definition is usable).
  std::vector<double> length{200.0, 157.07963267948966, 200.0, 157.07963267948966};
  std::vector<double> curvature_start{0.0, 0.02, 0.0, 0.02};
  std::vector<double> curvature_end{0.0, 0.02, 0.0, 0.02};
  std::vector<double> width_left{6.0, 6.0, 6.0, 6.0};
  std::vector<double> width_right{6.0, 6.0, 6.0, 6.0};
  std::vector<double> friction_scale{1.0};
  FrictionPatches friction_patches{};
  double step = 1.0;
  double closure_tolerance = 2.0;
  double heading_tolerance = 0.02;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.name, {.key = "name", .doc = "Track name (shown by scw track info)."});
    v.Field(s.start_x, {.key = "start_x",
                        .unit = "m",
                        .lo = -1e6,
                        .hi = 1e6,
                        .doc = "x of the start line (s = 0) on the centre line.",
                        .optional = true});
    v.Field(s.start_y, {.key = "start_y",
                        .unit = "m",
                        .lo = -1e6,
                        .hi = 1e6,
                        .doc = "y of the start line (s = 0) on the centre line.",
                        .optional = true});
    v.Field(s.start_heading,
            {.key = "start_heading",
             .unit = "rad",
             .lo = -7.0,
             .hi = 7.0,
             .doc = "Heading of the centre line at s = 0 (from +x, anticlockwise).",
             .optional = true});
    v.Field(s.length, {.key = "length",
                       .unit = "m",
                       .lo = 0.1,
                       .hi = 1e5,
                       .doc = "Arc length of each segment, in driving order from the start line.",
                       .min_size = 2});
    v.Field(s.curvature_start, {.key = "curvature_start",
                                .unit = "1/m",
                                .lo = -1.0,
                                .hi = 1.0,
                                .doc = "Curvature at the start of each segment (> 0: left turn).",
                                .min_size = 2});
    v.Field(s.curvature_end, {.key = "curvature_end",
                              .unit = "1/m",
                              .lo = -1.0,
                              .hi = 1.0,
                              .doc = "Curvature at the end of each segment (linear in between: "
                                     "equal to curvature_start for straights and arcs).",
                              .min_size = 2});
    v.Field(s.width_left, {.key = "width_left",
                           .unit = "m",
                           .lo = 0.5,
                           .hi = 100.0,
                           .doc = "Centre line to left edge at the start of each segment.",
                           .min_size = 2});
    v.Field(s.width_right, {.key = "width_right",
                            .unit = "m",
                            .lo = 0.5,
                            .hi = 100.0,
                            .doc = "Centre line to right edge at the start of each segment.",
                            .min_size = 2});
    v.Field(s.friction_scale, {.key = "friction_scale",
                               .unit = "-",
                               .lo = 0.05,
                               .hi = 2.0,
                               .doc = "Friction multiplier per segment (or one value for the whole "
                                      "track) applied to the tyre-road friction.",
                               .optional = true});
    v.Nested("friction_patches", s.friction_patches, true);
    v.Field(s.step, {.key = "step",
                     .unit = "m",
                     .lo = 0.05,
                     .hi = 20.0,
                     .doc = "Node spacing of the sampled centre line (rounded so that the length "
                            "is a whole number of steps).",
                     .optional = true});
    v.Field(s.closure_tolerance, {.key = "closure_tolerance",
                                  .unit = "m",
                                  .lo = 0.0,
                                  .hi = 100.0,
                                  .doc = "Largest accepted gap between end and start point before "
                                         "the closure correction.",
                                  .optional = true});
    v.Field(s.heading_tolerance, {.key = "heading_tolerance",
                                  .unit = "rad",
                                  .lo = 0.0,
                                  .hi = 1.0,
                                  .doc = "Largest accepted difference of the total turning from "
                                         "±2π before the curvature is rescaled.",
                                  .optional = true});
  }

  static void CrossCheck(const TrackParams& p, Problems& pr) {
    const std::size_t n = p.length.size();
    auto same = [&](const std::vector<double>& a, const char* key) {
      if (a.size() != n)
        pr.Add(key, "needs one value per segment (" + std::to_string(n) + " as in length), has " +
                        std::to_string(a.size()));
    };
    same(p.curvature_start, "curvature_start");
    same(p.curvature_end, "curvature_end");
    same(p.width_left, "width_left");
    same(p.width_right, "width_right");
    if (p.friction_scale.size() != 1 && p.friction_scale.size() != n)
      pr.Add("friction_scale", "needs one value or one per segment (" + std::to_string(n) +
                                   "), has " + std::to_string(p.friction_scale.size()));
  }
};

}  // namespace scw::params
