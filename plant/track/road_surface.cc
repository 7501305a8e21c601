#include "plant/track/road_surface.h"

#include <cmath>

namespace scw::plant {

RoadSurface::RoadSurface(const Track& track, const params::FrictionPatches& extra)
    : track_(&track) {
  for (const params::FrictionPatches* set : {&track.friction_patches(), &extra})
    for (std::size_t i = 0; i < set->start.size(); ++i)
      patches_.push_back({track.Wrap(set->start[i]), track.Wrap(set->end[i]), set->n_min[i],
                          set->n_max[i], set->factor[i]});
  uniform_ = patches_.empty();
  for (const double mu : track.friction())
    if (mu != 1.0) uniform_ = false;
}

double RoadSurface::FrictionAt(double s, double n) const noexcept {
  s = track_->Wrap(s);
  double mu = track_->FrictionAt(s);
  for (const Patch& p : patches_) {
    const bool along = p.start < p.end ? (s >= p.start && s < p.end) : (s >= p.start || s < p.end);
    if (along && n >= p.n_min && n <= p.n_max) mu *= p.factor;
  }
  return mu;
}

Environment RoadSurface::UnderWheels(const TrackProjection& p, const PerWheel<double>& px,
                                     const PerWheel<double>& py) const noexcept {
  Environment env;
  if (uniform_) return env;
  const double c = std::cos(p.heading_error), sn = std::sin(p.heading_error);
  const double stretch = 1.0 - track_->CurvatureAt(p.s) * p.n;
  const double inv_stretch = stretch > 0.1 ? 1.0 / stretch : 10.0;
  for (std::size_t i = 0; i < 4; ++i) {
    const double n_w = p.n + px[i] * sn + py[i] * c;
    const double s_w = p.s + (px[i] * c - py[i] * sn) * inv_stretch;
    env.mu[i] = FrictionAt(s_w, n_w);
  }
  return env;
}

}  // namespace scw::plant
