// Closed race track: centre line parameterised by arc length, widths, friction scaling, and the
// curvilinear (Frenet) frame (plant-and-track spec §5; issue 5 "Track").
//
// Representation. N nodes at uniform arc-length spacing ds = L/N, periodic (node N ≡ node 0):
//   s_i = i·ds [m], (x_i, y_i) [m], heading ψ_i [rad] (unwrapped, from +x anticlockwise),
//   curvature κ_i = dψ/ds [1/m] (> 0 turning left), widths w_left,i, w_right,i [m] (centre line to
//   the edge, both positive), friction scale μ_i [-]. Every per-node quantity is interpolated
//   linearly in s (Interpolate); s is wrapped into [0, L).
//
// Curvilinear coordinates of a point p = (x, y) with heading θ:
//   p = c(s) + n·N(s),   N(s) = (−sin ψ(s), cos ψ(s))   (n > 0: LEFT of the centre line)
//   heading error e_ψ = wrap(θ − ψ(s)) ∈ (−π, π].
// Between nodes i and i+1 the centre line is the chord and its tangent is blended linearly from
// T_i to T_{i+1}; the foot point solves (p − c(t))·T(t) = 0 (quadratic in t ∈ [0,1]). The normals
// at the nodes are shared by neighbouring segments, so s and n are continuous in p (no jumps at
// the vertices, unlike a plain nearest-chord projection).
//
// Construction
//   FromPoints:     sampled closed centre line (a duplicated closing point is dropped), optionally
//                   smoothed (periodic Gaussian of standard deviation `smoothing` metres), then a
//                   periodic cubic spline in chord length is resampled at uniform arc length;
//                   heading and curvature come from the spline's derivatives.
//   FromDefinition: straights/arcs/clothoids (params/schema/track_params.h). Closure correction:
//                   the total turning Θ must be within heading_tolerance of ±2π: every curvature
//                   is multiplied by ±2π/Θ. The remaining end gap d = c(L) − c(0) (≤
//                   closure_tolerance) is removed by the shift c(s) −= d·s/L; heading and curvature
//                   are those of the shifted curve (relative change O(|d|/L)), and s stays the
//                   definition's arc length (local stretch ≤ |d|/L).
//
// Thread-safety: immutable after construction; all queries are const, noexcept and allocation-free.
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "params/schema/track_params.h"

namespace scw::plant {

/// Options for Track::FromPoints.
struct TrackBuildOptions {
  double step = 1.0;  ///< node spacing target [m] (actual: L / round(L/step))
  /// Std. deviation of the periodic Gaussian smoothing of x, y [m]. Public centre lines carry
  /// cm-level noise that the curvature amplifies (±0.01 1/m at 2 m spacing); 2 m removes it
  /// while changing a 30 m radius by about 1 %.
  double smoothing = 2.0;
  /// Largest accepted gap between the last and the first input point [m]; negative: 5 × the
  /// median input spacing.
  double closure_tolerance = -1.0;
  /// The source line (1-based) of each input point, when the points are a file's rows: problems
  /// then name `line L` instead of `point K`, and an open loop names its last and first rows.
  std::vector<int> source_lines;
};

/// Curvilinear coordinates of a point (see the header comment).
struct TrackProjection {
  double s = 0.0;              ///< arc length of the foot point, in [0, L) [m]
  double n = 0.0;              ///< lateral offset, > 0 left of the centre line [m]
  double heading_error = 0.0;  ///< heading − ψ(s), wrapped to (−π, π] [rad]
  std::size_t segment = 0;     ///< index of the segment [s_i, s_{i+1}) of the foot point
};

/// Pose of the centre line at s.
struct TrackPose {
  double x = 0.0, y = 0.0;  ///< [m]
  double heading = 0.0;     ///< [rad], unwrapped (continuous over the lap, wraps by ±2π at L)
  double curvature = 0.0;   ///< [1/m]
};

class Track {
 public:
  static constexpr double kNoHint = std::numeric_limits<double>::quiet_NaN();

