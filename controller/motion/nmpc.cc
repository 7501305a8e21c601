#include "controller/motion/nmpc.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "controller/motion/nlp_solver.h"

namespace scw::controller::motion {
namespace {

constexpr double kInf = 1e19;
constexpr double kMinVx = 1.0;  // floor of v_x in the slip angles [m/s]
using M = SingleTrackModel;

struct TireEval {
  double f = 0.0;       // F_y [N]
  double df_da = 0.0;   // ∂F_y/∂α [N/rad]
  double df_dvx = 0.0;  // ∂F_y/∂v_x through the load [N s/m]
};

TireEval Axle(const AxleTire& t, double static_load, double downforce, double vx, double alpha) {
  const double fz = static_load + downforce * vx * vx;
  const double d = t.mu * fz;
  const double ba = t.b * alpha;
  const double phi = t.c * std::atan(ba);
  TireEval e;
  e.f = d * std::sin(phi);
  e.df_da = d * std::cos(phi) * t.c * t.b / (1.0 + ba * ba);
  e.df_dvx = t.mu * 2.0 * downforce * vx * std::sin(phi);
  return e;
}

double PathScale(double n, double kappa, bool* clamped) {
  const double den = 1.0 - n * kappa;
  *clamped = den < 0.2;
  return 1.0 / std::max(den, 0.2);
}

// Forces and their partials w.r.t. z = (n, μ, v_x, v_y, r, δ, a).
struct Forces {
  double fyf = 0.0, fyr = 0.0;
  M::Row dfyf = M::Row::Zero(), dfyr = M::Row::Zero();
};

Forces AxleForces(const SingleTrackParams& p, const M::StateVec& x, const M::InputVec& u) {
  const double l = p.lf + p.lr;
  const double wf = p.mass * p.gravity * p.lr / l, wr = p.mass * p.gravity * p.lf / l;
  const double vx = x[M::kVx], vy = x[M::kVy], r = x[M::kR], delta = u[M::kDelta];
  const bool floor = vx < kMinVx;
  const double vxe = floor ? kMinVx : vx;
  const double qf = (vy + p.lf * r) / vxe, qr = (vy - p.lr * r) / vxe;
  const double af = delta - std::atan(qf), ar = -std::atan(qr);
  const double gf = 1.0 / ((1.0 + qf * qf) * vxe), gr = 1.0 / ((1.0 + qr * qr) * vxe);
  const TireEval tf = Axle(p.front, wf, p.downforce_front, vx, af);
  const TireEval tr = Axle(p.rear, wr, p.downforce_rear, vx, ar);
  Forces F;
  F.fyf = tf.f;
  F.fyr = tr.f;
  // ∂α/∂(v_x, v_y, r, δ)
  const double daf_dvx = floor ? 0.0 : qf * gf, daf_dvy = -gf, daf_dr = -p.lf * gf;
  const double dar_dvx = floor ? 0.0 : qr * gr, dar_dvy = -gr, dar_dr = p.lr * gr;
  F.dfyf[M::kVx] = tf.df_da * daf_dvx + tf.df_dvx;
  F.dfyf[M::kVy] = tf.df_da * daf_dvy;
  F.dfyf[M::kR] = tf.df_da * daf_dr;
  F.dfyf[M::kNx + M::kDelta] = tf.df_da;
  F.dfyr[M::kVx] = tr.df_da * dar_dvx + tr.df_dvx;
  F.dfyr[M::kVy] = tr.df_da * dar_dvy;
  F.dfyr[M::kR] = tr.df_da * dar_dr;
  return F;
}

}  // namespace

SingleTrackParams SingleTrackParamsFrom(const params::VehicleParams& v, double reference_speed) {
  SingleTrackParams p;
  p.mass = v.chassis.mass;
  p.yaw_inertia = v.chassis.yaw_inertia;
  p.lf = v.chassis.cg_to_front_axle;
  p.lr = v.chassis.wheelbase - v.chassis.cg_to_front_axle;
  p.gravity = v.chassis.gravity;
  p.downforce_front = 0.5 * v.aero.air_density * v.aero.downforce_area_front;
  p.downforce_rear = 0.5 * v.aero.air_density * v.aero.downforce_area_rear;
  const double l = v.chassis.wheelbase;
  const auto axle = [&](const params::Mf52Params& t, bool front) {
    const double statics = p.mass * p.gravity * (front ? p.lr : p.lf) / l;
    const double aero =
        (front ? p.downforce_front : p.downforce_rear) * reference_speed * reference_speed;
    const double fz = 0.5 * (statics + aero);  // per tyre
    const double fz0 = t.fnomin;
    const double dfz = (fz - fz0) / fz0;
    const auto& g = v.grip;
    const std::size_t i = front ? 0 : 2;
    const double grip =
        g.mu * (front ? g.front_mu_y : g.rear_mu_y) * 0.5 * (g.wheel_mu_y[i] + g.wheel_mu_y[i + 1]);
    AxleTire a;
    a.c = t.pcy1;
    a.mu = std::max(0.05, (t.pdy1 + t.pdy2 * dfz) * t.lmuy * grip);
    const double ky =
        std::abs(t.pky1 * fz0 * std::sin(t.pky4 * std::atan(fz / (t.pky2 * fz0))) * t.lky);
    a.b = ky / (a.c * a.mu * fz);
    return a;
  };
  p.front = axle(v.tires.front, true);
  p.rear = axle(v.tires.rear, false);
  return p;
}

double CorneringStiffness(const SingleTrackParams& p, bool front, double v) noexcept {
  const double l = p.lf + p.lr;
  const AxleTire& t = front ? p.front : p.rear;
  const double fz = p.mass * p.gravity * (front ? p.lr : p.lf) / l +
                    (front ? p.downforce_front : p.downforce_rear) * v * v;
  return t.b * t.c * t.mu * fz;
}

double UndersteerGradient(const SingleTrackParams& p, double v) noexcept {
  const double l = p.lf + p.lr;
  return p.mass / l *
         (p.lr / CorneringStiffness(p, true, v) - p.lf / CorneringStiffness(p, false, v));
}

double SingleTrackModel::PathSpeed(const StateVec& x, double kappa) noexcept {
  bool clamped = false;
  const double g = PathScale(x[kN], kappa, &clamped);
  return (x[kVx] * std::cos(x[kMu]) - x[kVy] * std::sin(x[kMu])) * g;
}

double SingleTrackModel::LateralAcceleration(const SingleTrackParams& p, const StateVec& x,
                                             const InputVec& u, Row* grad) noexcept {
  const Forces F = AxleForces(p, x, u);
  const double cd = std::cos(u[kDelta]), sd = std::sin(u[kDelta]);
  if (grad != nullptr) {
    *grad = (F.dfyf * cd + F.dfyr) / p.mass;
    (*grad)[kNx + kDelta] -= F.fyf * sd / p.mass;
  }
  return (F.fyf * cd + F.fyr) / p.mass;
}

SingleTrackModel::StateVec SingleTrackModel::Derivatives(const SingleTrackParams& p,
                                                         const StateVec& x, const InputVec& u,
                                                         double kappa, Jac* jac) noexcept {
  const double n = x[kN], mu = x[kMu], vx = x[kVx], vy = x[kVy], r = x[kR];
  const double delta = u[kDelta], a = u[kA];
  const double cm = std::cos(mu), sm = std::sin(mu), cd = std::cos(delta), sd = std::sin(delta);
  bool clamped = false;
  const double g = PathScale(n, kappa, &clamped);
  const double num = vx * cm - vy * sm;
  const double sdot = num * g;
  const Forces F = AxleForces(p, x, u);
  StateVec f;
  f[kN] = vx * sm + vy * cm;
  f[kMu] = r - kappa * sdot;
  f[kVx] = a - F.fyf * sd / p.mass + vy * r;
  f[kVy] = (F.fyf * cd + F.fyr) / p.mass - vx * r;
  f[kR] = (p.lf * F.fyf * cd - p.lr * F.fyr) / p.yaw_inertia;
  if (jac != nullptr) {
    Jac& J = *jac;
    J.setZero();
    J(kN, kMu) = vx * cm - vy * sm;
    J(kN, kVx) = sm;
    J(kN, kVy) = cm;
    Row ds = Row::Zero();
    ds[kN] = clamped ? 0.0 : num * kappa * g * g;
    ds[kMu] = (-vx * sm - vy * cm) * g;
    ds[kVx] = cm * g;
    ds[kVy] = -sm * g;
    J.row(kMu) = -kappa * ds;
    J(kMu, kR) += 1.0;
    J.row(kVx) = -F.dfyf * sd / p.mass;
    J(kVx, kNx + kDelta) -= F.fyf * cd / p.mass;
    J(kVx, kNx + kA) += 1.0;
    J(kVx, kVy) += r;
    J(kVx, kR) += vy;
    J.row(kVy) = (F.dfyf * cd + F.dfyr) / p.mass;
    J(kVy, kNx + kDelta) -= F.fyf * sd / p.mass;
    J(kVy, kVx) -= r;
    J(kVy, kR) -= vx;
    J.row(kR) = (p.lf * F.dfyf * cd - p.lr * F.dfyr) / p.yaw_inertia;
    J(kR, kNx + kDelta) -= p.lf * F.fyf * sd / p.yaw_inertia;
  }
  return f;
}

SingleTrackModel::StateVec SingleTrackModel::Discrete(const SingleTrackParams& p,
                                                      const StateVec& x0, const InputVec& u,
                                                      double kappa, double dt, int substeps,
                                                      Jac* jac) noexcept {
  const int ns = std::max(1, substeps);
  const double h = dt / ns;
  StateVec x = x0;
  // dx/dz of the current iterate, z = (x0, u).
  Jac S = Jac::Zero();
  S.leftCols<kNx>().setIdentity();
  Eigen::Matrix<double, kNu, kNz> U = Eigen::Matrix<double, kNu, kNz>::Zero();
  U(0, kNx) = 1.0;
  U(1, kNx + 1) = 1.0;
  for (int i = 0; i < ns; ++i) {
    if (jac == nullptr) {
      const StateVec k1 = Derivatives(p, x, u, kappa);
      const StateVec k2 = Derivatives(p, x + 0.5 * h * k1, u, kappa);
      const StateVec k3 = Derivatives(p, x + 0.5 * h * k2, u, kappa);
      const StateVec k4 = Derivatives(p, x + h * k3, u, kappa);
      x += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
      continue;
    }
    Jac J1, J2, J3, J4;
    const StateVec k1 = Derivatives(p, x, u, kappa, &J1);
    const Jac dk1 = J1.leftCols<kNx>() * S + J1.rightCols<kNu>() * U;
    const StateVec k2 = Derivatives(p, x + 0.5 * h * k1, u, kappa, &J2);
    const Jac dk2 = J2.leftCols<kNx>() * (S + 0.5 * h * dk1) + J2.rightCols<kNu>() * U;
    const StateVec k3 = Derivatives(p, x + 0.5 * h * k2, u, kappa, &J3);
    const Jac dk3 = J3.leftCols<kNx>() * (S + 0.5 * h * dk2) + J3.rightCols<kNu>() * U;
    const StateVec k4 = Derivatives(p, x + h * k3, u, kappa, &J4);
    const Jac dk4 = J4.leftCols<kNx>() * (S + h * dk3) + J4.rightCols<kNu>() * U;
    x += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    S += h / 6.0 * (dk1 + 2.0 * dk2 + 2.0 * dk3 + dk4);
  }
  if (jac != nullptr) *jac = S;
  return x;
}

// ---------------------------------------------------------------------------------------------
// The NLP: z = [x_0 u_0 | x_1 u_1 | … | x_{N−1} u_{N−1} | x_N | ε_1 … ε_N].
// Rows: dynamics 5N (x_{k+1} − Φ_k = 0), g-g ellipse N, steering rate N−1, corridor 2N.
struct SingleTrackMpc::Workspace final : StoredSparseNlp {
  Workspace(const NmpcOptions& o, const SingleTrackParams& model)
      : N(o.horizon_steps), opt(o), p(model), solver([&] {
          NlpSolverOptions so;
          so.max_iter = o.max_iter;
          so.tol = o.tol;
          so.acceptable_tol = 1e-3;
          so.mu_strategy = "adaptive";
          so.mu_init = 1e-2;
          so.usable_violation = 1e-2;
          return so;
        }()) {
    nv = M::kNz * N + M::kNx + N;
    m = M::kNx * N + N + (N - 1) + 2 * N;
    const auto snv = static_cast<std::size_t>(nv), sm = static_cast<std::size_t>(m);
    zl.assign(snv, -kInf);
    zu.assign(snv, kInf);
    gl.assign(sm, -kInf);
    gu.assign(sm, kInf);
    z0.assign(snv, 0.0);
    z.assign(snv, 0.0);
    kappa.assign(static_cast<std::size_t>(N), 0.0);
    ax_lim.assign(static_cast<std::size_t>(N), 1.0);
    ay_lim.assign(static_cast<std::size_t>(N), 1.0);
    qdiag.assign(snv, 0.0);
    qref.assign(snv, 0.0);
    lin.assign(snv, 0.0);
    for (int r = 0; r < M::kNx * N; ++r)
      gl[static_cast<std::size_t>(r)] = gu[static_cast<std::size_t>(r)] = 0.0;
    // Jacobian structure.
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < M::kNx; ++i) {
        Add(DynRow(k, i), Z(k + 1) + i);
        for (int j = 0; j < M::kNz; ++j) Add(DynRow(k, i), Z(k) + j);
      }
    for (int k = 0; k < N; ++k)
      for (int j = 0; j < M::kNz; ++j) Add(EllRow(k), Z(k) + j);
    for (int k = 1; k < N; ++k) {
      Add(RateRow(k), Z(k) + M::kNx + M::kDelta);
      Add(RateRow(k), Z(k - 1) + M::kNx + M::kDelta);
    }
    for (int k = 1; k <= N; ++k) {
      Add(CorRow(k), Z(k) + M::kN);
      Add(CorRow(k), E(k));
      Add(CorRow(k) + 1, Z(k) + M::kN);
      Add(CorRow(k) + 1, E(k));
    }
    // Hessian structure: dense lower 7×7 per stage, the diagonal of x_N and ε, and the Δu
    // couplings (u_k, u_{k−1}).
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < M::kNz; ++i)
        for (int j = 0; j <= i; ++j) {
          hr.push_back(Z(k) + i);
          hc.push_back(Z(k) + j);
        }
    for (int i = 0; i < M::kNx; ++i) {
      hr.push_back(Z(N) + i);
      hc.push_back(Z(N) + i);
    }
    for (int k = 1; k <= N; ++k) {
      hr.push_back(E(k));
      hc.push_back(E(k));
    }
    for (int k = 1; k < N; ++k)
      for (int j = 0; j < M::kNu; ++j) {
        hr.push_back(Z(k) + M::kNx + j);
        hc.push_back(Z(k - 1) + M::kNx + j);
      }
  }

  int Z(int k) const { return M::kNz * k; }
  int E(int k) const { return M::kNz * N + M::kNx + (k - 1); }
  int DynRow(int k, int i) const { return M::kNx * k + i; }
  int EllRow(int k) const { return M::kNx * N + k; }
  int RateRow(int k) const { return M::kNx * N + N + (k - 1); }
  int CorRow(int k) const { return M::kNx * N + N + (N - 1) + 2 * (k - 1); }
  void Add(int row, int col) {
    jr.push_back(row);
    jc.push_back(col);
  }
  M::StateVec Xk(const double* v, int k) const { return Eigen::Map<const M::StateVec>(v + Z(k)); }
  M::InputVec Uk(const double* v, int k) const {
    return Eigen::Map<const M::InputVec>(v + Z(k) + M::kNx);
  }
  double Ell(const double* v, int k, M::Row* grad) const {
    const M::StateVec x = Xk(v, k);
    const M::InputVec u = Uk(v, k);
    const double ax = ax_lim[static_cast<std::size_t>(k)], ay = ay_lim[static_cast<std::size_t>(k)];
    M::Row gay;
    const double a_y = M::LateralAcceleration(p, x, u, grad != nullptr ? &gay : nullptr);
    if (grad != nullptr) {
      *grad = 2.0 * a_y / (ay * ay) * gay;
      (*grad)[M::kNx + M::kA] += 2.0 * u[M::kA] / (ax * ax);
    }
    return u[M::kA] * u[M::kA] / (ax * ax) + a_y * a_y / (ay * ay);
  }

  // Objective: Σ qdiag_i (z_i − qref_i)² + Σ pairs r (z_a − z_b)² + lin·z.
  double PairWeight(int j) const { return j == M::kDelta ? opt.r_ddelta : opt.r_da; }
  double Objective(const double* v) const override {
    double f = 0.0;
    for (int i = 0; i < nv; ++i) {
      const double d = v[i] - qref[static_cast<std::size_t>(i)];
      f += qdiag[static_cast<std::size_t>(i)] * d * d + lin[static_cast<std::size_t>(i)] * v[i];
    }
    for (int k = 1; k < N; ++k)
      for (int j = 0; j < M::kNu; ++j) {
        const double d = v[Z(k) + M::kNx + j] - v[Z(k - 1) + M::kNx + j];
        f += PairWeight(j) * d * d;
      }
    return f;
  }
  void Gradient(const double* v, double* grad) const override {
    for (int i = 0; i < nv; ++i)
      grad[i] =
          2.0 * qdiag[static_cast<std::size_t>(i)] * (v[i] - qref[static_cast<std::size_t>(i)]) +
          lin[static_cast<std::size_t>(i)];
    for (int k = 1; k < N; ++k)
      for (int j = 0; j < M::kNu; ++j) {
        const int a = Z(k) + M::kNx + j, b = Z(k - 1) + M::kNx + j;
        const double d = 2.0 * PairWeight(j) * (v[a] - v[b]);
        grad[a] += d;
        grad[b] -= d;
      }
  }
  void Constraints(const double* v, double* g) override {
    for (int k = 0; k < N; ++k) {
      const M::StateVec next = M::Discrete(
          p, Xk(v, k), Uk(v, k), kappa[static_cast<std::size_t>(k)], opt.step, opt.substeps);
      for (int i = 0; i < M::kNx; ++i) g[DynRow(k, i)] = v[Z(k + 1) + i] - next[i];
      g[EllRow(k)] = Ell(v, k, nullptr);
    }
    for (int k = 1; k < N; ++k)
      g[RateRow(k)] = v[Z(k) + M::kNx + M::kDelta] - v[Z(k - 1) + M::kNx + M::kDelta];
    for (int k = 1; k <= N; ++k) {
      g[CorRow(k)] = v[Z(k) + M::kN] - v[E(k)];
      g[CorRow(k) + 1] = v[Z(k) + M::kN] + v[E(k)];
    }
  }
  void JacobianValues(const double* v, double* val) override {
    std::size_t e = 0;
    for (int k = 0; k < N; ++k) {
      M::Jac J;
      M::Discrete(p, Xk(v, k), Uk(v, k), kappa[static_cast<std::size_t>(k)], opt.step, opt.substeps,
                  &J);
      for (int i = 0; i < M::kNx; ++i) {
        val[e++] = 1.0;
        for (int j = 0; j < M::kNz; ++j) val[e++] = -J(i, j);
      }
    }
    for (int k = 0; k < N; ++k) {
      M::Row gr;
      Ell(v, k, &gr);
      for (int j = 0; j < M::kNz; ++j) val[e++] = gr[j];
    }
    for (int k = 1; k < N; ++k) {
      val[e++] = 1.0;
      val[e++] = -1.0;
    }
    for (int k = 1; k <= N; ++k) {
      val[e++] = 1.0;
      val[e++] = -1.0;
      val[e++] = 1.0;
      val[e++] = 1.0;
    }
  }
  // Gradient over z_k of the stage's constraint terms Σ λ_i g_i (dynamics: −λᵀΦ, ellipse).
  M::Row StageGradient(const M::StateVec& x, const M::InputVec& u, int k, const double* lambda) {
    M::Jac J;
    M::Discrete(p, x, u, kappa[static_cast<std::size_t>(k)], opt.step, opt.substeps, &J);
    M::Row g = M::Row::Zero();
    for (int i = 0; i < M::kNx; ++i) g -= lambda[DynRow(k, i)] * J.row(i);
    // Ellipse at (x, u): rebuild the stage vector.
    double tmp[M::kNz];
    for (int i = 0; i < M::kNx; ++i) tmp[i] = x[i];
    tmp[M::kNx] = u[0];
    tmp[M::kNx + 1] = u[1];
    M::Row ge;
    EllAt(tmp, k, &ge);
    g += lambda[EllRow(k)] * ge;
    return g;
  }
  void EllAt(const double* zk, int k, M::Row* grad) const {
    const M::StateVec x = Eigen::Map<const M::StateVec>(zk);
    const M::InputVec u = Eigen::Map<const M::InputVec>(zk + M::kNx);
    const double ax = ax_lim[static_cast<std::size_t>(k)], ay = ay_lim[static_cast<std::size_t>(k)];
    M::Row gay;
    const double a_y = M::LateralAcceleration(p, x, u, &gay);
    *grad = 2.0 * a_y / (ay * ay) * gay;
    (*grad)[M::kNx + M::kA] += 2.0 * u[M::kA] / (ax * ax);
  }
  void HessianValues(const double* v, double obj_factor, const double* lambda,
                     double* val) override {
    std::size_t e = 0;
    for (int k = 0; k < N; ++k) {
      // Central differences of the analytic stage gradient.
      Eigen::Matrix<double, M::kNz, M::kNz> H;
      const M::StateVec x = Xk(v, k);
      const M::InputVec u = Uk(v, k);
      for (int j = 0; j < M::kNz; ++j) {
        const double zj = j < M::kNx ? x[j] : u[j - M::kNx];
        const double hstep = 1e-5 * std::max(1.0, std::abs(zj));
        M::StateVec xp = x, xm = x;
        M::InputVec up = u, um = u;
        if (j < M::kNx) {
          xp[j] += hstep;
          xm[j] -= hstep;
        } else {
          up[j - M::kNx] += hstep;
          um[j - M::kNx] -= hstep;
        }
        H.col(j) =
            ((StageGradient(xp, up, k, lambda) - StageGradient(xm, um, k, lambda)) / (2.0 * hstep))
                .transpose();
      }
      H = 0.5 * (H + H.transpose()).eval();
      for (int i = 0; i < M::kNz; ++i)
        for (int j = 0; j <= i; ++j) {
          double h = H(i, j);
          if (i == j) h += obj_factor * 2.0 * qdiag[static_cast<std::size_t>(Z(k) + i)];
          val[e++] = h;
        }
    }
    // Δu pair contributions on the stage diagonals.
    for (int k = 1; k < N; ++k)
      for (int j = 0; j < M::kNu; ++j) {
        const double w = obj_factor * 2.0 * PairWeight(j);
        val[DiagEntry(k, M::kNx + j)] += w;
        val[DiagEntry(k - 1, M::kNx + j)] += w;
      }
    for (int i = 0; i < M::kNx; ++i)
      val[e++] = obj_factor * 2.0 * qdiag[static_cast<std::size_t>(Z(N) + i)];
    for (int k = 1; k <= N; ++k)
      val[e++] = obj_factor * 2.0 * qdiag[static_cast<std::size_t>(E(k))];
    for (int k = 1; k < N; ++k)
      for (int j = 0; j < M::kNu; ++j) val[e++] = -obj_factor * 2.0 * PairWeight(j);
  }
  // Index of the diagonal entry (i, i) of stage k's lower-triangular block.
  std::size_t DiagEntry(int k, int i) const {
    const int per = M::kNz * (M::kNz + 1) / 2;
    return static_cast<std::size_t>(k * per + i * (i + 1) / 2 + i);
  }

  int N;
  NmpcOptions opt;
  SingleTrackParams p;
  std::vector<double> kappa, ax_lim, ay_lim, qdiag, qref, lin;
  NlpSolver solver;
};

