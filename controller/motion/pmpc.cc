#include "controller/motion/pmpc.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "controller/motion/nlp_solver.h"

namespace scw::controller::motion {
namespace {

constexpr double kInf = 1e19;  // Ipopt's "no bound"

// Vertices of the inscribed g-g polygon in r = |a_n|/ay_max.
constexpr double kPolygonR[] = {0.0, 0.5, 0.85, 1.0};
constexpr std::size_t kPolygonSides = std::size(kPolygonR) - 1;
constexpr double kExponentMin = 1.0, kExponentStep = 0.05;
constexpr int kExponentGrid = 41;  // p = 1.0 … 3.0; larger exponents use the polygon of 3.0

double CentripetalScale(double n, double kappa) { return 1.0 / std::max(1.0 - n * kappa, 0.2); }

}  // namespace

PointMassModel::StateVec PointMassModel::Step(const StateVec& x, const InputVec& u, double kappa,
                                              double dt) noexcept {
  const double c = kappa * x[kV] * x[kV] * CentripetalScale(x[kN], kappa);
  const double an = u[kAn] - c;
  return {x[kN] + dt * x[kW] + 0.5 * dt * dt * an, x[kW] + dt * an, x[kV] + dt * u[kAt]};
}

void PointMassModel::Jacobians(const StateVec& x, const InputVec&, double kappa, double dt,
                               Eigen::Matrix3d* a, Eigen::Matrix<double, 3, 2>* b) noexcept {
  const double den = 1.0 - x[kN] * kappa;
  const double g = CentripetalScale(x[kN], kappa);
  // ∂c/∂n (zero where the denominator is clamped) and ∂c/∂v.
  const double dc_dn = den > 0.2 ? kappa * kappa * x[kV] * x[kV] * g * g : 0.0;
  const double dc_dv = 2.0 * kappa * x[kV] * g;
  const double h2 = 0.5 * dt * dt;
  *a << 1.0 - h2 * dc_dn, dt, -h2 * dc_dv,  //
      -dt * dc_dn, 1.0, -dt * dc_dv,        //
      0.0, 0.0, 1.0;
  *b << 0.0, h2,  //
      0.0, dt,    //
      dt, 0.0;
}

// ---------------------------------------------------------------------------------------------
// The QP: z = [x_0 .. x_N (n, w, v), u_0 .. u_{N-1} (a_t, a_n), ε_1 .. ε_N],
// min ½ zᵀHz + lᵀz, rows: dynamics (3N, equalities), corridor (2N), g-g polygon (4·S·N).
struct PointMassMpc::Workspace final : StoredSparseNlp {
  Workspace(const PmpcOptions& o, int segments)
      : N(o.horizon_steps), S(segments), solver([&] {
          NlpSolverOptions so;
          so.quadratic = true;  // constant Jacobian and Hessian
          so.linear_solver = o.mumps ? NlpSolverOptions::LinearSolver::kMumps
                                     : NlpSolverOptions::LinearSolver::kQuasiDefiniteLdl;
          so.max_iter = o.max_iter;
          so.tol = o.tol;
          so.mu_strategy = "monotone";
          so.mu_init = 1e-1;
          so.min_refinement_steps = 0;  // Ipopt still refines when the residual asks for it
          so.warm_start = o.warm_start;
          return so;
        }()) {
    nv = 3 * (N + 1) + 2 * N + N;
    m = 3 * N + 2 * N + 4 * S * N;
    zl.assign(nv, -kInf);
    zu.assign(nv, kInf);
    gl.assign(m, -kInf);
    gu.assign(m, kInf);
    z0.assign(nv, 0.0);
    z.assign(nv, 0.0);
    lin.assign(nv, 0.0);
    // Jacobian structure.
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < 3; ++i) {
        const int row = 3 * k + i;
        Add(row, X(k + 1, i));
        for (int j = 0; j < 3; ++j) Add(row, X(k, j));
        for (int j = 0; j < 2; ++j) Add(row, U(k, j));
      }
    for (int k = 1; k <= N; ++k) {
      const int row = 3 * N + 2 * (k - 1);
      Add(row, X(k, 0));
      Add(row, E(k));
      Add(row + 1, X(k, 0));
      Add(row + 1, E(k));
    }
    for (int k = 0; k < N; ++k)
      for (int r = 0; r < 4 * S; ++r) {
        Add(GgRow(k, r), U(k, 0));
        Add(GgRow(k, r), U(k, 1));
      }
    jv.assign(jr.size(), 0.0);
    // Hessian: the diagonal, then the Δu couplings u_k–u_{k−1}.
    for (int i = 0; i < nv; ++i) {
      hr.push_back(i);
      hc.push_back(i);
    }
    for (int k = 1; k < N; ++k)
      for (int j = 0; j < 2; ++j) {
        hr.push_back(U(k, j));
        hc.push_back(U(k - 1, j));
      }
    hv.assign(hr.size(), 0.0);
    for (auto* v : {&zl_mult, &zu_mult, &new_zl_mult, &new_zu_mult}) v->assign(nv, 0.0);
    for (auto* v : {&g_mult, &new_g_mult}) v->assign(m, 0.0);
  }

