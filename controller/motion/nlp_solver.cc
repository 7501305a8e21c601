#include "controller/motion/nlp_solver.h"

#include <HSLLoader.h>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>
#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace scw::controller::motion {
namespace {

using Ipopt::Index;
using Ipopt::Number;

// Ipopt's view of a SparseNlp. Keeps the bounds to measure the violation of the final iterate.
class Adapter final : public Ipopt::TNLP {
 public:
  /// `start_mult`: z_l, z_u, lambda of a warm start (empty: cold start).
  Adapter(SparseNlp* nlp, std::vector<double>* bounds, const std::vector<double>* start_mult)
      : nlp_(nlp), bounds_(bounds), start_mult_(start_mult) {}

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override {
    const NlpSizes s = nlp_->Sizes();
    n = s.n;
    m = s.m;
    nnz_jac_g = s.nnz_jac;
    nnz_h_lag = s.nnz_hess;
    index_style = C_STYLE;
    n_ = s.n;
    m_ = s.m;
    return true;
  }
  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l,
                       Number* g_u) override {
    nlp_->Bounds(x_l, x_u, g_l, g_u);
    std::vector<double>& b = *bounds_;
    b.resize(2 * static_cast<std::size_t>(n + m));
    std::copy(x_l, x_l + n, b.begin());
    std::copy(x_u, x_u + n, b.begin() + n);
    std::copy(g_l, g_l + m, b.begin() + 2 * n);
    std::copy(g_u, g_u + m, b.begin() + 2 * n + m);
    return true;
  }
  bool get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number* z_l, Number* z_u,
                          Index m, bool init_lambda, Number* lambda) override {
    const std::vector<double>& w = *start_mult_;
    if ((init_z || init_lambda) && w.size() != 2 * static_cast<std::size_t>(n) + m) return false;
    if (init_x) nlp_->Start(x);
    if (init_z) {
      std::copy(w.begin(), w.begin() + n, z_l);
      std::copy(w.begin() + n, w.begin() + 2 * n, z_u);
    }
    if (init_lambda) std::copy(w.begin() + 2 * n, w.end(), lambda);
    return true;
  }
  bool eval_f(Index, const Number* x, bool, Number& obj_value) override {
    obj_value = nlp_->Objective(x);
    return std::isfinite(obj_value);
  }
  bool eval_grad_f(Index, const Number* x, bool, Number* grad_f) override {
    nlp_->Gradient(x, grad_f);
    return true;
  }
  bool eval_g(Index, const Number* x, bool, Index m, Number* g) override {
    nlp_->Constraints(x, g);
    for (Index i = 0; i < m; ++i)
      if (!std::isfinite(g[i])) return false;
    return true;
  }
  bool eval_jac_g(Index, const Number* x, bool, Index, Index, Index* iRow, Index* jCol,
                  Number* values) override {
    if (values == nullptr)
      nlp_->JacobianStructure(iRow, jCol);
    else
      nlp_->JacobianValues(x, values);
    return true;
  }
  bool eval_h(Index, const Number* x, bool, Number obj_factor, Index, const Number* lambda, bool,
              Index, Index* iRow, Index* jCol, Number* values) override {
    if (values == nullptr)
      nlp_->HessianStructure(iRow, jCol);
    else
      nlp_->HessianValues(x, obj_factor, lambda, values);
    return true;
  }
  void finalize_solution(Ipopt::SolverReturn, Index n, const Number* x, const Number* z_l,
                         const Number* z_u, Index m, const Number* g, const Number* lambda, Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    if (x == nullptr) return;
    nlp_->Solution(x);
    if (z_l != nullptr && z_u != nullptr && lambda != nullptr)
      nlp_->SolutionMultipliers(z_l, z_u, lambda);
    const std::vector<double>& b = *bounds_;
    double v = 0.0;
    if (b.size() == 2 * static_cast<std::size_t>(n + m)) {
      for (Index i = 0; i < n; ++i) v = std::max({v, b[i] - x[i], x[i] - b[n + i]});
      for (Index i = 0; g != nullptr && i < m; ++i)
        v = std::max({v, b[2 * n + i] - g[i], g[i] - b[2 * n + m + i]});
    }
    violation_ = std::isfinite(v) ? v : 1e300;
    finalized_ = true;
  }

  double violation() const { return violation_; }
  bool finalized() const { return finalized_; }

 private:
  SparseNlp* nlp_;
  std::vector<double>* bounds_;
  const std::vector<double>* start_mult_;
  Index n_ = 0, m_ = 0;
  double violation_ = 1e300;
  bool finalized_ = false;
};