namespace {

// Plan state i at time tau (linear between nodes, held outside).
double StateAt(const SingleTrackMpc::Plan& p, int i, double tau, double dt) {
  const int nodes = static_cast<int>(p.s.size());
  const double x = std::clamp(tau / dt, 0.0, static_cast<double>(nodes - 1));
  const int k = std::min(static_cast<int>(x), nodes - 2);
  const double w = x - k;
  const auto a = static_cast<std::size_t>(k * M::kNx + i), b = a + M::kNx;
  return p.x[a] + w * (p.x[b] - p.x[a]);
}

double InputAt(const SingleTrackMpc::Plan& p, int j, double tau, double dt) {
  const int steps = static_cast<int>(p.kappa.size());
  const int k = std::clamp(static_cast<int>(std::floor(tau / dt + 1e-9)), 0, steps - 1);
  return p.u[static_cast<std::size_t>(k * M::kNu + j)];
}

}  // namespace

void SingleTrackMpc::Plan::Resize(int steps) {
  x.assign(static_cast<std::size_t>((steps + 1) * M::kNx), 0.0);
  u.assign(static_cast<std::size_t>(steps * M::kNu), 0.0);
  s.assign(static_cast<std::size_t>(steps + 1), 0.0);
  kappa.assign(static_cast<std::size_t>(steps), 0.0);
  valid = false;
}

