#include "controller/planning/corridor.h"

#include <algorithm>

#include "plant/track/track.h"

namespace scw::controller::planning {

Corridor MakeCorridor(const plant::Track& track, const Path& path, double cap) {
  Corridor c;
  double hint = plant::Track::kNoHint;
  for (const auto& p : path.points()) {
    const auto tp = track.Project(p.x, p.y, p.psi, hint);
    hint = tp.s;
    const double left = track.WidthLeftAt(tp.s) - tp.n;
    const double right = track.WidthRightAt(tp.s) + tp.n;
    c.left.push_back(std::clamp(left, 0.0, cap));
    c.right.push_back(std::clamp(right, 0.0, cap));
  }
  return c;
}

}  // namespace scw::controller::planning
