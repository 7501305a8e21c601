#include "plant/track/track.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "params/schema/field.h"

namespace scw::plant {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

double WrapAngle(double a) noexcept {
  a = std::remainder(a, kTwoPi);
  return a <= -std::numbers::pi ? a + kTwoPi : a;
}

std::string Num(double x) { return params::FormatNumber(x); }

// Solves the cyclic tridiagonal system a_i x_{i-1} + b_i x_i + c_i x_{i+1} = r_i (indices mod m)
// by the Sherman-Morrison correction of the plain Thomas algorithm. m ≥ 3, diagonally dominant.
std::vector<double> SolveCyclic(const std::vector<double>& a, const std::vector<double>& b,
                                const std::vector<double>& c, const std::vector<double>& r) {
  const std::size_t m = b.size();
  const double alpha = c[m - 1], beta = a[0], gamma = -b[0];
  std::vector<double> bb(b);
  bb[0] = b[0] - gamma;
  bb[m - 1] = b[m - 1] - alpha * beta / gamma;
  auto thomas = [&](std::vector<double> rhs) {
    std::vector<double> cp(m), x(m);
    cp[0] = c[0] / bb[0];
    rhs[0] /= bb[0];
    for (std::size_t i = 1; i < m; ++i) {
      const double den = bb[i] - a[i] * cp[i - 1];
      cp[i] = c[i] / den;
      rhs[i] = (rhs[i] - a[i] * rhs[i - 1]) / den;
    }
    x[m - 1] = rhs[m - 1];
    for (std::size_t i = m - 1; i-- > 0;) x[i] = rhs[i] - cp[i] * x[i + 1];
    return x;
  };
  std::vector<double> x = thomas(r);
  std::vector<double> u(m, 0.0);
  u[0] = gamma;
  u[m - 1] = alpha;
  const std::vector<double> z = thomas(u);
  const double fact = (x[0] + beta * x[m - 1] / gamma) / (1.0 + z[0] + beta * z[m - 1] / gamma);
  for (std::size_t i = 0; i < m; ++i) x[i] -= fact * z[i];
  return x;
}

// Periodic natural-parameter cubic spline of one coordinate over knots u_i with spacings h_i.
struct Spline1 {
  std::vector<double> y, m2;  // values and second derivatives at the knots
};

Spline1 FitPeriodic(const std::vector<double>& y, const std::vector<double>& h) {
  const std::size_t m = y.size();
  std::vector<double> a(m), b(m), c(m), r(m);
  for (std::size_t i = 0; i < m; ++i) {
    const std::size_t ip = (i + 1) % m, im = (i + m - 1) % m;
    a[i] = h[im];
    b[i] = 2.0 * (h[im] + h[i]);
    c[i] = h[i];
    r[i] = 6.0 * ((y[ip] - y[i]) / h[i] - (y[i] - y[im]) / h[im]);
  }
  return {y, SolveCyclic(a, b, c, r)};
}

// Value, first and second derivative on interval i at local parameter t ∈ [0, h].
void EvalSpline(const Spline1& sp, std::size_t i, std::size_t ip, double h, double t, double* v,
                double* d1, double* d2) {
  const double mi = sp.m2[i], mj = sp.m2[ip], u = h - t;
  const double ci = sp.y[i] / h - mi * h / 6.0, cj = sp.y[ip] / h - mj * h / 6.0;
  if (v) *v = mi * u * u * u / (6.0 * h) + mj * t * t * t / (6.0 * h) + ci * u + cj * t;
  if (d1) *d1 = -mi * u * u / (2.0 * h) + mj * t * t / (2.0 * h) - ci + cj;
  if (d2) *d2 = (mi * u + mj * t) / h;
}

std::vector<double> PeriodicGaussian(const std::vector<double>& v, double sigma_idx) {
  const std::size_t m = v.size();
  if (!(sigma_idx > 0.0)) return v;
  // Points far closer together than the smoothing (a track of micrometres) would ask for a kernel
  // wider than the loop, beyond int range: wrapping around the whole loop once is enough.
  const int radius = static_cast<int>(std::min(std::ceil(3.0 * sigma_idx), static_cast<double>(m)));
  if (radius < 1) return v;
  std::vector<double> w(2 * radius + 1);
  double sum = 0.0;
  for (int k = -radius; k <= radius; ++k)
    sum += w[k + radius] = std::exp(-0.5 * k * k / (sigma_idx * sigma_idx));
  std::vector<double> out(m, 0.0);
  const long mm = static_cast<long>(m);
  for (long i = 0; i < mm; ++i) {
    double acc = 0.0;
    for (int k = -radius; k <= radius; ++k) acc += w[k + radius] * v[((i + k) % mm + mm) % mm];
    out[i] = acc / sum;
  }
  return out;
}

// Displacement of a clothoid piece ψ(σ) = psi0 + k0 σ + ½ k1 σ², σ ∈ [0, len], by Simpson's rule.
void IntegrateClothoid(double psi0, double k0, double k1, double len, double* dx, double* dy) {
  *dx = *dy = 0.0;
  if (len <= 0.0) return;
  const int m = 2 * std::max(1, static_cast<int>(std::ceil(len / 0.5)));
  const double h = len / m;
  for (int j = 0; j <= m; ++j) {
    const double sg = j * h, psi = psi0 + k0 * sg + 0.5 * k1 * sg * sg;
    const double w = (j == 0 || j == m) ? 1.0 : (j % 2 ? 4.0 : 2.0);
    *dx += w * std::cos(psi);
    *dy += w * std::sin(psi);
  }
  *dx *= h / 3.0;
  *dy *= h / 3.0;
}

}  // namespace