SingleTrackMpc::State::State(const SingleTrackMpc& c)
    : MpcState(c.options_.horizon_steps), ws(std::make_unique<Workspace>(c.options_, c.model_)) {}
SingleTrackMpc::State::~State() = default;

SingleTrackMpc::SingleTrackMpc(const NmpcOptions& options, const SingleTrackParams& model,
                               GgTable limits, Corridor corridor, std::shared_ptr<const Path> path)
    : MpcController(std::move(limits), std::move(corridor), std::move(path)),
      options_(options),
      model_(model) {
  Problems pr = ValidateInputs();
  const auto& o = options_;
  pr.Append(params::Validate(static_cast<const params::NmpcParams&>(o)));  // bounds
  const auto positive = [&pr](double v, const char* key) {
    if (!(v > 0.0)) pr.Add(key, "must be positive, is " + params::FormatNumber(v));
  };
  positive(model_.mass, "model.mass");
  positive(model_.yaw_inertia, "model.yaw_inertia");
  positive(model_.lf, "model.lf");
  positive(model_.lr, "model.lr");
  positive(model_.front.mu, "model.front.mu");
  positive(model_.rear.mu, "model.rear.mu");
  positive(model_.front.b, "model.front.b");
  positive(model_.rear.b, "model.rear.b");
  positive(o.max_steering, "max_steering");  // the vehicle's
  if (!pr.empty()) throw ConfigError("nmpc", pr.items());
}