// ---------------------------------------------------------------------------------------------
// Quasi-definite LDLᵀ in Ipopt's MA27 slot (NlpSolverOptions::LinearSolver::kQuasiDefiniteLdl).
//
// Ipopt 3.11 offers the HSL routines through function pointers (HSLLoader.h, LSL_setMA27); we set
// them to the routines below, which follow the MA27 calling convention (1-based triplets, factor
// kept in the caller's arrays A and IW, so they are stateless and reentrant):
//   MA27AD  analysis: approximate minimum degree ordering (Eigen's AMD) → IKEEP, storage estimates;
//   MA27BD  factorisation: elimination tree, then the up-looking LDLᵀ of T. Davis's LDL without
//           pivoting, with the regularisation of QDLDL-based interior-point solvers (Clarabel):
//           every pivot is given the sign expected of its row — positive where the matrix
//           diagonal is positive (primal variables and slacks: W + Σ + δ_x > 0 for a convex
//           problem), negative elsewhere (constraint rows, diagonal −δ_c ≤ 0) — plus a static
//           shift of 1e-8, and a pivot that comes out with the wrong sign or below 1e-13 is
//           replaced by ±2e-7. This factorises a quasi-definite neighbour of the KKT matrix for
//           any ordering; Ipopt's iterative refinement on the exact system removes the difference
//           (residual checks in PDFullSpaceSolver). The number of negative pivots is the inertia
//           Ipopt checks.
//   MA27CD  solve with the factor.
// Valid for convex problems (positive definite Hessian on the primal rows, e.g. the point-mass
// QP); a non-convex problem would get its negative curvature masked, so the NMPC keeps MUMPS.
// Layout: IW = [n, nz, lnz, Lp (n+1), Li (lnz), perm (n), scratch], A = [values (nz), Lx (lnz),
// D (n), scratch]; perm[k] = original index of the k-th pivot.
namespace ldl {

constexpr ipfint kHeader = 3;
constexpr double kStaticReg = 1e-8, kDynamicEps = 1e-13, kDynamicDelta = 2e-7;

// Upper triangle (row ≤ column) of P A Pᵀ in compressed columns; duplicates kept (summed later).
void PermutedUpper(ipfint n, ipfint nz, const ipfint* irn, const ipfint* icn, const ipfint* iperm,
                   ipfint* ap, ipfint* ai, ipfint* entry) {
  std::fill(ap, ap + n + 1, 0);
  for (ipfint e = 0; e < nz; ++e) ++ap[std::max(iperm[irn[e] - 1], iperm[icn[e] - 1]) + 1];
  for (ipfint k = 0; k < n; ++k) ap[k + 1] += ap[k];
  // ai/entry filled using ap[k] as a moving cursor, then ap shifted back.
  for (ipfint e = 0; e < nz; ++e) {
    const ipfint i = iperm[irn[e] - 1], j = iperm[icn[e] - 1];
    const ipfint p = ap[std::max(i, j)]++;
    ai[p] = std::min(i, j);
    entry[p] = e;
  }
  for (ipfint k = n; k > 0; --k) ap[k] = ap[k - 1];
  ap[0] = 0;
}

// Elimination tree and column counts of L (Davis, LDL): lnz[k] = non-zeros below the diagonal.
ipfint Symbolic(ipfint n, const ipfint* ap, const ipfint* ai, ipfint* parent, ipfint* lnz,
                ipfint* flag) {
  ipfint total = 0;
  for (ipfint k = 0; k < n; ++k) {
    parent[k] = -1;
    flag[k] = k;
    lnz[k] = 0;
    for (ipfint p = ap[k]; p < ap[k + 1]; ++p)
      for (ipfint i = ai[p]; i < k && flag[i] != k; i = parent[i]) {
        if (parent[i] == -1) parent[i] = k;
        ++lnz[i];
        flag[i] = k;
      }
  }
  for (ipfint k = 0; k < n; ++k) total += lnz[k];
  return total;
}

void Init(ipfint* icntl, double* cntl) {
  std::fill(icntl, icntl + 30, 0);
  std::fill(cntl, cntl + 5, 0.0);
  cntl[0] = 0.1;
}

void Analyse(ipfint* N, ipfint* NZ, const ipfint* irn, const ipfint* icn, ipfint*, ipfint*,
             ipfint* ikeep, ipfint*, ipfint* nsteps, ipfint*, ipfint*, double*, ipfint* info,
             double* ops) {
  const ipfint n = *N, nz = *NZ;
  std::fill(info, info + 20, 0);
  for (ipfint e = 0; e < nz; ++e)
    if (irn[e] < 1 || irn[e] > n || icn[e] < 1 || icn[e] > n) {
      info[0] = 1;  // MA27: entries out of range
      return;
    }
  try {
    std::vector<Eigen::Triplet<double, ipfint>> t;
    t.reserve(static_cast<std::size_t>(nz));
    for (ipfint e = 0; e < nz; ++e) t.emplace_back(irn[e] - 1, icn[e] - 1, 1.0);
    Eigen::SparseMatrix<double, Eigen::ColMajor, ipfint> pattern(n, n);
    pattern.setFromTriplets(t.begin(), t.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, ipfint> order;
    Eigen::AMDOrdering<ipfint>()(pattern, order);  // order.indices()[new] = old
    std::vector<ipfint> iperm(static_cast<std::size_t>(n)), ap(static_cast<std::size_t>(n) + 1),
        ai(static_cast<std::size_t>(nz)), entry(static_cast<std::size_t>(nz)),
        work(3 * static_cast<std::size_t>(n));
    for (ipfint k = 0; k < n; ++k) {
      ikeep[k] = order.indices()[k];
      iperm[static_cast<std::size_t>(order.indices()[k])] = k;
    }
    PermutedUpper(n, nz, irn, icn, iperm.data(), ap.data(), ai.data(), entry.data());
    const ipfint lnz =
        Symbolic(n, ap.data(), ai.data(), work.data(), work.data() + n, work.data() + 2 * n);
    *nsteps = 1;
    *ops = 0.0;
    for (ipfint k = 0; k < n; ++k) *ops += static_cast<double>(work[n + k]) * work[n + k];
    info[4] = nz + lnz + 3 * n;                              // LA: see Factorise
    info[5] = kHeader + 2 * (n + 1) + 2 * nz + 6 * n + lnz;  // LIW
  } catch (...) {
    info[0] = -1;
  }
}

void Factorise(ipfint* N, ipfint* NZ, const ipfint* irn, const ipfint* icn, double* a, ipfint* LA,
               ipfint* iw, ipfint* LIW, ipfint* ikeep, ipfint*, ipfint* maxfrt, ipfint*, ipfint*,
               double*, ipfint* info) {
  const ipfint n = *N, nz = *NZ;
  std::fill(info, info + 20, 0);
  // Scratch layout first, to know the sizes.
  ipfint* lp = iw + kHeader;
  ipfint* perm = lp + n + 1;  // placed before Li: lnz is known only after the symbolic phase
  ipfint* ap = perm + n;
  ipfint* ai = ap + n + 1;
  ipfint* entry = ai + nz;
  ipfint* iperm = entry + nz;
  ipfint* parent = iperm + n;
  ipfint* lnzc = parent + n;
  ipfint* flag = lnzc + n;
  ipfint* pattern = flag + n;
  ipfint* li = pattern + n;
  const ipfint fixed_iw = static_cast<ipfint>(li - iw);
  if (*LIW < fixed_iw) {
    info[0] = -3;
    info[1] = fixed_iw + nz + n;
    return;
  }
  for (ipfint k = 0; k < n; ++k) {
    perm[k] = ikeep[k];
    iperm[ikeep[k]] = k;
  }
  PermutedUpper(n, nz, irn, icn, iperm, ap, ai, entry);
  const ipfint lnz = Symbolic(n, ap, ai, parent, lnzc, flag);
  if (*LIW < fixed_iw + lnz) {
    info[0] = -3;
    info[1] = fixed_iw + lnz;
    return;
  }
  const ipfint need_a = nz + lnz + 2 * n + n;
  if (*LA < need_a) {
    info[0] = -4;
    info[1] = need_a;
    return;
  }
  double* lx = a + nz;
  double* d = lx + lnz;
  double* y = d + n;
  double* sign = y + n;
  lp[0] = 0;
  for (ipfint k = 0; k < n; ++k) lp[k + 1] = lp[k] + lnzc[k];
  // Expected pivot signs from the diagonal of the matrix.
  std::fill(sign, sign + n, 0.0);
  for (ipfint k = 0; k < n; ++k)
    for (ipfint p = ap[k]; p < ap[k + 1]; ++p)
      if (ai[p] == k) sign[k] += a[entry[p]];
  for (ipfint k = 0; k < n; ++k) sign[k] = sign[k] > 0.0 ? 1.0 : -1.0;
  // Numeric phase (Davis, LDL: up-looking, one row of L per step).
  std::fill(y, y + n, 0.0);
  ipfint negative = 0;
  bool finite = true;
  for (ipfint k = 0; k < n; ++k) {
    ipfint top = n;
    flag[k] = k;
    lnzc[k] = 0;
    for (ipfint p = ap[k]; p < ap[k + 1]; ++p) {
      ipfint i = ai[p];
      y[i] += a[entry[p]];
      ipfint len = 0;
      for (; flag[i] != k; i = parent[i]) {
        pattern[len++] = i;
        flag[i] = k;
      }
      while (len > 0) pattern[--top] = pattern[--len];
    }
    double dk = y[k] + sign[k] * kStaticReg;
    y[k] = 0.0;
    for (; top < n; ++top) {
      const ipfint i = pattern[top];
      const double yi = y[i];
      y[i] = 0.0;
      const ipfint p2 = lp[i] + lnzc[i];
      for (ipfint p = lp[i]; p < p2; ++p) y[li[p]] -= lx[p] * yi;
      const double l_ki = yi / d[i];
      dk -= l_ki * yi;
      li[p2] = k;
      lx[p2] = l_ki;
      ++lnzc[i];
    }
    if (!std::isfinite(dk)) finite = false;  // NaN/inf in the matrix: report it as singular
    if (!(sign[k] * dk > kDynamicEps)) dk = sign[k] * kDynamicDelta;
    d[k] = dk;
    if (dk < 0.0) ++negative;
  }
  // Li sits after the scratch arrays; CD needs only the header, Lp, perm and Li: move Li down.
  ipfint* li_final = perm + n;
  std::copy(li, li + lnz, li_final);
  iw[0] = n;
  iw[1] = nz;
  iw[2] = lnz;
  *maxfrt = std::max<ipfint>(n, 1);  // Ipopt passes a work vector of this length to MA27CD
  info[0] = finite ? 0 : -5;         // -5: singular (Ipopt then regularises)
  info[14] = negative;
}

void SolveFactor(ipfint* N, double* a, ipfint*, ipfint* iw, ipfint*, double* w, ipfint*,
                 double* rhs, ipfint*, ipfint*, ipfint*, double*) {
  const ipfint n = *N;
  if (n != iw[0]) return;
  const ipfint nz = iw[1], lnz = iw[2];
  const ipfint* lp = iw + kHeader;
  const ipfint* perm = lp + n + 1;
  const ipfint* li = perm + n;
  const double* lx = a + nz;
  const double* d = lx + lnz;
  for (ipfint k = 0; k < n; ++k) w[k] = rhs[perm[k]];
  for (ipfint j = 0; j < n; ++j)  // L y = b (column j of L holds rows li > j)
    for (ipfint p = lp[j]; p < lp[j + 1]; ++p) w[li[p]] -= lx[p] * w[j];
  for (ipfint j = 0; j < n; ++j) w[j] /= d[j];
  for (ipfint j = n; j-- > 0;)
    for (ipfint p = lp[j]; p < lp[j + 1]; ++p) w[j] -= lx[p] * w[li[p]];
  for (ipfint k = 0; k < n; ++k) rhs[perm[k]] = w[k];
}

}  // namespace ldl

}  // namespace

