// Patches of different grip on the track surface (a wet or oily patch in a braking zone, a damp
// line at a corner exit, one side of the track only: μ-split). Declared in a track file, where they
// belong to the track, or in a scenario, where they are the scenario's event; the scenario's add
// to the track's. Each patch i covers arc lengths s ∈ [start[i], end[i]) (end < start wraps over
// the start line) and lateral offsets n ∈ [n_min[i], n_max[i]] from the centre line (> 0 left), and
// multiplies the friction of the surface there by factor[i]. A wheel on a patch gets
// μ(s, n) = friction_scale(s) × Π factor of the patches covering its contact point
// (plant::Environment, filled by the closed loop at every plant step).
#pragma once

#include <string>
#include <vector>

#include "params/schema/field.h"

namespace scw::params {

struct FrictionPatches {
  std::vector<double> start{};
  std::vector<double> end{};
  std::vector<double> n_min{};
  std::vector<double> n_max{};
  std::vector<double> factor{};

  bool empty() const { return start.empty(); }

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.start, {.key = "start",
                      .unit = "m",
                      .lo = 0.0,
                      .hi = 1e5,
                      .doc = "Arc length where each patch begins (along the track's centre line).",
                      .optional = true,
                      .min_size = 0});
    v.Field(s.end, {.key = "end",
                    .unit = "m",
                    .lo = 0.0,
                    .hi = 1e5,
                    .doc = "Arc length where each patch ends (< start: the patch spans the start "
                           "line).",
                    .optional = true,
                    .min_size = 0});
    v.Field(s.n_min, {.key = "n_min",
                      .unit = "m",
                      .lo = -100.0,
                      .hi = 100.0,
                      .doc = "Right edge of each patch: lateral offset from the centre line (> 0 "
                             "left; -100 = the whole width to the right).",
                      .optional = true,
                      .min_size = 0});
    v.Field(s.n_max, {.key = "n_max",
                      .unit = "m",
                      .lo = -100.0,
                      .hi = 100.0,
                      .doc = "Left edge of each patch: lateral offset from the centre line (> 0 "
                             "left; 100 = the whole width to the left).",
                      .optional = true,
                      .min_size = 0});
    v.Field(s.factor, {.key = "factor",
                       .unit = "-",
                       .lo = 0.05,
                       .hi = 2.0,
                       .doc = "Friction multiplier on each patch (wet asphalt ≈ 0.6, oil ≈ 0.3).",
                       .optional = true,
                       .min_size = 0});
  }

  static void CrossCheck(const FrictionPatches& p, Problems& pr) {
    const std::size_t n = p.start.size();
    auto same = [&](const std::vector<double>& a, const char* key) {
      if (a.size() != n)
        pr.Add(key, "needs one value per patch (" + std::to_string(n) + " as in start), has " +
                        std::to_string(a.size()));
    };
    same(p.end, "end");
    same(p.n_min, "n_min");
    same(p.n_max, "n_max");
    same(p.factor, "factor");
    for (std::size_t i = 0; i < n && i < p.n_min.size() && i < p.n_max.size(); ++i)
      if (!(p.n_min[i] < p.n_max[i]))
        pr.Add("n_max", "patch " + std::to_string(i) + ": n_max must be above n_min");
    for (std::size_t i = 0; i < n && i < p.end.size(); ++i)
      if (p.start[i] == p.end[i])
        pr.Add("end", "patch " + std::to_string(i) + ": end equals start (an empty patch)");
  }
};

}  // namespace scw::params
