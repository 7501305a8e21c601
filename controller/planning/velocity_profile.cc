#include "controller/planning/velocity_profile.h"

#include <algorithm>
#include <cmath>

#include "params/schema/field.h"

namespace scw::controller::planning {
namespace {

struct Limits {
  const GgvTable& g;
  double scale;
  double AyLimit(double v, double mu) const { return scale * mu * g.AyMax(v); }
  // Largest forward acceleration at speed v on curvature k.
  double Drive(double v, double k, double mu) const {
    return scale * g.AxDriveMax(v) * g.DriveFactor(v * v * std::abs(k), AyLimit(v, mu), v);
  }
  // Largest deceleration (positive).
  double Brake(double v, double k, double mu) const {
    return scale * mu * g.AxBrakeMax(v) * g.BrakeFactor(v * v * std::abs(k), AyLimit(v, mu), v);
  }
};

// Smallest v with v²|κ| ≥ ay limit (the first crossing), in [v_min, v_max].
double SpeedCap(const Limits& lim, double k, double mu, double v_min, double v_max) {
  auto over = [&](double v) { return v * v * std::abs(k) >= lim.AyLimit(v, mu); };
  if (over(v_min)) return v_min;
  double lo = v_min;
  for (double v = v_min + 0.5;; v += 0.5) {
    const double hi = std::min(v, v_max);
    if (over(hi)) {
      double a = lo, b = hi;
      for (int it = 0; it < 50; ++it) {
        const double m = 0.5 * (a + b);
        (over(m) ? b : a) = m;
      }
      return a;
    }
    if (hi >= v_max) return v_max;
    lo = hi;
  }
}

// Largest w ≤ cap_next with (w² − v²)/(2 ds) ≤ min(acc(v, here), acc(w, next)).
template <class Acc>
double Step(double v, double cap_next, double ds, Acc&& acc_here, Acc&& acc_next) {
  const double a0 = acc_here(v);
  const double hi = std::min(cap_next, std::sqrt(v * v + 2.0 * ds * a0));
  if (hi <= v) return hi;
  auto ok = [&](double w) { return (w * w - v * v) / (2.0 * ds) <= acc_next(w); };
  if (ok(hi)) return hi;
  double a = v, b = hi;  // ok(v) holds: acc ≥ 0
  for (int it = 0; it < 50; ++it) {
    const double m = 0.5 * (a + b);
    (ok(m) ? a : b) = m;
  }
  return a;
}

}  // namespace

TrajectorySample ReferenceTrajectory::At(double sq) const noexcept {
  TrajectorySample r;
  if (s.empty()) return r;
  if (closed) {
    sq = std::fmod(sq, length);
    if (sq < 0.0) sq += length;
  } else {
    sq = std::clamp(sq, s.front(), s.back());
  }
  const auto it = std::upper_bound(s.begin(), s.end(), sq);
  std::size_t i = it == s.begin() ? 0 : static_cast<std::size_t>(it - s.begin()) - 1;
  if (i + 1 >= s.size()) i = s.size() - 2;
  const double u = (sq - s[i]) / (s[i + 1] - s[i]);
  auto lerp = [&](const std::vector<double>& a) { return a[i] + u * (a[i + 1] - a[i]); };
  r.s = sq;
  r.x = lerp(x);
  r.y = lerp(y);
  r.psi = lerp(psi);
  r.kappa = lerp(kappa);
  r.v = lerp(v);
  r.a_x = a_x[i];  // piecewise constant per segment (the segment's mean acceleration)
  r.a_y = lerp(a_y);
  r.t = lerp(t);
  return r;
}

ReferenceTrajectory ComputeVelocityProfile(const plant::Track& path, const GgvTable& limits,
                                           const VelocityProfileOptions& o) {
  limits.Validate("g-g-v limits");
  if (!(o.gg_scale > 0.0) || !(o.v_max > o.v_min) || !(o.v_min > 0.0))
    throw ConfigError("velocity profile", "options", "need gg_scale > 0 and 0 < v_min < v_max");
  const Limits lim{limits, o.gg_scale};
  const std::size_t n = path.size();
  const double ds = path.step();
  const auto& k = path.curvature();
  const auto& mu = path.friction();
  std::vector<double> cap(n + 1);
  for (std::size_t i = 0; i <= n; ++i) cap[i] = SpeedCap(lim, k[i], mu[i], o.v_min, o.v_max);

  std::vector<double> fw(n + 1), bw(n + 1);
  auto drive = [&](std::size_t i) {
    return [&, i](double v) { return lim.Drive(v, k[i], mu[i]); };
  };
  auto brake = [&](std::size_t i) {
    return [&, i](double v) { return lim.Brake(v, k[i], mu[i]); };
  };
  if (o.closed) {
    const std::size_t i0 =
        static_cast<std::size_t>(std::min_element(cap.begin(), cap.end() - 1) - cap.begin());
    fw[i0] = bw[i0] = cap[i0];
    for (std::size_t c = 1; c <= n; ++c) {
      const std::size_t i = (i0 + c - 1) % n, j = (i0 + c) % n;
      const double w = Step(fw[i], cap[j], ds, drive(i), drive(j));
      fw[j] = c == n ? std::min(fw[j], w) : w;
    }
    for (std::size_t c = 1; c <= n; ++c) {
      const std::size_t i = (i0 + n - c + 1) % n, j = (i0 + n - c) % n;
      const double w = Step(bw[i], cap[j], ds, brake(i), brake(j));
      bw[j] = c == n ? std::min(bw[j], w) : w;
    }
    fw[n] = fw[0];
    bw[n] = bw[0];
  } else {
    fw[0] = std::min(std::max(o.v_start, 0.0), cap[0]);
    for (std::size_t i = 0; i < n; ++i)
      fw[i + 1] = Step(fw[i], cap[i + 1], ds, drive(i), drive(i + 1));
    bw[n] = cap[n];
    for (std::size_t i = n; i-- > 0;) bw[i] = Step(bw[i + 1], cap[i], ds, brake(i + 1), brake(i));
  }

  ReferenceTrajectory r;
  r.closed = o.closed;
  r.length = path.length();
  r.s = path.s();
  r.x = path.x();
  r.y = path.y();
  r.psi = path.heading();
  r.kappa = path.curvature();
  r.v.resize(n + 1);
  r.a_x.resize(n + 1);
  r.a_y.resize(n + 1);
  r.t.assign(n + 1, 0.0);
  for (std::size_t i = 0; i <= n; ++i) {
    r.v[i] = std::min(fw[i], bw[i]);
    r.a_y[i] = r.v[i] * r.v[i] * r.kappa[i];
  }
  for (std::size_t i = 0; i < n; ++i) {
    r.a_x[i] = (r.v[i + 1] * r.v[i + 1] - r.v[i] * r.v[i]) / (2.0 * ds);
    r.t[i + 1] = r.t[i] + 2.0 * ds / (r.v[i] + r.v[i + 1]);
  }
  r.a_x[n] = o.closed ? r.a_x[0] : 0.0;
  r.lap_time = r.t[n];
  return r;
}

GgvTable RepresentativeGgv() {
  GgvTable g;
  g.speed = {0.0, 10.0, 30.0, 50.0, 70.0, 90.0};
  g.ay_max = {20.0, 20.0, 22.0, 25.0, 28.0, 30.0};
  g.ax_drive_max = {8.0, 8.0, 7.5, 6.0, 4.0, 2.0};
  g.ax_brake_max = {15.0, 15.0, 17.0, 21.0, 26.0, 31.0};
  g.SetExponent(1.6);
  return g;
}

}  // namespace scw::controller::planning