// Debian's Ipopt uses the sequential MUMPS build (MPI stub library), which keeps global state and
// is not thread-safe: parallel runs of the batch evaluator crashed in it. All Ipopt calls of the
// process therefore go through one lock (also those on the LDLᵀ, which itself would not need it:
// Ipopt 3.11's own thread safety is not documented); runs with MPCs still execute in parallel
// everywhere else (plant, stability controller), and results do not depend on the order. MPC
// sweeps parallelise over processes instead (`scw sweep --processes`, tuning/sweep/sweep.h).
static std::mutex& IpoptMutex() {
  static std::mutex m;
  return m;
}

struct NlpSolver::Impl {
  NlpSolverOptions options;
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app;
  std::vector<double> bounds;
  std::vector<double> start_mult;  ///< z_l, z_u, lambda of the next warm start
};

NlpSolver::NlpSolver(const NlpSolverOptions& o) : impl_(std::make_unique<Impl>()) {
  std::lock_guard<std::mutex> lock(IpoptMutex());
  impl_->options = o;
  impl_->app = IpoptApplicationFactory();
  auto opts = impl_->app->Options();
  opts->SetStringValue("sb", "yes");  // no banner
  opts->SetIntegerValue("print_level", o.print_level);
  opts->SetIntegerValue("max_iter", o.max_iter);
  opts->SetNumericValue("tol", o.tol);
  opts->SetNumericValue("acceptable_tol", o.acceptable_tol);
  opts->SetIntegerValue("acceptable_iter", o.acceptable_iter);
  opts->SetNumericValue("constr_viol_tol", o.constr_viol_tol);
  opts->SetNumericValue("mu_init", o.mu_init);
  opts->SetStringValue("mu_strategy", o.mu_strategy);
  opts->SetIntegerValue("min_refinement_steps", o.min_refinement_steps);
  if (o.linear_solver == NlpSolverOptions::LinearSolver::kQuasiDefiniteLdl) {
    static std::once_flag registered;
    std::call_once(registered, [] {
      LSL_setMA27(&ldl::Analyse, &ldl::Factorise, &ldl::SolveFactor, &ldl::Init);
    });
    opts->SetStringValue("linear_solver", "ma27");
    opts->SetStringValue("linear_system_scaling", "none");
  } else {
    opts->SetStringValue("linear_solver", "mumps");
    opts->SetIntegerValue("mumps_mem_percent", 10);
  }
  if (o.warm_start) {
    for (const char* k :
         {"warm_start_bound_push", "warm_start_bound_frac", "warm_start_slack_bound_push",
          "warm_start_slack_bound_frac", "warm_start_mult_bound_push"})
      opts->SetNumericValue(k, o.warm_start_bound_push);
  }
  if (o.print_level >= 5) opts->SetStringValue("print_timing_statistics", "yes");
  if (o.quadratic) {
    opts->SetStringValue("jac_c_constant", "yes");
    opts->SetStringValue("jac_d_constant", "yes");
    opts->SetStringValue("hessian_constant", "yes");
  }
  // An empty options-file name: never read an ipopt.opt lying in the working directory.
  if (impl_->app->Initialize("") != Ipopt::Solve_Succeeded)
    throw std::runtime_error("Ipopt could not be initialised");
}