  int X(int k, int i) const { return 3 * k + i; }
  int U(int k, int j) const { return 3 * (N + 1) + 2 * k + j; }
  int E(int k) const { return 3 * (N + 1) + 2 * N + (k - 1); }
  int GgRow(int k, int r) const { return 5 * N + 4 * S * k + r; }
  void Add(int row, int col) {
    jr.push_back(row);
    jc.push_back(col);
  }

  // weight·(z_i − ref)²
  void Quad(int i, double weight, double ref) {
    hv[static_cast<std::size_t>(i)] += 2.0 * weight;
    lin[static_cast<std::size_t>(i)] -= 2.0 * weight * ref;
  }

  double Objective(const double* x) const override {
    double f = 0.0;
    for (std::size_t e = 0; e < hr.size(); ++e) {
      const double p = hv[e] * x[hr[e]] * x[hc[e]];
      f += hr[e] == hc[e] ? 0.5 * p : p;
    }
    for (int i = 0; i < nv; ++i) f += lin[static_cast<std::size_t>(i)] * x[i];
    return f;
  }
  void Gradient(const double* x, double* grad) const override {
    std::copy(lin.begin(), lin.end(), grad);
    for (std::size_t e = 0; e < hr.size(); ++e) {
      grad[hr[e]] += hv[e] * x[hc[e]];
      if (hr[e] != hc[e]) grad[hc[e]] += hv[e] * x[hr[e]];
    }
  }
  void Constraints(const double* x, double* g) override {
    std::fill(g, g + m, 0.0);
    for (std::size_t e = 0; e < jr.size(); ++e) g[jr[e]] += jv[e] * x[jc[e]];
  }
  void JacobianValues(const double*, double* values) override {
    std::copy(jv.begin(), jv.end(), values);
  }
  void HessianValues(const double*, double obj_factor, const double*, double* values) override {
    for (std::size_t e = 0; e < hv.size(); ++e) values[e] = obj_factor * hv[e];
  }

