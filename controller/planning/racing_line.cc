#include "controller/planning/racing_line.h"

#include <nlopt.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "params/schema/field.h"

namespace scw::controller::planning {
namespace {

struct LineProblem {
  std::vector<double> cx, cy, nx, ny;  // base points and unit left normals
  double inv_h4 = 1.0;
  int evaluations = 0;
  std::vector<double> rx, ry;  // scratch: second differences
};

double Objective(unsigned m, const double* n, double* grad, void* data) {
  auto& p = *static_cast<LineProblem*>(data);
  ++p.evaluations;
  double j = 0.0;
  auto px = [&](unsigned i) { return p.cx[i] + n[i] * p.nx[i]; };
  auto py = [&](unsigned i) { return p.cy[i] + n[i] * p.ny[i]; };
  for (unsigned i = 0; i < m; ++i) {
    const unsigned a = (i + m - 1) % m, b = (i + 1) % m;
    p.rx[i] = px(b) - 2.0 * px(i) + px(a);
    p.ry[i] = py(b) - 2.0 * py(i) + py(a);
    j += p.rx[i] * p.rx[i] + p.ry[i] * p.ry[i];
  }
  if (grad) {
    for (unsigned i = 0; i < m; ++i) {
      const unsigned a = (i + m - 1) % m, b = (i + 1) % m;
      const double gx = p.rx[a] - 2.0 * p.rx[i] + p.rx[b], gy = p.ry[a] - 2.0 * p.ry[i] + p.ry[b];
      grad[i] = 2.0 * p.inv_h4 * (p.nx[i] * gx + p.ny[i] * gy);
    }
  }
  return j * p.inv_h4;
}

nlopt::algorithm Algorithm(const std::string& name) {
  if (name == "LD_LBFGS") return nlopt::LD_LBFGS;
  if (name == "LD_MMA") return nlopt::LD_MMA;
  if (name == "LD_SLSQP") return nlopt::LD_SLSQP;
  throw ConfigError("racing line", "algorithm",
                    "'" + name + "' is not one of LD_LBFGS, LD_MMA, LD_SLSQP");
}

const char* ResultName(nlopt::result r) {
  switch (r) {
    case nlopt::SUCCESS:
      return "success";
    case nlopt::STOPVAL_REACHED:
      return "stopval reached";
    case nlopt::FTOL_REACHED:
      return "ftol reached";
    case nlopt::XTOL_REACHED:
      return "xtol reached";
    case nlopt::MAXEVAL_REACHED:
      return "maxeval reached";
    case nlopt::MAXTIME_REACHED:
      return "maxtime reached";
    default:
      return "failure";
  }
}

plant::Track LineTrack(const std::vector<double>& x, const std::vector<double>& y,
                       const std::vector<double>& wl, const std::vector<double>& wr,
                       const std::vector<double>& mu, double step, const std::string& name,
                       const std::string& source) {
  plant::TrackBuildOptions o;
  o.step = step;
  o.smoothing = 0.0;
  return plant::Track::FromPoints(x, y, wl, wr, mu, o, name, source);
}

}  // namespace

double SquaredCurvatureIntegral(const plant::Track& path) {
  double acc = 0.0;
  for (std::size_t i = 0; i < path.size(); ++i)
    acc += path.curvature()[i] * path.curvature()[i] * path.step();
  return acc;
}

namespace {

/// The racing line through the offsets `n` of the nodes of `p` (the last step of
/// MinimumCurvatureLine, whether the offsets were optimised or known).
RacingLine BuildLine(const plant::Track& track, const LineProblem& p, const std::vector<double>& n,
                     const std::vector<double>& wl, const std::vector<double>& wr,
                     const std::vector<double>& mu, const RacingLineOptions& o, RacingLine out) {
  const std::size_t m = n.size();
  std::vector<double> x(m), y(m), lw(m), rw(m);
  for (std::size_t i = 0; i < m; ++i) {
    x[i] = p.cx[i] + n[i] * p.nx[i];
    y[i] = p.cy[i] + n[i] * p.ny[i];
    lw[i] = wl[i] - n[i];
    rw[i] = wr[i] + n[i];
  }
  out.line =
      LineTrack(x, y, lw, rw, mu, o.output_step, track.name() + " racing line", "racing line");
  return out;
}

}  // namespace

RacingLine MinimumCurvatureLine(const plant::Track& track, const RacingLineOptions& o) {
  if (!(o.step >= 0.5 && o.step <= 20.0) || !(o.margin >= 0.0) || o.max_evaluations < 1 ||
      !(o.output_step > 0.0))
    throw ConfigError("racing line", "options",
                      "need 0.5 ≤ step ≤ 20 m, margin ≥ 0, max_evaluations ≥ 1, output_step > 0");
  const auto algorithm = Algorithm(o.algorithm);
  const std::size_t m =
      std::max<std::size_t>(8, static_cast<std::size_t>(std::llround(track.length() / o.step)));
  const double h = track.length() / static_cast<double>(m);
  LineProblem p;
  p.cx.resize(m);
  p.cy.resize(m);
  p.nx.resize(m);
  p.ny.resize(m);
  p.rx.resize(m);
  p.ry.resize(m);
  p.inv_h4 = 1.0 / (h * h * h * h);
  RacingLine out{track, {}, {}, 0, 0.0, 0.0, 0.0, ""};
  out.s_centre.resize(m);
  std::vector<double> lo(m), hi(m), wl(m), wr(m), mu(m);
  for (std::size_t i = 0; i < m; ++i) {
    const double s = h * static_cast<double>(i);
    const plant::TrackPose pose = track.PoseAt(s);
    out.s_centre[i] = s;
    p.cx[i] = pose.x;
    p.cy[i] = pose.y;
    p.nx[i] = -std::sin(pose.heading);
    p.ny[i] = std::cos(pose.heading);
    wl[i] = track.WidthLeftAt(s);
    wr[i] = track.WidthRightAt(s);
    mu[i] = track.FrictionAt(s);
    lo[i] = -(wr[i] - o.margin);
    hi[i] = wl[i] - o.margin;
    if (lo[i] > hi[i])
      throw ConfigError("racing line", "margin",
                        "the track is " + params::FormatNumber(wl[i] + wr[i]) + " m wide at s = " +
                            params::FormatNumber(s) + " m, less than twice the margin " +
                            params::FormatNumber(o.margin) + " m");
  }
  std::vector<double> n(m, 0.0);
  for (std::size_t i = 0; i < m; ++i) n[i] = std::clamp(0.0, lo[i], hi[i]);
  out.objective_initial = Objective(static_cast<unsigned>(m), n.data(), nullptr, &p);

  if (o.known_offset != nullptr && o.known_offset->size() == m) {
    bool inside = true;
    for (std::size_t i = 0; i < m; ++i)
      inside = inside && (*o.known_offset)[i] >= lo[i] && (*o.known_offset)[i] <= hi[i];
    if (inside) {
      n = *o.known_offset;
      out.status = "known";
      out.objective_final = Objective(static_cast<unsigned>(m), n.data(), nullptr, &p);
      out.offset = n;
      return BuildLine(track, p, n, wl, wr, mu, o, std::move(out));
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  nlopt::opt opt(algorithm, static_cast<unsigned>(m));
  opt.set_lower_bounds(lo);
  opt.set_upper_bounds(hi);
  opt.set_min_objective(&Objective, &p);
  opt.set_maxeval(o.max_evaluations);
  opt.set_ftol_rel(o.ftol_rel);
  opt.set_xtol_abs(1e-6);
  if (algorithm == nlopt::LD_LBFGS) opt.set_vector_storage(20);
  double f = out.objective_initial;
  nlopt::result res = nlopt::FAILURE;
  try {
    res = opt.optimize(n, f);
  } catch (const nlopt::roundoff_limited&) {
    res = nlopt::SUCCESS;  // converged to machine precision: the point is usable
    f = Objective(static_cast<unsigned>(m), n.data(), nullptr, &p);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("racing line optimisation failed: ") + e.what());
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.evaluations = p.evaluations - 1;
  out.objective_final = f;
  out.status = ResultName(res);
  out.offset = n;
  return BuildLine(track, p, n, wl, wr, mu, o, std::move(out));
}

RacingLine RacingLineThrough(const plant::Track& track, const RacelinePoints& points,
                             const std::string& source, double output_step) {
  const std::size_t rows = points.a.size();
  std::vector<double> x(rows), y(rows), wl(rows), wr(rows), mu(rows);
  RacingLine out{track, {}, {}, 0, 0.0, 0.0, 0.0, "loaded from " + source};
  out.s_centre.resize(rows);
  out.offset.resize(rows);
  Problems pr;
  double hint = plant::Track::kNoHint;
  for (std::size_t i = 0; i < rows; ++i) {
    double s, n;
    if (points.cartesian) {
      x[i] = points.a[i];
      y[i] = points.b[i];
      const plant::TrackProjection q = track.Project(x[i], y[i], 0.0, hint);
      s = q.s;
      n = q.n;
      hint = s;
    } else {
      s = points.a[i];
      n = points.b[i];
      track.ToCartesian(s, n, &x[i], &y[i]);
    }
    out.s_centre[i] = s;
    out.offset[i] = n;
    wl[i] = track.WidthLeftAt(s) - n;
    wr[i] = track.WidthRightAt(s) + n;
    mu[i] = track.FrictionAt(s);
    if (!(wl[i] > 0.0 && wr[i] > 0.0))
      pr.Add("line " + std::to_string(points.rows[i]),
             "the raceline point is off the track (lateral offset " + params::FormatNumber(n) +
                 " m at s = " + params::FormatNumber(s) + " m)");
  }
  if (!pr.empty()) throw ConfigError(source, pr.items());
  out.line = LineTrack(x, y, wl, wr, mu, output_step, track.name() + " raceline", source);
  return out;
}

}  // namespace scw::controller::planning