  /// Samples x, y (and per-sample widths, friction; `mu` may be empty = 1) of a closed loop in
  /// driving order. Throws ConfigError(`source`, …) on too few points (< 8), non-finite values,
  /// non-positive widths, repeated points or a loop that does not close.
  static Track FromPoints(const std::vector<double>& x, const std::vector<double>& y,
                          const std::vector<double>& width_left,
                          const std::vector<double>& width_right, const std::vector<double>& mu,
                          const TrackBuildOptions& options, const std::string& name,
                          const std::string& source);

  /// Integrates a piecewise definition (validated first). Throws ConfigError naming the
  /// definition when it does not close within its tolerances.
  static Track FromDefinition(const params::TrackParams& def, const std::string& source = "");

  const std::string& name() const { return name_; }
  double length() const { return length_; }
  double step() const { return ds_; }
  /// Number of distinct nodes N (the arrays below hold N + 1 entries, the last equal to the first
  /// up to the heading's 2π).
  std::size_t size() const { return n_; }
  const std::vector<double>& s() const { return s_; }
  const std::vector<double>& x() const { return x_; }
  const std::vector<double>& y() const { return y_; }
  const std::vector<double>& heading() const { return psi_; }
  const std::vector<double>& curvature() const { return kappa_; }
  const std::vector<double>& width_left() const { return wl_; }
  const std::vector<double>& width_right() const { return wr_; }
  const std::vector<double>& friction() const { return mu_; }
  /// Total turning ψ(L) − ψ(0): +2π anticlockwise, −2π clockwise [rad].
  double total_turning() const { return psi_[n_] - psi_[0]; }
  /// FromDefinition: end gap removed by the closure correction [m] (0 for FromPoints).
  double closure_gap() const { return closure_gap_; }

  /// s wrapped into [0, L).
  double Wrap(double s) const noexcept;
  /// Linear interpolation in s of a per-node quantity with N or N + 1 entries (periodic).
  double Interpolate(const std::vector<double>& values, double s) const noexcept;

  TrackPose PoseAt(double s) const noexcept;
  double CurvatureAt(double s) const noexcept { return Interpolate(kappa_, s); }
  double WidthLeftAt(double s) const noexcept { return Interpolate(wl_, s); }
  double WidthRightAt(double s) const noexcept { return Interpolate(wr_, s); }
  double FrictionAt(double s) const noexcept { return Interpolate(mu_, s); }
  /// Patches of other grip the track file declares (params/schema/friction_patch_params.h; none
  /// for centre-line CSV tracks). plant/track/road_surface.h evaluates them.
  const params::FrictionPatches& friction_patches() const { return patches_; }

  /// Point at arc length s and lateral offset n (> 0 left).
  void ToCartesian(double s, double n, double* x, double* y) const noexcept;

  /// Curvilinear coordinates of (x, y, heading). With a finite `s_hint` (e.g. the previous
  /// step's s) a local walk from the hint's segment is tried first (O(1) per call); the global
  /// search over all segments runs when there is no hint or the walk does not end within
  /// `local_radius` metres of the centre line. Pure, noexcept, no allocation.
  TrackProjection Project(double x, double y, double heading = 0.0, double s_hint = kNoHint,
                          double local_radius = 30.0) const noexcept;

 private:
  Track() = default;
  static Track FromNodes(std::vector<double> x, std::vector<double> y, std::vector<double> psi,
                         std::vector<double> kappa, std::vector<double> wl, std::vector<double> wr,
                         std::vector<double> mu, double length, std::string name);
  // Foot point on segment i if p lies between the node normals of i and i+1; returns false
  // otherwise. *t ∈ [0,1], *dist2 squared distance to the foot point.
  bool SegmentFoot(std::size_t i, double px, double py, double* t, double* dist2) const noexcept;
  TrackProjection Finish(std::size_t i, double t, double px, double py,
                         double heading) const noexcept;

  std::string name_;
  std::size_t n_ = 0;
  double length_ = 0.0, ds_ = 0.0, closure_gap_ = 0.0;
  std::vector<double> s_, x_, y_, psi_, kappa_, wl_, wr_, mu_, tx_, ty_;
  params::FrictionPatches patches_{};
};

}  // namespace scw::plant
