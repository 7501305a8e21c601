#include "plant/vehicle/quasi_steady.h"

#include <algorithm>
#include <cmath>

#include "plant/powertrain/differential.h"
#include "plant/powertrain/engine.h"
#include "plant/tire/magic_formula.h"

namespace scw::plant {
namespace {

// Illinois regula falsi on [a, b] with f(a) < 0 ≤ f(b): shrinks the bracket until its width is
// below rel (1 + |b|), `iters` steps, or an exact root (fb == 0 when `stop_on_fb_zero`, else the
// last f(x) == 0); x is the last point evaluated.
struct Bracket {
  double a, fa, b, fb, x;
};
template <class F>
void Illinois(F&& f, Bracket* br, int iters, double rel, bool stop_on_fb_zero) noexcept {
  double a = br->a, fa = br->fa, b = br->b, fb = br->fb, x = br->b;
  int side = 0;
  for (int k = 0; k < iters; ++k) {
    x = (fb * a - fa * b) / (fb - fa);
    if (!(x > a && x < b)) x = 0.5 * (a + b);
    const double fx = f(x);
    if (fx >= 0.0) {
      b = x;
      fb = fx;
      if (side == -1) fa *= 0.5;
      side = -1;
    } else {
      a = x;
      fa = fx;
      if (side == 1) fb *= 0.5;
      side = 1;
    }
    if (b - a < rel * (1.0 + std::abs(b)) || (stop_on_fb_zero ? fb : fx) == 0.0) break;
  }
  *br = {a, fa, b, fb, x};
}

// Root of an increasing-then-peaking function: the first x ≥ lo with f(x) ≥ 0, searched in steps
// of `step` up to `hi`, refined by the Illinois variant of regula falsi. Returns false when f
// passes its peak below 0 (checked by a golden-section search of the peak between the last
// samples) or `hi` is reached. On entry f(lo) should be < 0; if it is not, the search first walks
// down (at most 200 steps, not below `floor`).
template <class F>
bool FirstCrossing(F&& f, double lo, double step, double hi, double floor, double* root) noexcept {
  double a = lo;
  double fa = f(a);
  for (int k = 0; fa >= 0.0 && k < 200; ++k) {
    if (a - step < floor) {
      if (a <= floor) {
        *root = a;
        return true;
      }
      a = floor;
    } else {
      a -= step;
    }
    fa = f(a);
  }
  if (fa >= 0.0) {
    *root = a;
    return true;
  }
  double b = a, fb = fa, prev_a = a;
  bool bracketed = false;
  while (b < hi) {
    prev_a = a;
    a = b;
    fa = fb;
    b = std::min(b + step, hi);
    fb = f(b);
    if (fb >= 0.0) {
      bracketed = true;
      break;
    }
    if (fb < fa) {
      // Past a peak: find it between prev_a and b; a crossing may hide there.
      double x0 = prev_a, x3 = b;
      const double gr = 0.6180339887498949;
      double x1 = x3 - gr * (x3 - x0), x2 = x0 + gr * (x3 - x0);
      double f1 = f(x1), f2 = f(x2);
      for (int k = 0; k < 40 && x3 - x0 > 1e-9 * (1.0 + std::abs(x3)); ++k) {
        if (f1 >= 0.0 || f2 >= 0.0) break;
        if (f1 > f2) {
          x3 = x2;
          x2 = x1;
          f2 = f1;
          x1 = x3 - gr * (x3 - x0);
          f1 = f(x1);
        } else {
          x0 = x1;
          x1 = x2;
          f1 = f2;
          x2 = x0 + gr * (x3 - x0);
          f2 = f(x2);
        }
      }
      if (f1 >= 0.0) {
        b = x1;
        fb = f1;
        a = x0;
        fa = f(a);
      } else if (f2 >= 0.0) {
        b = x2;
        fb = f2;
        a = x1 < x2 ? x1 : x0;
        fa = f(a);
        if (fa >= 0.0) {
          a = x0;
          fa = f(a);
        }
      } else {
        return false;
      }
      bracketed = fa < 0.0;
      break;
    }
  }
  if (!bracketed) return false;
  Bracket br{a, fa, b, fb, b};
  Illinois(f, &br, 60, 1e-10, true);
  *root = br.b;
  return true;
}

// Root of an increasing f on [a, b] (f(a) ≤ 0 ≤ f(b) expected; clamped to the ends otherwise):
// Illinois regula falsi.
template <class F>
double BracketedRoot(F&& f, double a, double b) noexcept {
  double fa = f(a), fb = f(b);
  if (fa >= 0.0) return a;
  if (fb <= 0.0) return b;
  Bracket br{a, fa, b, fb, b};
  Illinois(f, &br, 80, 1e-9, false);
  return br.x;
}

// Largest x in [lo, hi] with pred(x) true, assuming pred is true at lo and monotone; bisection to
// a relative width `rel`.
template <class P>
double LargestTrue(P&& pred, double lo, double hi, double rel) noexcept {
  if (pred(hi)) return hi;
  for (int k = 0; k < 60 && hi - lo > rel * std::max(1.0, hi); ++k) {
    const double mid = 0.5 * (lo + hi);
    if (pred(mid)) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return lo;
}

}  // namespace

QuasiSteadyModel::QuasiSteadyModel(const params::VehicleParams& p, const QuasiSteadyOptions& o)
    : veh_(p), o_(o), diff_(veh_.params().differential) {
  const auto& c = veh_.params().chassis;
  m_ = c.mass;
  l_ = c.wheelbase;
  lf_ = c.cg_to_front_axle;
  lr_ = l_ - lf_;
  drag_k_ = 0.5 * p.aero.air_density * p.aero.drag_area;
  crr_ = p.wheels.rolling_resistance;
  px_ = {lf_, lf_, -lr_, -lr_};
  py_ = {0.5 * c.track_front, -0.5 * c.track_front, 0.5 * c.track_rear, -0.5 * c.track_rear};
  radius_ = FromFrontRear(p.wheels.radius_front, p.wheels.radius_rear);
}

double QuasiSteadyModel::TireFx(std::size_t i, double fz, double kappa,
                                double alpha) const noexcept {
  const auto& p = veh_.params().tires;
  const TireInput in = veh_.WheelTireInput(i, fz, kappa, IsLeft(i) ? alpha : -alpha);
  return TireForces(in, IsFront(i) ? p.front : p.rear).fx;
}

double QuasiSteadyModel::TireFy(std::size_t i, double fz, double kappa,
                                double alpha) const noexcept {
  const auto& p = veh_.params().tires;
  const TireInput in = veh_.WheelTireInput(i, fz, kappa, IsLeft(i) ? alpha : -alpha);
  const double fy = TireForces(in, IsFront(i) ? p.front : p.rear).fy;
  return IsLeft(i) ? fy : -fy;
}

bool QuasiSteadyModel::SolveWheelFx(std::size_t i, double fz, double alpha, double /*vxt*/,
                                    double fx_target, double* kappa) const noexcept {
  const double f0 = TireFx(i, fz, 0.0, alpha);
  const double dir = fx_target >= f0 ? 1.0 : -1.0;
  auto h = [&](double k) { return dir * (TireFx(i, fz, dir * k, alpha) - fx_target); };
  double k = 0.0;
  if (!FirstCrossing(h, 0.0, 0.004, 0.8, 0.0, &k)) return false;
  *kappa = dir * k;
  return true;
}

double QuasiSteadyModel::MaxEngineForce(double v) const noexcept {
  const auto& p = veh_.params();
  const double r = p.wheels.radius_rear;
  const double limit = RpmToRadPerSec(p.engine.rev_limit_rpm);
  const double clutch = RpmToRadPerSec(p.engine.clutch_slip_rpm);
  const auto& gb = veh_.gearbox();
  double best = 0.0;
  for (int g = 0; g < gb.gears; ++g) {
    // The automatic gearbox leaves gear g at its upshift speed (the last gear at the rev limit).
    const double top =
        g + 1 < gb.gears ? std::min(gb.up[static_cast<std::size_t>(g)], limit) : limit;
    const double we = std::max(v / r * gb.overall[static_cast<std::size_t>(g)], clutch);
    if (we > top) continue;
    const double t = veh_.engine().FullLoadTorque(we);
    best = std::max(best, t * gb.overall[static_cast<std::size_t>(g)] *
                              gb.eta[static_cast<std::size_t>(g)] / r);
  }
  return best;
}

QuasiSteadyState QuasiSteadyModel::Solve(double v, double a_x, double a_y_in) const noexcept {
  QuasiSteadyState out;
  if (!(v > 0.5) || !std::isfinite(a_x) || !std::isfinite(a_y_in)) return out;
  // Solve the left turn; a right turn is its mirror image.
  const bool mirror = a_y_in < 0.0;
  const double a_y = std::abs(a_y_in);
  const double r = a_y / v;
  const bool spool = diff_.spool;
  const double b = o_.brake_bias_front;

  StateVector x = StateVector::Zero();
  x[kVx] = v;
  x[kAxLoadTransfer] = a_x;
  x[kAyLoadTransfer] = a_y;
  const PerWheel<double> fz = veh_.WheelLoads(x);
  const double f_need = m_ * a_x + drag_k_ * v * v;
  double rolling = 0.0;
  for (double f : fz) rolling += crr_ * f;
  const bool drive = f_need > -rolling;

  PerWheel<double> vxt{}, alpha{}, kappa{}, fx{}, fy{};
  double vy = r * lr_;        // rear axle at zero slip angle
  double steer = l_ * r / v;  // kinematic steering
  double spool_kappa = 0.0, brake = 0.0, axle_force = 0.0;
  auto kinematics = [&](double vy_, double steer_, std::size_t i, double* vx_t) {
    const double vxw = v - r * py_[i];
    const double vyw = vy_ + r * px_[i];
    double vx_t_ = vxw, vy_t = vyw;
    if (IsFront(i)) {
      const double c = std::cos(steer_), s = std::sin(steer_);
      vx_t_ = c * vxw + s * vyw;
      vy_t = -s * vxw + c * vyw;
    }
    *vx_t = vx_t_;
    return -std::atan(vy_t / std::abs(vx_t_));
  };
  auto all_kinematics = [&]() {
    for (std::size_t i = 0; i < 4; ++i) alpha[i] = kinematics(vy, steer, i, &vxt[i]);
  };

  bool converged = false;
  for (int it = 0; it < 60; ++it) {
    all_kinematics();
    const double c = std::cos(steer), s = std::sin(steer);
    // 1. Longitudinal forces (tyre frame) for the current slip angles and lateral forces.
    if (drive) {
      for (std::size_t i : {kFL, kFR}) {
        fx[i] = -crr_ * fz[i];
        if (!SolveWheelFx(i, fz[i], alpha[i], vxt[i], fx[i], &kappa[i])) return out;
      }
      const double f_rear = f_need - (c * (fx[kFL] + fx[kFR]) - s * (fy[kFL] + fy[kFR]));
      // Both rear wheels: ω_i = (1 + κ_m) v / R ± Δ/2 (Δ = ω_RL − ω_RR), with Δ from the
      // differential's torque balance (spool: Δ = 0; LSD/open: T_RL − T_RR = −2 M(Δ, T)).
      const double rr = radius_[kRL];
      auto wheel_kappa = [&](double km, double delta, std::size_t i) {
        const double w = (1.0 + km) * v / rr + (i == kRL ? 0.5 : -0.5) * delta;
        return (w * rr - vxt[i]) / vxt[i];
      };
      auto rear_fx = [&](double km, double delta, PerWheel<double>* f) {
        for (std::size_t i : {kRL, kRR})
          (*f)[i] = TireFx(i, fz[i], wheel_kappa(km, delta, i), alpha[i]);
      };
      double delta = 0.0;
      auto solve_delta = [&](double km) {
        if (spool) return 0.0;
        PerWheel<double> f{};
        auto h = [&](double d) {
          rear_fx(km, d, &f);
          const double tl = (f[kRL] + crr_ * fz[kRL]) * rr;
          const double tr = (f[kRR] + crr_ * fz[kRR]) * rr;
          return tl - tr +
                 2.0 * LsdTorque((1.0 + km) * v / rr + 0.5 * d, (1.0 + km) * v / rr - 0.5 * d,
                                 tl + tr, diff_);
        };
        return BracketedRoot(h, -60.0, 60.0);
      };
      auto g = [&](double km) {
        PerWheel<double> f{};
        rear_fx(km, solve_delta(km), &f);
        return f[kRL] + f[kRR] - f_rear;
      };
      double km = 0.0;
      if (!FirstCrossing(g, spool_kappa - 0.008, 0.004, 0.8, -0.5, &km)) return out;
      spool_kappa = km;
      delta = solve_delta(km);
      for (std::size_t i : {kRL, kRR}) {
        kappa[i] = wheel_kappa(km, delta, i);
        fx[i] = TireFx(i, fz[i], kappa[i], alpha[i]);
      }
      axle_force = fx[kRL] + fx[kRR] + crr_ * (fz[kRL] + fz[kRR]);
      if (axle_force > MaxEngineForce(v)) return out;
      brake = 0.0;
    } else {
      const double rear_roll = -crr_ * (fz[kRL] + fz[kRR]);
      const double front = -c * crr_ * (fz[kFL] + fz[kFR]) - s * (fy[kFL] + fy[kFR]);
      brake = std::max(0.0, (rear_roll + front - f_need) / ((1.0 - b) + c * b));
      for (std::size_t i = 0; i < 4; ++i) {
        fx[i] = -crr_ * fz[i] - 0.5 * (IsFront(i) ? b : 1.0 - b) * brake;
        if (!SolveWheelFx(i, fz[i], alpha[i], vxt[i], fx[i], &kappa[i])) return out;
      }
      axle_force = 0.0;
    }
    // 2. Axle lateral forces from the force and yaw-moment balance.
    double mx = 0.0;
    for (std::size_t i = 0; i < 4; ++i) {
      const double fxv = IsFront(i) ? c * fx[i] - s * fy[i] : fx[i];
      mx -= py_[i] * fxv;
    }
    const double fr_req = (m_ * a_y * lf_ + mx) / l_;
    const double ff_req = m_ * a_y - fr_req;
    // 3. Rear axle: lateral velocity (parametrised by the rear axle slip angle) for fr_req.
    const double vy_old = vy, steer_old = steer;
    auto rear = [&](double a_r) {
      const double vy_ = r * lr_ - v * std::tan(a_r);
      double sum = 0.0, dummy = 0.0;
      for (std::size_t i : {kRL, kRR})
        sum += TireFy(i, fz[i], kappa[i], kinematics(vy_, steer, i, &dummy));
      return sum - fr_req;
    };
    const double a_r0 = std::atan((r * lr_ - vy) / v);
    double a_r = 0.0;
    if (!FirstCrossing(rear, a_r0 - 0.01, 0.005, 0.4, -0.4, &a_r)) return out;
    vy = r * lr_ - v * std::tan(a_r);
    // 4. Front axle: steering angle for ff_req (body-frame lateral force of the front wheels).
    auto front = [&](double d) {
      const double cd = std::cos(d), sd = std::sin(d);
      double sum = 0.0, dummy = 0.0;
      for (std::size_t i : {kFL, kFR})
        sum += sd * fx[i] + cd * TireFy(i, fz[i], kappa[i], kinematics(vy, d, i, &dummy));
      return sum - ff_req;
    };
    double d = 0.0;
    if (!FirstCrossing(front, steer - 0.01, 0.005, 0.6, -0.6, &d)) return out;
    steer = d;
    all_kinematics();
    for (std::size_t i = 0; i < 4; ++i) fy[i] = TireFy(i, fz[i], kappa[i], alpha[i]);
    if (std::abs(vy - vy_old) < 1e-9 * v && std::abs(steer - steer_old) < 1e-10 && it > 0) {
      converged = true;
      break;
    }
  }
  if (!converged) return out;
  // Final consistency of the longitudinal balance with the converged lateral forces.
  out.feasible = true;
  out.steer_limited = std::abs(steer) > veh_.params().steering.max_angle;
  if (out.steer_limited && o_.respect_steering_lock) out.feasible = false;
  out.v_y = vy;
  out.steer = steer;
  out.axle_torque = axle_force * radius_[kRL];
  out.brake_force = brake;
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& tp = IsFront(i) ? veh_.params().tires.front : veh_.params().tires.rear;
    const TirePeakFriction mu =
        PeakFriction(fz[i], veh_.lambda_mu_x()[i], veh_.lambda_mu_y()[i], tp);
    const double cap = std::max(mu.mu_x, mu.mu_y) * fz[i];
    out.usage[i] = cap > 0.0 ? std::hypot(fx[i], fy[i]) / cap : 1.0;
  }
  out.fz = fz;
  out.kappa = kappa;
  out.alpha = alpha;
  out.fx = fx;
  out.fy = fy;
  if (mirror) {
    auto swap_lr = [](PerWheel<double>& w) {
      std::swap(w[kFL], w[kFR]);
      std::swap(w[kRL], w[kRR]);
    };
    out.v_y = -out.v_y;
    out.steer = -out.steer;
    for (auto* w : {&out.fz, &out.kappa, &out.alpha, &out.fx, &out.fy, &out.usage}) swap_lr(*w);
    for (std::size_t i = 0; i < 4; ++i) {
      out.alpha[i] = -out.alpha[i];
      out.fy[i] = -out.fy[i];
    }
  }
  return out;
}

double QuasiSteadyModel::MinDeceleration(double v) const noexcept {
  if (Solve(v, 0.0, 0.0).feasible) return 0.0;
  // Above the top speed: coasting (no drive torque), drag and rolling resistance decelerate.
  return RoadLoad(v) / m_;
}

double QuasiSteadyModel::RoadLoad(double v) const noexcept {
  const auto& a = veh_.params().aero;
  const double down =
      0.5 * a.air_density * (a.downforce_area_front + a.downforce_area_rear) * v * v;
  return drag_k_ * v * v + crr_ * (m_ * veh_.params().chassis.gravity + down);
}

double QuasiSteadyModel::MaxLateral(double v) const noexcept {
  const double d0 = MinDeceleration(v);
  auto ok = [&](double ay) { return Solve(v, -d0, ay).feasible; };
  if (!ok(0.0)) return 0.0;
  return LargestTrue(ok, 0.0, 80.0, 1e-4);
}

double QuasiSteadyModel::MaxDrive(double v, double a_y) const noexcept {
  auto ok = [&](double ax) { return Solve(v, ax, a_y).feasible; };
  if (!ok(0.0)) return 0.0;
  return LargestTrue(ok, 0.0, 40.0, 1e-4);
}

double QuasiSteadyModel::MaxBrake(double v, double a_y) const noexcept {
  const double d0 = MinDeceleration(v);
  auto ok = [&](double d) { return Solve(v, -d, a_y).feasible; };
  if (!ok(d0)) return d0;
  return LargestTrue(ok, d0, 80.0, 1e-4);
}

double QuasiSteadyModel::UndersteerGradient(double v) const noexcept {
  const QuasiSteadyState a = Solve(v, 0.0, 0.5);
  const QuasiSteadyState b = Solve(v, 0.0, 1.5);
  if (!a.feasible || !b.feasible) return std::nan("");
  return (b.steer - a.steer) / 1.0 - l_ / (v * v);
}

}  // namespace scw::plant