  // Warm start: the multipliers of the plan in use, shifted in time like the primal start
  // (stage k of the new problem takes stage k + mult_shift of the old one, interpolated linearly
  // and held at the ends). Kept only from usable solves (see PointMassMpc::Solve).
  bool StartMultipliers(double* z_l, double* z_u, double* lambda) const override {
    if (!(mult_shift >= 0.0)) return false;
    // value(k) of a stage-indexed quantity with stages k0..k1 at index idx(k).
    const auto shifted = [this](const std::vector<double>& from, double* to, int k0, int k1,
                                const auto& idx) {
      for (int k = k0; k <= k1; ++k) {
        const double x =
            std::clamp(k + mult_shift, static_cast<double>(k0), static_cast<double>(k1));
        const int i = std::min(static_cast<int>(x), k1 - (k1 > k0 ? 1 : 0));
        const double w = k1 > k0 ? x - i : 0.0;
        const double a = from[static_cast<std::size_t>(idx(i))];
        const double b = from[static_cast<std::size_t>(idx(std::min(i + 1, k1)))];
        to[idx(k)] = a + w * (b - a);
      }
    };
    for (int pass = 0; pass < 2; ++pass) {
      const std::vector<double>& from = pass == 0 ? zl_mult : zu_mult;
      double* to = pass == 0 ? z_l : z_u;
      for (int i = 0; i < 3; ++i) shifted(from, to, 0, N, [&](int k) { return X(k, i); });
      for (int j = 0; j < 2; ++j) shifted(from, to, 0, N - 1, [&](int k) { return U(k, j); });
      shifted(from, to, 1, N, [&](int k) { return E(k); });
    }
    for (int i = 0; i < 3; ++i) shifted(g_mult, lambda, 0, N - 1, [&](int k) { return 3 * k + i; });
    for (int r = 0; r < 2; ++r)
      shifted(g_mult, lambda, 1, N, [&](int k) { return 3 * N + 2 * (k - 1) + r; });
    for (int r = 0; r < 4 * S; ++r)
      shifted(g_mult, lambda, 0, N - 1, [&](int k) { return GgRow(k, r); });
    return true;
  }
  void SolutionMultipliers(const double* z_l, const double* z_u, const double* lambda) override {
    std::copy(z_l, z_l + nv, new_zl_mult.begin());
    std::copy(z_u, z_u + nv, new_zu_mult.begin());
    std::copy(lambda, lambda + m, new_g_mult.begin());
  }

  int N, S;
  std::vector<double> lin;
  std::vector<double> jv, hv;
  // Multipliers of the plan in use and of the last solve; shift of the next warm start in steps
  // (< 0: cold start).
  std::vector<double> zl_mult, zu_mult, g_mult, new_zl_mult, new_zu_mult, new_g_mult;
  double mult_shift = -1.0;
  NlpSolver solver;
};

namespace {

// Linear interpolation of node values at time tau after node 0 (held outside).
double NodeAt(const std::vector<double>& v, double tau, double dt) {
  const double x = tau / dt;
  if (x <= 0.0) return v.front();
  const auto last = static_cast<double>(v.size() - 1);
  if (x >= last) return v.back();
  const auto i = static_cast<std::size_t>(x);
  const double w = x - static_cast<double>(i);
  return v[i] + w * (v[i + 1] - v[i]);
}

// Interval value (piecewise constant input) at time tau after node 0.
double IntervalAt(const std::vector<double>& u, double tau, double dt) {
  const double x = std::floor(tau / dt + 1e-9);
  if (x <= 0.0) return u.front();
  const auto i = std::min(static_cast<std::size_t>(x), u.size() - 1);
  return u[i];
}

}  // namespace

void PointMassMpc::Plan::Resize(int steps) {
  const auto nodes = static_cast<std::size_t>(steps + 1), ints = static_cast<std::size_t>(steps);
  for (auto* x : {&n, &w, &v, &s}) x->assign(nodes, 0.0);
  for (auto* x : {&at, &an, &kappa}) x->assign(ints, 0.0);
  valid = false;
}

PointMassMpc::State::State(const PointMassMpc& c)
    : MpcState(c.options_.horizon_steps),
      ws(std::make_unique<Workspace>(c.options_, static_cast<int>(kPolygonSides))) {}
PointMassMpc::State::~State() = default;