Track Track::FromNodes(std::vector<double> x, std::vector<double> y, std::vector<double> psi,
                       std::vector<double> kappa, std::vector<double> wl, std::vector<double> wr,
                       std::vector<double> mu, double length, std::string name) {
  Track t;
  t.name_ = std::move(name);
  t.n_ = x.size();
  t.length_ = length;
  t.ds_ = length / static_cast<double>(t.n_);
  // Closing entries (node N ≡ node 0) so that every interpolation is a plain i, i+1 lerp.
  const double turn = psi.back() + WrapAngle(psi.front() - psi.back()) - psi.front();
  x.push_back(x.front());
  y.push_back(y.front());
  psi.push_back(psi.front() + turn);
  kappa.push_back(kappa.front());
  wl.push_back(wl.front());
  wr.push_back(wr.front());
  mu.push_back(mu.front());
  t.s_.resize(t.n_ + 1);
  t.tx_.resize(t.n_ + 1);
  t.ty_.resize(t.n_ + 1);
  for (std::size_t i = 0; i <= t.n_; ++i) {
    t.s_[i] = t.ds_ * static_cast<double>(i);
    t.tx_[i] = std::cos(psi[i]);
    t.ty_[i] = std::sin(psi[i]);
  }
  t.s_[t.n_] = length;
  t.x_ = std::move(x);
  t.y_ = std::move(y);
  t.psi_ = std::move(psi);
  t.kappa_ = std::move(kappa);
  t.wl_ = std::move(wl);
  t.wr_ = std::move(wr);
  t.mu_ = std::move(mu);
  return t;
}

