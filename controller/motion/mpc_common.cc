#include "controller/motion/mpc_common.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "controller/motion/nlp_solver.h"

namespace scw::controller::motion {

Problems ValidateMpcInputs(const Path* path, const GgTable& limits, const Corridor& corridor) {
  Problems pr;
  if (path == nullptr) pr.Add("path", "is missing (the controller follows a reference path)");
  try {
    limits.Validate();
  } catch (const ConfigError& e) {
    for (const Problem& p : e.problems()) pr.Add(params::JoinKey("limits", p.path), p.message);
  }
  if (path != nullptr) {
    const auto sized = [&](const std::vector<double>& v, const char* key) {
      if (v.size() != path->size())
        pr.Add(key, "needs one entry per path station (" + std::to_string(path->size()) +
                        "), has " + std::to_string(v.size()));
    };
    sized(corridor.left, "corridor.left");
    sized(corridor.right, "corridor.right");
  }
  return pr;
}

double InterpolateStations(const Path& path, const std::vector<double>& values, double s) noexcept {
  const auto& pts = path.points();
  const std::size_t n = pts.size();
  if (values.size() != n || n == 0) return 0.0;
  s = path.Wrap(s);
  const auto it = std::upper_bound(pts.begin(), pts.end(), s,
                                   [](double a, const PathPoint& p) { return a < p.s; });
  const std::size_t i = it == pts.begin() ? 0 : static_cast<std::size_t>(it - pts.begin()) - 1;
  const std::size_t j = i + 1 < n ? i + 1 : 0;
  const double s1 = i + 1 < n ? pts[j].s : path.length();
  const double w = s1 > pts[i].s ? std::clamp((s - pts[i].s) / (s1 - pts[i].s), 0.0, 1.0) : 0.0;
  return values[i] + w * (values[j] - values[i]);
}

void SolveStats::Add(double seconds) noexcept {
  if (!times_.empty())
    times_[static_cast<std::size_t>(count_ % static_cast<std::int64_t>(times_.size()))] = seconds;
  ++count_;
  max_ = std::max(max_, seconds);
  sum_ += seconds;
}

double SolveStats::Quantile(double q) const {
  const std::size_t n =
      static_cast<std::size_t>(std::min<std::int64_t>(count_, std::ssize(times_)));
  if (n == 0) return 0.0;
  std::vector<double> v(times_.begin(), times_.begin() + static_cast<std::ptrdiff_t>(n));
  const std::size_t k =
      std::min(n - 1, static_cast<std::size_t>(std::clamp(q, 0.0, 1.0) * static_cast<double>(n)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

double SolveStats::Median() const { return Quantile(0.5); }

double MeanCurvature(const Path& path, double s0, double s1) noexcept {
  const double ds = s1 - s0;
  if (ds < 0.5) return path.Sample(s0).kappa;
  return WrapAngle(path.Sample(s1).psi - path.Sample(s0).psi) / ds;
}

MpcController::MpcController(GgTable limits, Corridor corridor, std::shared_ptr<const Path> path)
    : limits_(std::move(limits)), corridor_(std::move(corridor)), path_(std::move(path)) {}

double MpcController::CorridorLeft(double s) const noexcept {
  return InterpolateStations(*path_, corridor_.left, s);
}
double MpcController::CorridorRight(double s) const noexcept {
  return InterpolateStations(*path_, corridor_.right, s);
}

void MpcController::CorridorBounds(double s, double margin, double* lo, double* up) const noexcept {
  *up = CorridorLeft(s) - margin;
  *lo = -(CorridorRight(s) - margin);
  if (*up < *lo) *up = *lo = 0.5 * (*up + *lo);
}

PathProjection MpcController::Locate(const MotionInput& in, double window, MotionState* st,
                                     MotionOutput* out, PathPoint* ref) const noexcept {
  const PathProjection here = MatchOnPath(*path_, in, window, st, out);
  *ref = path_->Sample(here.s);
  out->v_target = ref->v;
  return here;
}

bool MpcController::TimedSolve(NlpSolver* solver, SparseNlp* nlp, MpcDiagnostics* d) {
  NlpResult res;
  {
    ScopedSolveTimer timer(&d->solve_time);
    res = solver->Solve(nlp);
  }
  ++d->solves;
  d->iterations += res.iterations;
  d->last_status = res.status;
  return res.usable;
}

}  // namespace scw::controller::motion