PointMassMpc::PointMassMpc(const PmpcOptions& options, GgTable limits, Corridor corridor,
                           std::shared_ptr<const Path> path)
    : MpcController(std::move(limits), std::move(corridor), std::move(path)),
      options_(options),
      esc_target_(options.esc_target == "commanded"  ? EscTarget::kCommanded
                  : options.esc_target == "steering" ? EscTarget::kSteering
                                                     : EscTarget::kPlan),
      provided_limits_(options.limits == "provided") {
  Problems pr = ValidateInputs();
  const auto& o = options_;
  pr.Append(params::Validate(static_cast<const params::PmpcParams&>(o)));  // bounds, cross-checks
  const auto positive = [&pr](double v, const char* key) {
    if (!(v > 0.0)) pr.Add(key, "must be positive, is " + params::FormatNumber(v));
  };
  // What the vehicle and the tracking loop fix.
  positive(o.sample_time, "sample_time");
  if (!(o.solve_period >= o.sample_time))
    pr.Add("solve_period", "must be at least sample_time (" + params::FormatNumber(o.sample_time) +
                               " s), is " + params::FormatNumber(o.solve_period));
  positive(o.wheelbase, "wheelbase");
  positive(o.max_steering, "max_steering");
  if (!pr.empty()) throw ConfigError("pmpc", pr.items());
  // Inscribed polygons of (1 − r^p)^(1/p) for p on a grid; each node uses the polygon of the
  // largest grid exponent not above the table's drive or brake exponent at its speed (inside).
  for (int q = 0; q < kExponentGrid; ++q) {
    const double p = kExponentMin + kExponentStep * q;
    const auto x_of = [p](double r) {
      return std::pow(std::max(0.0, 1.0 - std::pow(r, p)), 1 / p);
    };
    for (std::size_t j = 0; j + 1 < std::size(kPolygonR); ++j) {
      const double r0 = kPolygonR[j], r1 = kPolygonR[j + 1];
      const double m = (x_of(r1) - x_of(r0)) / (r1 - r0);
      slope_.push_back(m);
      offset_.push_back(x_of(r0) - m * r0);
    }
  }
}

std::size_t PointMassMpc::PolygonBase(double p) const noexcept {
  const int q = std::clamp(static_cast<int>(std::floor((p - kExponentMin) / kExponentStep + 1e-9)),
                           0, kExponentGrid - 1);
  return static_cast<std::size_t>(q) * kPolygonSides;
}

PointMassMpc::~PointMassMpc() = default;

std::unique_ptr<MotionState> PointMassMpc::MakeState() const {
  return std::make_unique<State>(*this);
}