SingleTrackMpc::~SingleTrackMpc() = default;

std::unique_ptr<MotionState> SingleTrackMpc::MakeState() const {
  return std::make_unique<State>(*this);
}

bool SingleTrackMpc::Solve(const MotionInput& in, double s, const M::StateVec& x0,
                           State* st) const {
  const auto& o = options_;
  const int N = o.horizon_steps;
  const double dt = o.step;
  const Path& path = this->path();
  Workspace& ws = *st->ws;
  Plan& lin = st->scratch;
  const Plan& prev = st->plan;
  const double tau = in.t - prev.t0;
  const bool shift = prev.valid && tau < (N - 1) * dt;
  const double l = model_.lf + model_.lr;

  // 1. Warm start / linearisation trajectory.
  for (int i = 0; i < M::kNx; ++i) lin.x[static_cast<std::size_t>(i)] = x0[i];
  lin.s[0] = s;
  for (int k = 0; k < N; ++k) {
    const auto K = static_cast<std::size_t>(k);
    M::StateVec xk = Eigen::Map<const M::StateVec>(&lin.x[K * M::kNx]);
    double delta, a;
    if (shift) {
      delta = InputAt(prev, M::kDelta, tau + k * dt, dt);
      a = InputAt(prev, M::kA, tau + k * dt, dt);
    } else {
      const PathPoint r0 = path.Sample(lin.s[K]);
      const double v = std::max(xk[M::kVx], o.min_speed);
      delta = std::atan(l * r0.kappa) + UndersteerGradient(model_, v) * r0.kappa * v * v;
      a = std::clamp((path.Sample(lin.s[K] + v * dt).v - v) / dt, -limits().AxBrakeMax(v),
                     limits().AxDriveMax(v));
    }
    delta = std::clamp(delta, -o.max_steering, o.max_steering);
    lin.u[K * M::kNu + M::kDelta] = delta;
    lin.u[K * M::kNu + M::kA] = a;
    // Predict with the model along the reference curvature to get the stations.
    const double s_guess = lin.s[K] + dt * std::max(xk[M::kVx], o.min_speed);
    lin.kappa[K] = MeanCurvature(path, lin.s[K], s_guess);
    const M::StateVec xn =
        M::Discrete(model_, xk, M::InputVec(delta, a), lin.kappa[K], dt, o.substeps);
    M::StateVec next = xn;
    if (shift) {
      for (int i = 0; i < M::kNx; ++i) next[i] = StateAt(prev, i, tau + (k + 1) * dt, dt);
    }
    if (!next.allFinite()) next = xk;
    next[M::kVx] = std::max(next[M::kVx], o.min_speed);
    for (int i = 0; i < M::kNx; ++i)
      lin.x[(K + 1) * M::kNx + static_cast<std::size_t>(i)] = next[i];
    lin.s[K + 1] =
        lin.s[K] + 0.5 * dt * (M::PathSpeed(xk, lin.kappa[K]) + M::PathSpeed(next, lin.kappa[K]));
    lin.kappa[K] = MeanCurvature(path, lin.s[K], lin.s[K + 1]);
  }

  // 2. The NLP data.
  std::fill(ws.qdiag.begin(), ws.qdiag.end(), 0.0);
  std::fill(ws.qref.begin(), ws.qref.end(), 0.0);
  std::fill(ws.lin.begin(), ws.lin.end(), 0.0);
  for (int k = 0; k <= N; ++k) {
    const auto K = static_cast<std::size_t>(k);
    const auto zk = static_cast<std::size_t>(ws.Z(k));
    for (int i = 0; i < M::kNx; ++i) {
      ws.z0[zk + static_cast<std::size_t>(i)] = lin.x[K * M::kNx + static_cast<std::size_t>(i)];
      ws.zl[zk + static_cast<std::size_t>(i)] = k == 0 ? x0[i] : -kInf;
      ws.zu[zk + static_cast<std::size_t>(i)] = k == 0 ? x0[i] : kInf;
    }
    if (k > 0) {
      ws.zl[zk + M::kVx] = o.min_speed;
      const double tf = k == N ? o.terminal_factor : 1.0;
      ws.qdiag[zk + M::kN] = o.q_n * tf;
      ws.qdiag[zk + M::kMu] = o.q_mu * tf;
      ws.qdiag[zk + M::kVx] = o.q_v * tf;
      ws.qref[zk + M::kVx] = path.Sample(lin.s[K]).v;
      const auto e = static_cast<std::size_t>(ws.E(k));
      ws.zl[e] = 0.0;
      ws.qdiag[e] = o.slack_l2;
      ws.lin[e] = o.slack_l1;
      double lo = 0.0, up = 0.0;
      CorridorBounds(lin.s[K], o.margin, &lo, &up);
      const auto row = static_cast<std::size_t>(ws.CorRow(k));
      ws.gu[row] = up;
      ws.gl[row + 1] = lo;
      const double nk = lin.x[K * M::kNx + M::kN];
      ws.z0[e] = std::max({0.0, nk - up, lo - nk}) + 1e-3;
    }
    if (k < N) {
      const double vb = std::max(lin.x[K * M::kNx + M::kVx], o.min_speed);
      ws.kappa[K] = lin.kappa[K];
      ws.ax_lim[K] = o.accel_fraction * limits().AxBrakeMax(vb);
      ws.ay_lim[K] = o.accel_fraction * limits().AyMax(vb);
      ws.gu[static_cast<std::size_t>(ws.EllRow(k))] = 1.0;
      const auto ud = zk + M::kNx + M::kDelta, ua = zk + M::kNx + M::kA;
      ws.z0[ud] = lin.u[K * M::kNu + M::kDelta];
      ws.z0[ua] = lin.u[K * M::kNu + M::kA];
      ws.zl[ud] = -o.max_steering;
      ws.zu[ud] = o.max_steering;
      ws.zl[ua] = -1.2 * ws.ax_lim[K];
      ws.zu[ua] = std::max(o.accel_fraction * limits().AxDriveMax(vb), 0.0);
      ws.z0[ua] = std::clamp(ws.z0[ua], ws.zl[ua], ws.zu[ua]);
      ws.qdiag[ua] = o.r_a;
      ws.qref[ua] = path.Sample(lin.s[K]).a_x;
      if (k > 0) {
        const auto row = static_cast<std::size_t>(ws.RateRow(k));
        ws.gl[row] = -o.max_steering_rate * dt;
        ws.gu[row] = o.max_steering_rate * dt;
      }
    }
  }
  // The first input: steering rate from the applied steering, Δ penalties to the applied inputs.
  {
    const auto ud = static_cast<std::size_t>(ws.Z(0) + M::kNx + M::kDelta);
    const auto ua = static_cast<std::size_t>(ws.Z(0) + M::kNx + M::kA);
    const double rate = o.max_steering_rate * o.sample_time;
    ws.zl[ud] = std::max(-o.max_steering, st->prev_delta - rate);
    ws.zu[ud] = std::min(o.max_steering, st->prev_delta + rate);
    ws.z0[ud] = std::clamp(ws.z0[ud], ws.zl[ud], ws.zu[ud]);
    // (z − r1)²·w1 + (z − r2)²·w2 = (w1 + w2)(z − (w1 r1 + w2 r2)/(w1 + w2))² + const.
    const double w1 = ws.qdiag[ua], r1 = ws.qref[ua];
    ws.qdiag[ua] = w1 + o.r_da;
    ws.qref[ua] = (w1 * r1 + o.r_da * st->prev_a) / (w1 + o.r_da);
    ws.qdiag[ud] = o.r_ddelta;
    ws.qref[ud] = st->prev_delta;
  }

  // 3. Solve.
  if (!TimedSolve(&ws.solver, &ws, &st->diagnostics)) return false;
  for (double v : ws.z)
    if (!std::isfinite(v)) return false;

  // 4. The new plan.
  Plan& p = st->plan;
  for (int k = 0; k <= N; ++k) {
    const auto K = static_cast<std::size_t>(k);
    for (int i = 0; i < M::kNx; ++i)
      p.x[K * M::kNx + static_cast<std::size_t>(i)] = ws.z[static_cast<std::size_t>(ws.Z(k) + i)];
    if (k < N) {
      p.u[K * M::kNu + M::kDelta] = ws.z[static_cast<std::size_t>(ws.Z(k) + M::kNx + M::kDelta)];
      p.u[K * M::kNu + M::kA] = ws.z[static_cast<std::size_t>(ws.Z(k) + M::kNx + M::kA)];
      p.kappa[K] = ws.kappa[K];
    }
  }
  p.s[0] = s;
  for (int k = 0; k < N; ++k) {
    const auto K = static_cast<std::size_t>(k);
    const M::StateVec a = Eigen::Map<const M::StateVec>(&p.x[K * M::kNx]);
    const M::StateVec b = Eigen::Map<const M::StateVec>(&p.x[(K + 1) * M::kNx]);
    p.s[K + 1] = p.s[K] + 0.5 * dt * (M::PathSpeed(a, p.kappa[K]) + M::PathSpeed(b, p.kappa[K]));
  }
  p.t0 = in.t;
  p.valid = true;
  return true;
}