Track Track::FromPoints(const std::vector<double>& x_in, const std::vector<double>& y_in,
                        const std::vector<double>& wl_in, const std::vector<double>& wr_in,
                        const std::vector<double>& mu_in, const TrackBuildOptions& opt,
                        const std::string& name, const std::string& source) {
  Problems pr;
  // Where a problem is: the file's line of input point k when the points are rows.
  const std::vector<int>& lines = opt.source_lines;
  auto at = [&](std::size_t k) {
    return k < lines.size() ? "line " + std::to_string(lines[k]) : "point " + std::to_string(k);
  };
  std::size_t m = x_in.size();
  if (y_in.size() != m || wl_in.size() != m || wr_in.size() != m ||
      (!mu_in.empty() && mu_in.size() != m))
    throw ConfigError(source, "", "x, y, widths and friction need the same number of points");
  if (m < 8)
    throw ConfigError(source, "",
                      "too few points for a closed track: " + std::to_string(m) + " (need ≥ 8)");
  for (std::size_t i = 0; i < m; ++i) {
    const double vals[] = {x_in[i], y_in[i], wl_in[i], wr_in[i], mu_in.empty() ? 1.0 : mu_in[i]};
    if (!std::all_of(std::begin(vals), std::end(vals), [](double v) { return std::isfinite(v); }))
      pr.Add(at(i), "values must be finite");
    else if (!(wl_in[i] > 0.0 && wr_in[i] > 0.0))
      pr.Add(at(i), "widths must be positive");
    else if (!(vals[4] > 0.0))
      pr.Add(at(i), "friction scale must be positive");
  }
  if (!pr.empty()) throw ConfigError(source, pr.items());

  // Spacings, median, closure.
  std::vector<double> gaps(m);
  for (std::size_t i = 0; i < m; ++i) {
    const std::size_t j = (i + 1) % m;
    gaps[i] = std::hypot(x_in[j] - x_in[i], y_in[j] - y_in[i]);
  }
  std::vector<double> sorted(gaps.begin(), gaps.end() - 1);
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted[sorted.size() / 2];
  if (!(median > 0.0)) throw ConfigError(source, "", "the points do not advance (median step 0)");
  const bool duplicated_end = gaps[m - 1] < 1e-3 * median;
  if (duplicated_end) --m;
  if (m < 8)
    throw ConfigError(source, "",
                      "too few points for a closed track: " + std::to_string(m) + " (need ≥ 8)");
  const double tol = opt.closure_tolerance >= 0.0 ? opt.closure_tolerance : 5.0 * median;
  if (!duplicated_end && gaps[m - 1] > tol)
    throw ConfigError(
        source,
        lines.empty() ? std::string()
                      : "line " + std::to_string(lines.back()) + " (last row) vs line " +
                            std::to_string(lines.front()) + " (first row)",
        "the loop does not close: the last point is " + Num(gaps[m - 1]) +
            " m from the first (accepted: " + Num(tol) + " m); give a closed centre line");
  for (std::size_t i = 0; i < m; ++i)
    if (!(gaps[i] > 1e-6 * median))
      throw ConfigError(source, at(i + 1), "repeats the previous point; remove duplicates");

  const double sigma_idx = opt.smoothing > 0.0 ? opt.smoothing / median : 0.0;
  const std::vector<double> xs =
      PeriodicGaussian(std::vector<double>(x_in.begin(), x_in.begin() + m), sigma_idx);
  const std::vector<double> ys =
      PeriodicGaussian(std::vector<double>(y_in.begin(), y_in.begin() + m), sigma_idx);
  std::vector<double> h(m);
  for (std::size_t i = 0; i < m; ++i) {
    const std::size_t j = (i + 1) % m;
    h[i] = std::hypot(xs[j] - xs[i], ys[j] - ys[i]);
    if (!(h[i] > 0.0)) throw ConfigError(source, "", "smoothing collapsed two points");
  }
  const Spline1 sx = FitPeriodic(xs, h), sy = FitPeriodic(ys, h);

  // Arc length of each interval (5-point Gauss-Legendre on [0, t]).
  static constexpr double kGx[] = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                   0.5384693101056831, 0.9061798459386640};
  static constexpr double kGw[] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                   0.4786286704993665, 0.2369268850561891};
  auto speed = [&](std::size_t i, double t) {
    double dx, dy;
    const std::size_t j = (i + 1) % m;
    EvalSpline(sx, i, j, h[i], t, nullptr, &dx, nullptr);
    EvalSpline(sy, i, j, h[i], t, nullptr, &dy, nullptr);
    return std::hypot(dx, dy);
  };
  auto arc = [&](std::size_t i, double t) {
    double acc = 0.0;
    for (int k = 0; k < 5; ++k) acc += kGw[k] * speed(i, 0.5 * t * (kGx[k] + 1.0));
    return 0.5 * t * acc;
  };
  std::vector<double> cum(m + 1, 0.0);
  for (std::size_t i = 0; i < m; ++i) cum[i + 1] = cum[i] + arc(i, h[i]);
  const double length = cum[m];
  // A stray point or coordinates in the wrong unit make a centre line of thousands of km, which
  // would be resampled into length/step nodes (gigabytes): refuse it and name the largest gap.
  constexpr double kMaxLength = 1e5;  // [m]; the longest circuits are about 25 km
  if (!(length <= kMaxLength) || !(length / opt.step <= 1e7)) {
    const std::size_t far = static_cast<std::size_t>(
        std::max_element(gaps.begin(), gaps.begin() + static_cast<long>(m)) - gaps.begin());
    throw ConfigError(source, at((far + 1) % m),
                      "the centre line would be " + Num(length) + " m long (at most " +
                          Num(kMaxLength) + " m); the largest step, " + Num(gaps[far]) +
                          " m, ends here (a stray point, or coordinates not in metres?)");
  }
  const std::size_t n =
      std::max<std::size_t>(8, static_cast<std::size_t>(std::llround(length / opt.step)));
  const double ds = length / static_cast<double>(n);

  std::vector<double> x(n), y(n), psi(n), kappa(n), wl(n), wr(n), mu(n);
  std::size_t k = 0;
  double prev_psi = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    const double sj = ds * static_cast<double>(j);
    while (k + 1 < m && cum[k + 1] <= sj) ++k;
    double t = h[k] * (sj - cum[k]) / (cum[k + 1] - cum[k]);
    for (int it = 0; it < 5; ++it) {
      t -= (cum[k] + arc(k, t) - sj) / speed(k, t);
      t = std::clamp(t, 0.0, h[k]);
    }
    const std::size_t kn = (k + 1) % m;
    double dx, dy, ddx, ddy;
    EvalSpline(sx, k, kn, h[k], t, &x[j], &dx, &ddx);
    EvalSpline(sy, k, kn, h[k], t, &y[j], &dy, &ddy);
    const double raw = std::atan2(dy, dx);
    psi[j] = j == 0 ? raw : prev_psi + WrapAngle(raw - prev_psi);
    prev_psi = psi[j];
    kappa[j] = (dx * ddy - dy * ddx) / std::pow(dx * dx + dy * dy, 1.5);
    const double f = t / h[k];
    wl[j] = wl_in[k] + f * (wl_in[kn] - wl_in[k]);
    wr[j] = wr_in[k] + f * (wr_in[kn] - wr_in[k]);
    mu[j] = mu_in.empty() ? 1.0 : mu_in[k] + f * (mu_in[kn] - mu_in[k]);
  }
  Track tr = FromNodes(std::move(x), std::move(y), std::move(psi), std::move(kappa), std::move(wl),
                       std::move(wr), std::move(mu), length, name);
  if (std::abs(std::abs(tr.total_turning()) - kTwoPi) > 0.5)
    throw ConfigError(source, "",
                      "the centre line turns " + Num(tr.total_turning()) +
                          " rad in total; a simple closed loop turns ±2π (self-intersecting or "
                          "out-of-order points?)");
  return tr;
}

