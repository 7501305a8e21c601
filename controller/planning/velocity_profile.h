// Reference trajectory along a path: the velocity profile of the forward–backward g-g-v method
// (plant-and-track spec §6.1, TUM trajectory_planning_helpers; our own implementation).
//
// Path: the nodes of a plant::Track (uniform step ds, curvature κ_i, friction scale μ_i), usually
// the racing line (controller/planning/racing_line.h) or a centre line. With g = gg_scale:
//   1. Speed cap v_lim,i = the smallest v > 0 with v²|κ_i| = g·μ_i·ay_max(v) (first crossing,
//      so downforce — ay_max growing with v — is handled exactly), clipped to v_max.
//   2. Forward pass (accelerating): v_{i+1} = the largest w ≤ v_lim,{i+1} with
//        (w² − v_i²) / (2 ds) ≤ min(A(v_i, κ_i, μ_i), A(w, κ_{i+1}, μ_{i+1})),
//        A(v, κ, μ) = g·ax_drive_max(v)·C(v²|κ|, g·μ·ay_max(v)),  C = (1 − r^p)^(1/p)
//      i.e. the segment's mean acceleration respects the g-g-v limit at BOTH ends (solved by
//      bisection, so the result never exceeds the limits, unlike a one-sided explicit step).
//   3. Backward pass (braking) likewise with B(v, κ, μ) = g·μ·ax_brake_max(v)·C(·).
//   4. Closed path: both passes start at the node with the lowest cap (an apex whose speed is its
//      cap) and run once around, so v is periodic by construction; open path: v_0 = v_start.
//   v_i = min(forward_i, backward_i).
// Outputs per node: a_x,i = (v_{i+1}² − v_i²)/(2 ds) (the acceleration of the segment that starts
// at node i; the last node repeats the first on a closed path), a_y,i = v_i² κ_i, t by
// Δt = 2 ds/(v_i + v_{i+1}). Lap time = t at the end of the last segment.
// Drag: GgvTable's drive limit is net of drag and its braking limit includes it
// (controller/planning/ggv.h), so no extra drag term appears here.
#pragma once

#include <string>
#include <vector>

#include "controller/planning/ggv.h"
#include "plant/track/track.h"

namespace scw::controller::planning {

struct VelocityProfileOptions {
  double gg_scale = 1.0;  ///< the paper's acceleration scaling GG (multiplies every limit) [-]
  double v_max = 90.0;    ///< top speed [m/s]
  double v_min = 1.0;     ///< floor of the cap (keeps t finite on degenerate input) [m/s]
  bool closed = true;     ///< closed lap (periodic profile) or open path from v_start
  double v_start = 0.0;   ///< open path: initial speed [m/s]
};

/// One sample of the reference trajectory.
struct TrajectorySample {
  double s = 0.0, x = 0.0, y = 0.0, psi = 0.0, kappa = 0.0;  ///< [m], [m], [m], [rad], [1/m]
  double v = 0.0, a_x = 0.0, a_y = 0.0, t = 0.0;             ///< [m/s], [m/s^2], [m/s^2], [s]
};

/// Reference trajectory at the path nodes (N + 1 samples on a closed path: the last repeats the
/// first at s = L, t = lap time). Arrays all have the same length.
struct ReferenceTrajectory {
  std::vector<double> s, x, y, psi, kappa, v, a_x, a_y, t;
  double length = 0.0;    ///< path length [m]
  double lap_time = 0.0;  ///< ideal lap (or path) time [s]
  bool closed = true;

  std::size_t size() const { return s.size(); }
  /// Linear interpolation at arc length s (wrapped on a closed path, clamped on an open one).
  TrajectorySample At(double s_query) const noexcept;
};

/// Velocity profile on the nodes of `path`. Throws ConfigError if `limits` are invalid.
ReferenceTrajectory ComputeVelocityProfile(const plant::Track& path, const GgvTable& limits,
                                           const VelocityProfileOptions& options = {});

/// A representative g-g-v table of the default car (AV-21/EAV class, spec §4.2/§4.4): lateral
/// limit growing with downforce from 20 to 30 m/s², power-limited drive, braking 15 → 31 m/s²,
/// p = 1.6. Used by `scw track line` when no table is given and by the tests.
GgvTable RepresentativeGgv();

}  // namespace scw::controller::planning
