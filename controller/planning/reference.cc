#include "controller/planning/reference.h"

#include <utility>
#include <vector>

#include "controller/planning/late_braking.h"
#include "controller/planning/velocity_profile.h"
#include "params/schema/field.h"

namespace scw::controller::planning {
namespace {

std::shared_ptr<const plant::Track> LineOf(const plant::Track& track, const ReferenceOptions& o,
                                           ReferenceCache& cache) {
  switch (o.line) {
    case LineKind::kCentreLine:
      return std::make_shared<const plant::Track>(track);
    case LineKind::kGiven:
      if (!o.given_line) throw ConfigError(o.source, "motion.raceline", "no given line");
      return std::make_shared<const plant::Track>(
          RacingLineThrough(track, *o.given_line, o.given_source).line);
    case LineKind::kOptimal:
      break;
  }
  return cache.OptimalLine(track, o.line_margin);
}

std::shared_ptr<const Path> ToPath(const ReferenceTrajectory& r) {
  std::vector<PathPoint> pts(r.size());
  for (std::size_t i = 0; i < r.size(); ++i)
    pts[i] = {r.s[i], r.x[i], r.y[i], r.psi[i], r.kappa[i], r.v[i], r.a_x[i]};
  // The velocity profile may repeat the closing node at s = length: drop it.
  while (pts.size() > 3 && pts.back().s >= r.length) pts.pop_back();
  return std::make_shared<Path>(std::move(pts), r.length);
}

}  // namespace

PreparedReference PrepareReference(const plant::Track& track, const params::VehicleParams& vehicle,
                                   const ReferenceOptions& options, ReferenceCache& cache) {
  PreparedReference out;
  out.line = LineOf(track, options, cache);
  out.ggv = cache.PlantGgv(vehicle, options.brake_bias_front);
  VelocityProfileOptions vo;
  vo.gg_scale = options.limit_scale;
  const ReferenceTrajectory ref = ComputeVelocityProfile(*out.line, *out.ggv, vo);
  out.path = ToPath(ref);
  if (!options.late_braking.s.empty()) {
    try {
      out.path =
          std::make_shared<const Path>(LateBrakingPath(*out.path, options.late_braking, track));
    } catch (const ConfigError& e) {
      throw ConfigError(options.source, e.problems());
    }
  }
  out.ideal_lap_time = ref.lap_time;
  out.limit_lap_time = cache.LimitLapTime(*out.line, *out.ggv);
  return out;
}

}  // namespace scw::controller::planning