Track Track::FromDefinition(const params::TrackParams& def, const std::string& source) {
  params::ValidateOrThrow(def, source);
  const std::size_t nseg = def.length.size();
  double turning = 0.0, length = 0.0;
  for (std::size_t k = 0; k < nseg; ++k) {
    turning += 0.5 * def.length[k] * (def.curvature_start[k] + def.curvature_end[k]);
    length += def.length[k];
  }
  const double loops = std::round(turning / kTwoPi);
  if (std::abs(loops) != 1.0 || std::abs(turning - loops * kTwoPi) > def.heading_tolerance)
    throw ConfigError(source, "curvature_start",
                      "the segments turn " + Num(turning) +
                          " rad in total; a closed loop turns ±2π (±" + Num(def.heading_tolerance) +
                          " rad, heading_tolerance)");
  const double scale = loops * kTwoPi / turning;

  // Segment start states.
  std::vector<double> s0(nseg + 1, 0.0), x0(nseg + 1), y0(nseg + 1), p0(nseg + 1);
  x0[0] = def.start_x;
  y0[0] = def.start_y;
  p0[0] = def.start_heading;
  auto k0 = [&](std::size_t k) { return scale * def.curvature_start[k]; };
  auto k1 = [&](std::size_t k) {
    return scale * (def.curvature_end[k] - def.curvature_start[k]) / def.length[k];
  };
  for (std::size_t k = 0; k < nseg; ++k) {
    double dx, dy;
    IntegrateClothoid(p0[k], k0(k), k1(k), def.length[k], &dx, &dy);
    x0[k + 1] = x0[k] + dx;
    y0[k + 1] = y0[k] + dy;
    p0[k + 1] = p0[k] + k0(k) * def.length[k] + 0.5 * k1(k) * def.length[k] * def.length[k];
    s0[k + 1] = s0[k] + def.length[k];
  }
  const double gx = x0[nseg] - x0[0], gy = y0[nseg] - y0[0];
  const double gap = std::hypot(gx, gy);
  if (gap > def.closure_tolerance)
    throw ConfigError(source, "length",
                      "the segments do not close: the end point is " + Num(gap) +
                          " m from the start (closure_tolerance " + Num(def.closure_tolerance) +
                          " m); adjust lengths or curvatures");

  const std::size_t n =
      std::max<std::size_t>(8, static_cast<std::size_t>(std::llround(length / def.step)));
  const double ds = length / static_cast<double>(n);
  std::vector<double> x(n), y(n), psi(n), kappa(n), wl(n), wr(n), mu(n);
  const double ex = gx / length, ey = gy / length;  // closure shift per metre
  std::size_t k = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const double sj = ds * static_cast<double>(j);
    while (k + 1 < nseg && s0[k + 1] <= sj) ++k;
    const double sg = sj - s0[k];
    double dx, dy;
    IntegrateClothoid(p0[k], k0(k), k1(k), sg, &dx, &dy);
    const double ps = p0[k] + k0(k) * sg + 0.5 * k1(k) * sg * sg;
    const double kap = k0(k) + k1(k) * sg;
    x[j] = x0[k] + dx - ex * sj;
    y[j] = y0[k] + dy - ey * sj;
    // Shifted curve: c' = T − e, c'' = κ N.
    const double cx = std::cos(ps) - ex, cy = std::sin(ps) - ey;
    psi[j] = ps + std::atan2(std::cos(ps) * cy - std::sin(ps) * cx,
                             std::cos(ps) * cx + std::sin(ps) * cy);
    kappa[j] = kap * (cx * std::cos(ps) + cy * std::sin(ps)) / std::pow(cx * cx + cy * cy, 1.5);
    const std::size_t kn = (k + 1) % nseg;
    const double f = sg / def.length[k];
    wl[j] = def.width_left[k] + f * (def.width_left[kn] - def.width_left[k]);
    wr[j] = def.width_right[k] + f * (def.width_right[kn] - def.width_right[k]);
    if (def.friction_scale.size() == 1)
      mu[j] = def.friction_scale[0];
    else
      mu[j] = def.friction_scale[k] + f * (def.friction_scale[kn] - def.friction_scale[k]);
  }
  Track tr = FromNodes(std::move(x), std::move(y), std::move(psi), std::move(kappa), std::move(wl),
                       std::move(wr), std::move(mu), length, def.name);
  tr.closure_gap_ = gap;
  tr.patches_ = def.friction_patches;
  return tr;
}

