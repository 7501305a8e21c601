// The grip of the road surface at any point of the track: the track's friction_scale(s) times the
// factors of the friction patches covering the point (params/schema/friction_patch_params.h), and
// the friction under each wheel of a car on the track (plant::Environment).
//
// A wheel's contact point is placed from the car's projection onto the centre line (s, n, heading
// error ε) and the wheel's body-frame offset (p_x forward, p_y left) from the CoG:
//   n_w = n + p_x sin ε + p_y cos ε,   s_w = s + (p_x cos ε − p_y sin ε) / (1 − κ(s) n),
// exact for a straight centre line and within millimetres for the corners of a race track
// (offsets ≤ 2 m, radii ≥ 15 m).
//
// Thread-safety: immutable after construction; queries are const, noexcept, allocation-free.
#pragma once

#include <vector>

#include "params/schema/friction_patch_params.h"
#include "plant/track/track.h"
#include "plant/vehicle/environment.h"

namespace scw::plant {

class RoadSurface {
 public:
  /// The surface of `track` (its friction_scale and its own patches) plus the `extra` patches (a
  /// scenario's). `track` must outlive this object. `extra` must be valid (params::Validate).
  explicit RoadSurface(const Track& track, const params::FrictionPatches& extra = {});

  /// Friction 1 everywhere (no patches, friction_scale 1): the default Environment is exact.
  bool uniform() const noexcept { return uniform_; }

  /// Friction factor at arc length s (wrapped) and lateral offset n (> 0 left).
  double FrictionAt(double s, double n) const noexcept;

  /// Friction under each wheel of a car projected to `p`, with contact points offset by
  /// (px[i], py[i]) from the CoG in the body frame [m].
  Environment UnderWheels(const TrackProjection& p, const PerWheel<double>& px,
                          const PerWheel<double>& py) const noexcept;

 private:
  struct Patch {
    double start, end, n_min, n_max, factor;
  };
  const Track* track_;
  std::vector<Patch> patches_;
  bool uniform_ = true;
};

}  // namespace scw::plant
