#include "controller/planning/late_braking.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "params/schema/field.h"

namespace scw::controller::planning {
namespace {

/// Forward distance from a to b on a loop of length L, in [0, L).
double Ahead(double a, double b, double length) {
  double d = std::fmod(b - a, length);
  if (d < 0.0) d += length;
  return d;
}

}  // namespace

double PlaceOn(const plant::Track& track, const std::vector<plant::Corner>& corners, double corner,
               double s, const std::string& key, std::size_t index) {
  const int k = static_cast<int>(corner);
  if (k <= 0) return track.Wrap(s);
  if (static_cast<std::size_t>(k) > corners.size())
    throw ConfigError("", key + ".corner",
                      "element [" + std::to_string(index) + "] = " + std::to_string(k) +
                          ": the track '" + track.name() + "' has " +
                          std::to_string(corners.size()) + " corners (scw track info)");
  return track.Wrap(corners[static_cast<std::size_t>(k - 1)].s_apex + s);
}

double EventPlace(const plant::Track& track, double corner, double s, const std::string& key,
                  std::size_t index) {
  return PlaceOn(track, corner > 0.0 ? plant::FindCorners(track) : std::vector<plant::Corner>{},
                 corner, s, key, index);
}

Path LateBrakingPath(const Path& path, const params::LateBraking& late, const plant::Track& track) {
  std::vector<PathPoint> pts = path.points();
  const std::size_t n = pts.size();
  const double length = path.length();
  if (late.s.empty() || n < 3) return path;

  // Braking zones of the original profile: maximal runs of falling speed, scanned from the
  // fastest point (which no zone contains) so that none is split at the start line.
  struct Zone {
    std::size_t b, a;  // brake point and slowest point (indices, a after b going forward)
  };
  std::vector<Zone> zones;
  const std::size_t top = static_cast<std::size_t>(
      std::max_element(pts.begin(), pts.end(),
                       [](const PathPoint& x, const PathPoint& y) { return x.v < y.v; }) -
      pts.begin());
  for (std::size_t k = 0; k < n;) {
    const std::size_t i = (top + k) % n, j = (top + k + 1) % n;
    if (!(pts[j].v < pts[i].v)) {
      ++k;
      continue;
    }
    std::size_t end = k + 1;
    while (end < n && pts[(top + end + 1) % n].v < pts[(top + end) % n].v) ++end;
    const std::size_t b = i, a = (top + end) % n;
    if (pts[b].v - pts[a].v > 1.0) zones.push_back({b, a});  // ignore ripples below 1 m/s
    k = end;
  }
  auto unwrapped = [&](std::size_t from, std::size_t to) {
    return Ahead(pts[from].s, pts[to].s, length);
  };

  const std::vector<plant::Corner> corners = plant::FindCorners(track);
  const std::vector<PathPoint> original = pts;
  const Path original_path(original, length);
  for (std::size_t e = 0; e < late.s.size(); ++e) {
    if (zones.empty()) break;
    const double s_track =
        PlaceOn(track, corners, late.corner[e], late.s[e], "events.late_braking", e);
    const auto pose = track.PoseAt(s_track);
    const double s_path = path.Project(pose.x, pose.y, pose.heading).s;
    const Zone* best = nullptr;
    double best_d = std::numeric_limits<double>::infinity();
    for (const Zone& z : zones) {
      const double d =
          std::min(Ahead(s_path, pts[z.a].s, length), Ahead(pts[z.a].s, s_path, length));
      if (d < best_d) {
        best_d = d;
        best = &z;
      }
    }
    const double zone_len = unwrapped(best->b, best->a);
    const double shift = std::min(late.distance[e], 0.8 * zone_len);
    if (!(shift > 0.0)) continue;
    const double v_entry = original[best->b].v;
    for (std::size_t i = best->b;; i = (i + 1) % n) {
      const double x = unwrapped(best->b, i);
      if (x <= shift) {
        pts[i].v = v_entry;
      } else {
        const double sigma = pts[best->b].s + (x - shift) * zone_len / (zone_len - shift);
        pts[i].v = original_path.Sample(sigma).v;
      }
      if (i == best->a) break;
    }
    // a_x = d(v²/2)/ds over the zone (forward differences), ending at the slowest point.
    for (std::size_t i = best->b; i != best->a; i = (i + 1) % n) {
      const std::size_t j = (i + 1) % n;
      const double ds = unwrapped(i, j);
      if (ds > 0.0) pts[i].a_x = (pts[j].v * pts[j].v - pts[i].v * pts[i].v) / (2.0 * ds);
    }
  }
  return Path(std::move(pts), length);
}

}  // namespace scw::controller::planning