bool PointMassMpc::Solve(const MotionInput& in, double s, double n, double w, double v,
                         State* st) const {
  const auto& o = options_;
  const int N = o.horizon_steps;
  const double dt = o.step;
  const Path& path = this->path();
  Workspace& ws = *st->ws;
  Plan& lin = st->scratch;
  const Plan& prev = st->plan;
  const double tau = in.t - prev.t0;
  const bool shift = prev.valid && tau < N * dt;

  // 1. Linearisation trajectory: the previous plan shifted by tau, or the reference.
  lin.n[0] = n;
  lin.w[0] = w;
  lin.v[0] = v;
  lin.s[0] = s;
  for (int k = 0; k <= N; ++k) {
    const auto K = static_cast<std::size_t>(k);
    if (k > 0) {
      if (shift) {
        lin.n[K] = NodeAt(prev.n, tau + k * dt, dt);
        lin.w[K] = NodeAt(prev.w, tau + k * dt, dt);
        lin.v[K] = std::max(NodeAt(prev.v, tau + k * dt, dt), o.min_speed);
      } else {
        lin.n[K] = 0.0;
        lin.w[K] = 0.0;
        lin.v[K] = std::max(path.Sample(lin.s[K]).v, o.min_speed);
      }
    }
    if (k < N) {
      const double ds = dt * std::max(lin.v[K], o.min_speed);
      lin.s[K + 1] = lin.s[K] + ds;  // first guess for the cold start; refined below
    }
  }
  for (int k = 0; k < N; ++k) {
    const auto K = static_cast<std::size_t>(k);
    lin.s[K + 1] = lin.s[K] + 0.5 * dt * (lin.v[K] + lin.v[K + 1]);
    lin.kappa[K] = MeanCurvature(path, lin.s[K], lin.s[K + 1]);
    if (shift) {
      lin.at[K] = IntervalAt(prev.at, tau + k * dt, dt);
      lin.an[K] = IntervalAt(prev.an, tau + k * dt, dt);
    } else {
      lin.at[K] = (lin.v[K + 1] - lin.v[K]) / dt;
      lin.an[K] = lin.kappa[K] * lin.v[K] * lin.v[K];
    }
  }

  // 2. The QP around it.
  std::fill(ws.hv.begin(), ws.hv.end(), 0.0);
  std::fill(ws.lin.begin(), ws.lin.end(), 0.0);
  std::size_t e = 0;  // Jacobian entry (same order as the structure)
  const double x0[3] = {n, w, v};
  for (int i = 0; i < 3; ++i) {
    ws.zl[static_cast<std::size_t>(ws.X(0, i))] = x0[i];
    ws.zu[static_cast<std::size_t>(ws.X(0, i))] = x0[i];
    ws.z0[static_cast<std::size_t>(ws.X(0, i))] = x0[i];
  }
  for (int k = 0; k < N; ++k) {
    const auto K = static_cast<std::size_t>(k);
    const PointMassModel::StateVec xb(lin.n[K], lin.w[K], lin.v[K]);
    const PointMassModel::InputVec ub(lin.at[K], lin.an[K]);
    Eigen::Matrix3d a;
    Eigen::Matrix<double, 3, 2> b;
    PointMassModel::Jacobians(xb, ub, lin.kappa[K], dt, &a, &b);
    const PointMassModel::StateVec rhs =
        PointMassModel::Step(xb, ub, lin.kappa[K], dt) - a * xb - b * ub;
    for (int i = 0; i < 3; ++i) {
      ws.jv[e++] = 1.0;
      for (int j = 0; j < 3; ++j) ws.jv[e++] = -a(i, j);
      for (int j = 0; j < 2; ++j) ws.jv[e++] = -b(i, j);
      ws.gl[static_cast<std::size_t>(3 * k + i)] = rhs[i];
      ws.gu[static_cast<std::size_t>(3 * k + i)] = rhs[i];
    }
  }
  for (int k = 1; k <= N; ++k) {
    const auto K = static_cast<std::size_t>(k);
    double lo = 0.0, up = 0.0;
    CorridorBounds(lin.s[K], o.tube_lateral, &lo, &up);
    const auto row = static_cast<std::size_t>(3 * N + 2 * (k - 1));
    ws.jv[e++] = 1.0;
    ws.jv[e++] = -1.0;
    ws.jv[e++] = 1.0;
    ws.jv[e++] = 1.0;
    ws.gl[row] = -kInf;
    ws.gu[row] = up;
    ws.gl[row + 1] = lo;
    ws.gu[row + 1] = kInf;
    const double tf = k == N ? o.terminal_factor : 1.0;
    ws.Quad(ws.X(k, 0), o.q_n * tf, 0.0);
    ws.Quad(ws.X(k, 1), o.q_w * tf, 0.0);
    const PathPoint ref = path.Sample(lin.s[K]);
    ws.Quad(ws.X(k, 2), o.q_v * tf, ref.v);
    ws.zl[static_cast<std::size_t>(ws.X(k, 2))] = o.min_speed;
    ws.zl[static_cast<std::size_t>(ws.E(k))] = 0.0;
    ws.Quad(ws.E(k), o.slack_l2, 0.0);
    ws.lin[static_cast<std::size_t>(ws.E(k))] += o.slack_l1;
    // Start point: the linearisation trajectory, slack = its corridor violation.
    ws.z0[static_cast<std::size_t>(ws.X(k, 0))] = lin.n[K];
    ws.z0[static_cast<std::size_t>(ws.X(k, 1))] = lin.w[K];
    ws.z0[static_cast<std::size_t>(ws.X(k, 2))] = lin.v[K];
    ws.z0[static_cast<std::size_t>(ws.E(k))] = std::max({0.0, lin.n[K] - up, lo - lin.n[K]}) + 1e-3;
  }
  for (int k = 0; k < N; ++k) {
    const auto K = static_cast<std::size_t>(k);
    const double vb = lin.v[K];
    const double ay = o.nominal_fraction * limits().AyMax(vb);
    const double ad = std::max(o.nominal_fraction * limits().AxDriveMax(vb), 0.05);
    const double ab = o.nominal_fraction * limits().AxBrakeMax(vb);
    const std::size_t S = kPolygonSides;
    const std::size_t base[2] = {PolygonBase(limits().DriveExponent(vb)),
                                 PolygonBase(limits().BrakeExponent(vb))};
    for (int side = 0; side < 2; ++side)
      for (std::size_t j = 0; j < S; ++j)
        for (int sg = 0; sg < 2; ++sg) {
          ws.jv[e++] = side == 0 ? 1.0 / ad : -1.0 / ab;
          ws.jv[e++] = -slope_[base[side] + j] * (sg == 0 ? 1.0 : -1.0) / ay;
          const auto row = static_cast<std::size_t>(
              ws.GgRow(k, side * 2 * static_cast<int>(S) + 2 * static_cast<int>(j) + sg));
          ws.gl[row] = -kInf;
          ws.gu[row] = offset_[base[side] + j];
        }
    const auto at = static_cast<std::size_t>(ws.U(k, 0)), an = static_cast<std::size_t>(ws.U(k, 1));
    ws.zl[at] = -1.5 * ab;
    ws.zu[at] = 1.5 * ad + 1.0;
    ws.zl[an] = -1.5 * ay;
    ws.zu[an] = 1.5 * ay;
    const PathPoint ref = path.Sample(lin.s[K]);
    const double c_ref = lin.kappa[K] * vb * vb;
    ws.Quad(ws.U(k, 0), o.r_at, ref.a_x);
    ws.Quad(ws.U(k, 1), o.r_an, c_ref);
    // Start inside the polygon: scale the guess into it.
    double gt = lin.at[K], gn = lin.an[K];
    const double xr = gt >= 0.0 ? gt / ad : -gt / ab, rr = std::abs(gn) / ay;
    double worst = 0.0;
    const std::size_t b = base[gt >= 0.0 ? 0 : 1];
    for (std::size_t j = 0; j < S; ++j)
      worst = std::max(worst, (xr - slope_[b + j] * rr) / offset_[b + j]);
    if (worst > 0.98) {
      gt *= 0.98 / worst;
      gn *= 0.98 / worst;
    }
    ws.z0[at] = gt;
    ws.z0[an] = gn;
  }
  // Δu: to the previously applied input at k = 0, then between intervals.
  ws.Quad(ws.U(0, 0), o.r_dat, st->prev_at);
  ws.Quad(ws.U(0, 1), o.r_dan, st->prev_an);
  std::size_t hp = static_cast<std::size_t>(ws.nv);
  for (int k = 1; k < N; ++k)
    for (int j = 0; j < 2; ++j) {
      const double r = j == 0 ? o.r_dat : o.r_dan;
      ws.hv[static_cast<std::size_t>(ws.U(k, j))] += 2.0 * r;
      ws.hv[static_cast<std::size_t>(ws.U(k - 1, j))] += 2.0 * r;
      ws.hv[hp++] = -2.0 * r;
    }

  // 3. Solve (warm-started from the multipliers of the plan in use when it is shifted).
  ws.mult_shift = shift ? tau / dt : -1.0;
  if (!TimedSolve(&ws.solver, &ws, &st->diagnostics)) return false;

  // 4. The new plan.
  Plan& p = st->plan;
  for (int k = 0; k <= N; ++k) {
    const auto K = static_cast<std::size_t>(k);
    p.n[K] = ws.z[static_cast<std::size_t>(ws.X(k, 0))];
    p.w[K] = ws.z[static_cast<std::size_t>(ws.X(k, 1))];
    p.v[K] = ws.z[static_cast<std::size_t>(ws.X(k, 2))];
    if (k < N) {
      p.at[K] = ws.z[static_cast<std::size_t>(ws.U(k, 0))];
      p.an[K] = ws.z[static_cast<std::size_t>(ws.U(k, 1))];
      p.kappa[K] = lin.kappa[K];
    }
  }
  p.s[0] = s;
  for (int k = 0; k < N; ++k) {
    const auto K = static_cast<std::size_t>(k);
    p.s[K + 1] = p.s[K] + 0.5 * dt * (p.v[K] + p.v[K + 1]) * CentripetalScale(p.n[K], p.kappa[K]);
  }
  p.t0 = in.t;
  p.valid = true;
  st->prev_at = p.at[0];
  st->prev_an = p.an[0];
  ws.zl_mult.swap(ws.new_zl_mult);
  ws.zu_mult.swap(ws.new_zu_mult);
  ws.g_mult.swap(ws.new_g_mult);
  return true;
}