MotionOutput SingleTrackMpc::Step(const MotionInput& in, MotionState* base) const noexcept {
  auto* st = static_cast<State*>(base);
  const auto& o = options_;
  MotionOutput out;
  const double v_x = std::isfinite(in.v_x) ? in.v_x : 0.0;
  const double v_y = std::isfinite(in.v_y) ? in.v_y : 0.0;
  const double r = std::isfinite(in.yaw_rate) ? in.yaw_rate : 0.0;
  PathPoint ref;
  const PathProjection here = Locate(in, o.projection_window, st, &out, &ref);

  const M::StateVec x0(here.lateral_error, here.heading_error, std::max(v_x, o.min_speed), v_y, r);
  SolveOrHold(in.t, (o.horizon_steps - 1) * o.step, &st->plan, &st->diagnostics,
              [&] { return Solve(in, here.s, x0, st); });

  double delta = 0.0, a = 0.0;
  if (FollowPlan(st->plan, &st->diagnostics)) {
    const Plan& p = st->plan;
    const double tau = in.t - p.t0;
    delta = InputAt(p, M::kDelta, tau, o.step);
    a = InputAt(p, M::kA, tau, o.step);
    M::StateVec x1;
    for (int i = 0; i < M::kNx; ++i) x1[i] = StateAt(p, i, tau + o.step, o.step);
    const M::InputVec u1(InputAt(p, M::kDelta, tau + o.step, o.step),
                         InputAt(p, M::kA, tau + o.step, o.step));
    out.ay_request = M::LateralAcceleration(model_, x1, u1);
    out.yaw_rate_request = x1[M::kR];
    out.beta_request = std::atan2(x1[M::kVy], std::max(x1[M::kVx], 1.0));
  } else {
    // Fallback: pure-pursuit-like geometry on the reference with the speed profile.
    const double v = std::max(v_x, o.min_speed);
    const double look = std::max(o.fallback_min_lookahead, o.fallback_lookahead_time * v);
    const PathPoint goal = path().Sample(here.s + look);
    const double dx = goal.x - in.x, dy = goal.y - in.y;
    const double d_lat = -std::sin(in.psi) * dx + std::cos(in.psi) * dy;
    const double kappa = 2.0 * d_lat / (look * look);
    delta =
        std::atan((model_.lf + model_.lr) * kappa) + UndersteerGradient(model_, v) * kappa * v * v;
    a = ref.a_x + 0.5 * (ref.v - v);
    out.ay_request = kappa * v * v;
  }
  if (!std::isfinite(delta)) delta = 0.0;
  if (!std::isfinite(a)) a = 0.0;
  out.steering_request = std::clamp(delta, -o.max_steering, o.max_steering);
  out.ax_request = a;
  st->prev_delta = out.steering_request;
  st->prev_a = a;
  if (!std::isfinite(out.ay_request)) out.ay_request = 0.0;
  if (!std::isfinite(out.yaw_rate_request)) out.yaw_rate_request = std::nan("");
  if (!std::isfinite(out.beta_request)) out.beta_request = std::nan("");
  return out;
}

}  // namespace scw::controller::motion