double Track::Wrap(double s) const noexcept {
  double r = std::fmod(s, length_);
  if (r < 0.0) r += length_;
  return r >= length_ ? 0.0 : r;
}

double Track::Interpolate(const std::vector<double>& v, double s) const noexcept {
  const double w = Wrap(s);
  std::size_t i = std::min(static_cast<std::size_t>(w / ds_), n_ - 1);
  const double t = (w - s_[i]) / ds_;
  const double a = v[i], b = v[(i + 1) % v.size()];
  return a + t * (b - a);
}

TrackPose Track::PoseAt(double s) const noexcept {
  const double w = Wrap(s);
  const std::size_t i = std::min(static_cast<std::size_t>(w / ds_), n_ - 1);
  const double t = (w - s_[i]) / ds_;
  TrackPose p;
  p.x = x_[i] + t * (x_[i + 1] - x_[i]);
  p.y = y_[i] + t * (y_[i + 1] - y_[i]);
  p.heading = psi_[i] + t * (psi_[i + 1] - psi_[i]);
  p.curvature = kappa_[i] + t * (kappa_[i + 1] - kappa_[i]);
  return p;
}

void Track::ToCartesian(double s, double n, double* x, double* y) const noexcept {
  const double w = Wrap(s);
  const std::size_t i = std::min(static_cast<std::size_t>(w / ds_), n_ - 1);
  const double t = (w - s_[i]) / ds_;
  // Blended tangent, as in Project, so that Project(ToCartesian(s, n)) returns (s, n).
  double tx = tx_[i] + t * (tx_[i + 1] - tx_[i]), ty = ty_[i] + t * (ty_[i + 1] - ty_[i]);
  const double norm = std::hypot(tx, ty);
  tx /= norm;
  ty /= norm;
  *x = x_[i] + t * (x_[i + 1] - x_[i]) - n * ty;
  *y = y_[i] + t * (y_[i + 1] - y_[i]) + n * tx;
}

