// Racing line: minimum curvature within the track bounds (plant-and-track spec §6.1, the
// "minimum curvature" path of TUM's global trajectory optimisation; our own formulation), or a
// given raceline file.
//
// Minimum curvature. The centre line is resampled at `step` (nodes c_i, left normals N_i,
// i = 0…M−1, periodic); the line is p_i = c_i + n_i N_i with lateral offsets n_i bounded by
//   −(w_right,i − margin) ≤ n_i ≤ w_left,i − margin.
// Objective: the discrete squared curvature  J(n) = Σ_i |p_{i+1} − 2 p_i + p_{i−1}|² / h⁴
// (h = step: |Δ²p|/h² ≈ |κ| for a uniformly parameterised line), a convex quadratic in n with the
// analytic gradient ∂J/∂n_j = (2/h⁴) N_j·(r_{j−1} − 2 r_j + r_{j+1}), r_i = Δ²p_i. Minimised by
// NLopt (LD_LBFGS with bounds, or LD_MMA / LD_SLSQP). Δ²p/h² is the curvature of a uniformly
// spaced line; where the offsets change the spacing it also penalises that tangential change,
// which keeps the line evenly parameterised. The line is then a plant::Track (spline-resampled;
// widths = distance to the original edges), ready for the velocity profile.
//
// Given line. The points of a raceline file (read by tuning/sim/track_csv.h: `x_m,y_m` of the
// racetrack-database racelines or `s_opt,n_opt` of TUMRT's global racing lines, the offset n from
// the reference line at its arc length s) placed on the track (RacingLineThrough).
#pragma once

#include <string>
#include <vector>

#include "plant/track/track.h"

namespace scw::controller::planning {

struct RacingLineOptions {
  double step = 3.0;    ///< node spacing of the optimisation [m]
  double margin = 2.0;  ///< distance kept from each edge (half car width + safety) [m]
  std::string algorithm = "LD_LBFGS";  ///< LD_LBFGS | LD_MMA | LD_SLSQP (small problems only)
  int max_evaluations = 50000;
  double ftol_rel = 1e-9;    ///< relative change of J that ends the search
  double output_step = 1.0;  ///< node spacing of the returned line [m]
  /// The optimisation's known result (the `offset` of an earlier call with the same track and
  /// options, e.g. from the preparation cache): used instead of optimising when it has one value
  /// per node, each within the bounds; otherwise ignored. The line built from it is bit for bit
  /// the one the optimisation gave.
  const std::vector<double>* known_offset = nullptr;
};

struct RacingLine {
  plant::Track line;               ///< the racing line as a path (its own s, κ, widths to edges)
  std::vector<double> s_centre;    ///< centre-line arc length of each optimisation node [m]
  std::vector<double> offset;      ///< lateral offset n_i from the centre line (> 0 left) [m]
  int evaluations = 0;             ///< objective/gradient evaluations
  double seconds = 0.0;            ///< wall time of the optimisation (report only) [s]
  double objective_initial = 0.0;  ///< J of the centre line [1/m²·node]
  double objective_final = 0.0;    ///< J of the result
  std::string status;              ///< NLopt result code name
};

/// Minimum-curvature line within `track`'s bounds. Throws ConfigError on bad options or when the
/// track is narrower than 2·margin somewhere; std::runtime_error if NLopt fails outright.
RacingLine MinimumCurvatureLine(const plant::Track& track, const RacingLineOptions& options = {});

/// The points of a given line, as read from a raceline file: either world coordinates (x, y) or
/// curvilinear ones (s along the track's centre line, n > 0 left of it), one per file row.
struct RacelinePoints {
  bool cartesian = true;     ///< a = x, b = y [m]; otherwise a = s, b = n [m]
  std::vector<double> a, b;  ///< equal lengths, ≥ 8 points
  std::vector<int> rows;     ///< the file line of each point (for errors)
};

/// The line through `points` relative to `track` (widths = distance to the track's edges),
/// resampled at `output_step`. Throws ConfigError(`source`, "line N", ...) for every point off the
/// track.
RacingLine RacingLineThrough(const plant::Track& track, const RacelinePoints& points,
                             const std::string& source, double output_step = 1.0);

/// Σ κ_i² ds over the nodes of a path [1/m]: the curvature measure compared in the tests.
double SquaredCurvatureIntegral(const plant::Track& path);

}  // namespace scw::controller::planning