MotionOutput PointMassMpc::Step(const MotionInput& in, MotionState* base) const noexcept {
  auto* st = static_cast<State*>(base);
  const auto& o = options_;
  MotionOutput out;
  const double v_x = std::isfinite(in.v_x) ? in.v_x : 0.0;
  const double v_y = std::isfinite(in.v_y) ? in.v_y : 0.0;
  PathPoint ref;
  const PathProjection here = Locate(in, o.projection_window, st, &out, &ref);

  const double beta = std::atan2(v_y, std::max(std::abs(v_x), 1.0));
  const double xi = WrapAngle(here.heading_error + beta);
  const double v = std::max(std::hypot(v_x, v_y), o.min_speed);
  const double n = here.lateral_error;

  if (!st->plan.valid || in.t - st->last_solve_t >= o.solve_period - 1e-9) {
    st->last_solve_t = in.t;
    SolveOrHold(in.t, o.horizon_steps * o.step - o.step, &st->plan, &st->diagnostics,
                [&] { return Solve(in, here.s, n, v * std::sin(xi), v * std::cos(xi), st); });
  }

  // Nominal state and input at this time: the plan, or the reference (fallback).
  double n_nom = 0.0, xi_nom = 0.0, v_nom = ref.v, at_nom = ref.a_x, an_nom = ref.kappa * v * v;
  if (FollowPlan(st->plan, &st->diagnostics)) {
    const Plan& p = st->plan;
    const double tau = in.t - p.t0;
    n_nom = NodeAt(p.n, tau, o.step);
    v_nom = NodeAt(p.v, tau, o.step);
    xi_nom = std::asin(std::clamp(NodeAt(p.w, tau, o.step) / std::max(v_nom, 1.0), -1.0, 1.0));
    at_nom = IntervalAt(p.at, tau, o.step);
    an_nom = IntervalAt(p.an, tau, o.step);
  }

  // Ancillary feedback: return to the nominal within the lookahead distance.
  const double e_n = n - n_nom, e_xi = WrapAngle(xi - xi_nom);
  const double look = std::max(o.min_lookahead, o.lookahead_time * v);
  const double ay_cap = o.headroom * limits().AyMax(v);
  const double an_cmd =
      std::clamp(an_nom - 2.0 * v * v * (e_n + look * e_xi) / (look * look), -ay_cap, ay_cap);
  double delta = std::atan(o.wheelbase * an_cmd / (v * v)) + o.understeer_gradient * an_cmd;
  if (o.yaw_rate_gain != 0.0) delta -= o.yaw_rate_gain * (in.yaw_rate - an_cmd / v);
  if (o.lat_accel_gain != 0.0 && std::isfinite(in.a_y))
    delta += o.lat_accel_gain * (an_cmd - in.a_y) / (v * v);
  if (!std::isfinite(delta)) delta = 0.0;
  out.steering_request = std::clamp(delta, -o.max_steering, o.max_steering);
  double ax = at_nom + o.speed_gain * (v_nom - v);
  double drive_cap = o.headroom * limits().AxDriveMax(v),
         brake_cap = o.headroom * limits().AxBrakeMax(v);
  if (provided_limits_) {
    const double ay_abs = std::abs(an_cmd), ay_lim = limits().AyMax(v);
    drive_cap *= limits().DriveFactor(ay_abs, ay_lim, v);
    brake_cap *= limits().BrakeFactor(ay_abs, ay_lim, v);
  }
  ax = std::clamp(ax, -brake_cap, std::max(drive_cap, 0.5));
  out.ax_request = std::isfinite(ax) ? ax : 0.0;
  if (esc_target_ == EscTarget::kSteering) {
    out.ay_request = std::numeric_limits<double>::quiet_NaN();  // not published
  } else {
    const double ay_target = esc_target_ == EscTarget::kCommanded ? an_cmd : an_nom;
    out.ay_request = std::isfinite(ay_target) ? ay_target : 0.0;
  }
  return out;
}

}  // namespace scw::controller::motion
