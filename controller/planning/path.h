// Reference path of the motion controllers: a closed (periodic in s) racing line with its speed
// and acceleration profile, sampled at arc-length stations. Planning builds it once per scenario
// (PrepareReference, controller/planning/reference.h); every motion controller and thread shares
// it read-only (controller/motion/path.h names it in scw::controller::motion).
//
// Conventions: s [m] arc length along the line, wrapped into [0, length); x, y [m] world frame;
// psi [rad] heading of the line; kappa [1/m] > 0 turning left; v [m/s] target speed; a_x [m/s²]
// target longitudinal acceleration. Lateral error n > 0: the point lies LEFT of the line.
#pragma once

#include <cstddef>
#include <vector>

namespace scw::controller::planning {

struct PathPoint {
  double s = 0.0, x = 0.0, y = 0.0, psi = 0.0, kappa = 0.0, v = 0.0, a_x = 0.0;
  /// Exact, member by member (bit-for-bit comparisons of prepared references).
  bool operator==(const PathPoint&) const = default;
};

struct PathProjection {
  double s = 0.0;              ///< [m] arc length of the closest point
  double lateral_error = 0.0;  ///< [m] signed distance, > 0 left of the line
  double heading_error = 0.0;  ///< [rad] vehicle heading − line heading, wrapped to (−π, π]
  std::size_t segment = 0;     ///< index of the segment [i, i+1] holding the closest point
};

class Path {
 public:
  /// Stations must be strictly increasing in s, starting at 0; the line closes from the last
  /// station back to the first over `length` − s_last; all of x, y, psi, kappa, v, a_x finite.
  /// Throws scw::ConfigError (source "reference path") otherwise.
  Path(std::vector<PathPoint> points, double length);

  double length() const noexcept { return length_; }
  std::size_t size() const noexcept { return points_.size(); }
  const std::vector<PathPoint>& points() const noexcept { return points_; }

  /// s wrapped into [0, length).
  double Wrap(double s) const noexcept;
  /// Linear interpolation of every field at s (wrapped; heading interpolated on the circle).
  PathPoint Sample(double s) const noexcept;
  /// Closest point to (x, y). With a finite `s_hint` only segments within ±`window` metres of the
  /// hint are searched (O(window)), otherwise all. Allocation-free.
  PathProjection Project(double x, double y, double psi, double s_hint = -1.0,
                         double window = 60.0) const noexcept;

 private:
  std::size_t SegmentAt(double s) const noexcept;
  std::vector<PathPoint> points_;
  // Segment k (station k to k + 1; the last one closes the loop) as Project scans it, one array
  // per quantity: start point, direction b − a and its squared length (the scan's own
  // expressions, computed once).
  std::vector<double> seg_ax_, seg_ay_, seg_ex_, seg_ey_, seg_len2_;
  // Blocks of kBlock consecutive segments (block b: segments kBlock·b …), each inside the circle
  // (blk_cx_, blk_cy_) of radius blk_r_: Project skips a block no point of which can beat the
  // closest segment found so far.
  static constexpr std::size_t kBlock = 8;
  std::vector<double> blk_cx_, blk_cy_, blk_r_;
  double length_;
  double mean_ds_;
};

double WrapAngle(double a) noexcept;

}  // namespace scw::controller::planning