bool Track::SegmentFoot(std::size_t i, double px, double py, double* t_out,
                        double* dist2) const noexcept {
  const double qx = px - x_[i], qy = py - y_[i];
  const double g0 = tx_[i] * qx + ty_[i] * qy;
  if (g0 < 0.0) return false;
  const double g1 = tx_[i + 1] * (px - x_[i + 1]) + ty_[i + 1] * (py - y_[i + 1]);
  if (g1 >= 0.0) return false;
  const double dx = x_[i + 1] - x_[i], dy = y_[i + 1] - y_[i];
  const double dtx = tx_[i + 1] - tx_[i], dty = ty_[i + 1] - ty_[i];
  // g(t) = (T0 + tΔT)·(q − tD): a quadratic with g(0) ≥ 0 > g(1); Newton from the secant root.
  double t = g0 / (g0 - g1);
  for (int it = 0; it < 4; ++it) {
    const double ex = qx - t * dx, ey = qy - t * dy;
    const double g = (tx_[i] + t * dtx) * ex + (ty_[i] + t * dty) * ey;
    const double dg = dtx * ex + dty * ey - ((tx_[i] + t * dtx) * dx + (ty_[i] + t * dty) * dy);
    if (dg >= 0.0) break;  // not expected (g decreasing); keep the current estimate
    t = std::clamp(t - g / dg, 0.0, 1.0);
  }
  const double ex = qx - t * dx, ey = qy - t * dy;
  *t_out = t;
  *dist2 = ex * ex + ey * ey;
  return true;
}

TrackProjection Track::Finish(std::size_t i, double t, double px, double py,
                              double heading) const noexcept {
  TrackProjection r;
  r.segment = i;
  r.s = Wrap(s_[i] + t * ds_);
  const double cx = x_[i] + t * (x_[i + 1] - x_[i]), cy = y_[i] + t * (y_[i + 1] - y_[i]);
  const double tx = tx_[i] + t * (tx_[i + 1] - tx_[i]), ty = ty_[i] + t * (ty_[i + 1] - ty_[i]);
  r.n = (tx * (py - cy) - ty * (px - cx)) / std::hypot(tx, ty);
  r.heading_error = WrapAngle(heading - (psi_[i] + t * (psi_[i + 1] - psi_[i])));
  return r;
}

TrackProjection Track::Project(double px, double py, double heading, double s_hint,
                               double local_radius) const noexcept {
  double t = 0.0, d2 = 0.0;
  if (std::isfinite(s_hint)) {
    std::size_t i = std::min(static_cast<std::size_t>(Wrap(s_hint) / ds_), n_ - 1);
    const std::size_t max_steps =
        std::min<std::size_t>(n_, static_cast<std::size_t>(64.0 + 2.0 * local_radius / ds_));
    for (std::size_t step = 0; step < max_steps; ++step) {
      const double g0 = tx_[i] * (px - x_[i]) + ty_[i] * (py - y_[i]);
      if (g0 < 0.0) {
        i = (i + n_ - 1) % n_;
        continue;
      }
      const double g1 = tx_[i + 1] * (px - x_[i + 1]) + ty_[i + 1] * (py - y_[i + 1]);
      if (g1 >= 0.0) {
        i = (i + 1) % n_;
        continue;
      }
      if (SegmentFoot(i, px, py, &t, &d2) && d2 <= local_radius * local_radius)
        return Finish(i, t, px, py, heading);
      break;
    }
  }
  // Global: the closest foot point over every segment.
  double best = std::numeric_limits<double>::infinity(), best_t = 0.0;
  std::size_t best_i = n_;
  for (std::size_t i = 0; i < n_; ++i)
    if (SegmentFoot(i, px, py, &t, &d2) && d2 < best) {
      best = d2;
      best_i = i;
      best_t = t;
    }
  // Node N is node 0, but its tangent is cos/sin of ψ0 + 2π, which may round differently from
  // node 0's: a point within rounding of node 0's normal can then be refused by both segment N−1
  // (g(1) ≥ 0) and segment 0 (g(0) < 0), and the search above finds a far segment instead (a
  // racing line starting at s = 0 of a CSV track did). Its foot is node 0.
  const double g_first = tx_[0] * (px - x_[0]) + ty_[0] * (py - y_[0]);
  const double g_last = tx_[n_] * (px - x_[n_]) + ty_[n_] * (py - y_[n_]);
  if (g_first < 0.0 && g_last >= 0.0) {
    const double d2_node = (px - x_[0]) * (px - x_[0]) + (py - y_[0]) * (py - y_[0]);
    if (d2_node < best) {
      best = d2_node;
      best_i = 0;
      best_t = 0.0;
    }
  }
  if (best_i == n_) {  // degenerate (exactly on a normal everywhere): nearest node
    best_i = 0;
    for (std::size_t i = 0; i < n_; ++i) {
      const double d = std::hypot(px - x_[i], py - y_[i]);
      if (d < best) {
        best = d;
        best_i = i;
      }
    }
    best_t = 0.0;
  }
  return Finish(best_i, best_t, px, py, heading);
}

}  // namespace scw::plant