NlpSolver::~NlpSolver() {
  std::lock_guard<std::mutex> lock(IpoptMutex());
  impl_.reset();
}

NlpResult NlpSolver::Solve(SparseNlp* nlp) noexcept {
  NlpResult r;
  try {
    std::lock_guard<std::mutex> lock(IpoptMutex());
    const NlpSolverOptions& o = impl_->options;
    bool warm = false;
    if (o.warm_start) {
      const NlpSizes sz = nlp->Sizes();
      impl_->start_mult.resize(2 * static_cast<std::size_t>(sz.n) + sz.m);
      double* w = impl_->start_mult.data();
      warm = nlp->StartMultipliers(w, w + sz.n, w + 2 * sz.n);
      if (!warm) impl_->start_mult.clear();
      auto opts = impl_->app->Options();
      opts->SetStringValue("warm_start_init_point", warm ? "yes" : "no");
      opts->SetNumericValue("mu_init", warm ? o.warm_start_mu_init : o.mu_init);
    }
    Ipopt::SmartPtr<Adapter> adapter = new Adapter(nlp, &impl_->bounds, &impl_->start_mult);
    const Ipopt::ApplicationReturnStatus st =
        impl_->app->OptimizeTNLP(Ipopt::SmartPtr<Ipopt::TNLP>(GetRawPtr(adapter)));
    r.status = static_cast<int>(st);
    auto stats = impl_->app->Statistics();
    if (Ipopt::IsValid(stats)) r.iterations = stats->IterationCount();
    r.violation = adapter->violation();
    const bool converged = st == Ipopt::Solve_Succeeded || st == Ipopt::Solved_To_Acceptable_Level;
    const bool feasible_stop = st == Ipopt::Maximum_Iterations_Exceeded ||
                               st == Ipopt::Search_Direction_Becomes_Too_Small ||
                               st == Ipopt::Restoration_Failed;
    r.usable = adapter->finalized() && (converged || feasible_stop) &&
               r.violation <= impl_->options.usable_violation;
  } catch (...) {
    r.usable = false;
  }
  return r;
}

}  // namespace scw::controller::motion
