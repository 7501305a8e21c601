// Thin bridge from the MPCs' sparse problems to Ipopt (Debian's coinor-libipopt-dev, 3.11), the
// only file of the library that sees Ipopt's headers.
//
//   min f(z)   s.t.   z_l ≤ z ≤ z_u,   g_l ≤ g(z) ≤ g_u
//
// A problem describes itself through SparseNlp (0-based triplets, Hessian of the Lagrangian
// obj_factor·∇²f + Σ λ_i ∇²g_i as lower triangle). NlpSolver owns one Ipopt application with the
// options fixed at construction; Solve never throws and never reads the wall clock for a decision
// (iteration limits only, so results do not depend on the machine's speed).
//
// Linear algebra: each Ipopt iteration factorises the KKT matrix of the Newton step. Debian's
// Ipopt has MUMPS only, which costs ~1 ms per factorisation and ~0.4 ms per solve even for the
// point-mass QP (KKT order ~740): 95 % of a PMPC solve. Convex problems can instead use
// LinearSolver::kQuasiDefiniteLdl, a sparse LDLᵀ without pivoting on a regularised,
// quasi-definite neighbour of the KKT matrix (AMD ordering; Ipopt's iterative refinement
// corrects for the regularisation), plugged into Ipopt's MA27 slot through HSLLoader.h
// (LSL_setMA27); with it (and the warm start) a PMPC solve takes ~1 ms instead of ~15 ms.
// Non-convex problems (the NMPC) keep MUMPS: without pivoting their negative curvature would
// be masked rather than reported through the inertia.
//
// Warm start: with `warm_start`, a problem that offers multipliers (SparseNlp::StartMultipliers)
// starts from them and from its primal start with small bound pushes and mu_init =
// warm_start_mu_init (Ipopt's warm_start_init_point); otherwise Ipopt's cold start.
//
// Re-solves: when the same SparseNlp comes back with the same sizes, sparsity and bound classes
// (finite / infinite / equal, per variable and row), Solve calls Ipopt's ReOptimizeTNLP with
// warm_start_same_structure, so Ipopt keeps its spaces, matrices, factor storage and symbolic
// factorisation; the LDLᵀ's ordering and elimination tree are also kept per sparsity pattern for
// the whole process. Results are bit for bit those of a fresh solve.
//
// System calls: none in a solve. Ipopt 3.11 reads getrusage twice per timed task (~40 times an
// iteration) for its timing statistics; nlp_solver.cc replaces Ipopt::CpuTime/SysTime, which
// Ipopt calls through its PLT, by functions returning 0 in every program linking this library:
// Ipopt's CPU and system time statistics read 0 (its wall-clock times are unaffected).
//
// Allocation: Ipopt still allocates its iterate vectors in every iteration; the problem's own
// data live in the caller's preallocated workspace.
#pragma once

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace scw::controller::motion {

struct NlpSizes {
  int n = 0;         ///< variables
  int m = 0;         ///< constraints
  int nnz_jac = 0;   ///< structural non-zeros of ∂g/∂z
  int nnz_hess = 0;  ///< structural non-zeros of the Lagrangian Hessian (lower triangle)
};

class SparseNlp {
 public:
  virtual ~SparseNlp() = default;
  virtual NlpSizes Sizes() const = 0;
  virtual void Bounds(double* z_l, double* z_u, double* g_l, double* g_u) const = 0;
  virtual void Start(double* z) const = 0;
  virtual double Objective(const double* z) const = 0;
  virtual void Gradient(const double* z, double* grad) const = 0;
  virtual void Constraints(const double* z, double* g) = 0;
  virtual void JacobianStructure(int* rows, int* cols) const = 0;
  virtual void JacobianValues(const double* z, double* values) = 0;
  virtual void HessianStructure(int* rows, int* cols) const = 0;
  virtual void HessianValues(const double* z, double obj_factor, const double* lambda,
                             double* values) = 0;
  /// Called once with the last iterate (also when not converged).
  virtual void Solution(const double* z) = 0;
  /// Optional warm start of the multipliers (NlpSolverOptions::warm_start): bound multipliers
  /// z_l, z_u ≥ 0 (n each) and constraint multipliers lambda (m). False: cold start.
  virtual bool StartMultipliers(double* /*z_l*/, double* /*z_u*/, double* /*lambda*/) const {
    return false;
  }
  /// Optional: the multipliers of the last iterate, called right after Solution.
  virtual void SolutionMultipliers(const double* /*z_l*/, const double* /*z_u*/,
                                   const double* /*lambda*/) {}
};

/// A SparseNlp whose sizes, bounds, start, sparsity structure and last iterate are stored
/// vectors: the problem (the MPCs' workspaces) fills them once and supplies the values.
struct StoredSparseNlp : SparseNlp {
  NlpSizes Sizes() const override {
    return {nv, m, static_cast<int>(jr.size()), static_cast<int>(hr.size())};
  }
  void Bounds(double* z_l, double* z_u, double* g_l, double* g_u) const override {
    std::copy(zl.begin(), zl.end(), z_l);
    std::copy(zu.begin(), zu.end(), z_u);
    std::copy(gl.begin(), gl.end(), g_l);
    std::copy(gu.begin(), gu.end(), g_u);
  }
  void Start(double* out) const override { std::copy(z0.begin(), z0.end(), out); }
  void JacobianStructure(int* rows, int* cols) const override {
    std::copy(jr.begin(), jr.end(), rows);
    std::copy(jc.begin(), jc.end(), cols);
  }
  void HessianStructure(int* rows, int* cols) const override {
    std::copy(hr.begin(), hr.end(), rows);
    std::copy(hc.begin(), hc.end(), cols);
  }
  void Solution(const double* v) override { std::copy(v, v + nv, z.begin()); }

  int nv = 0;                              ///< variables
  int m = 0;                               ///< constraints
  std::vector<double> zl, zu, gl, gu, z0;  ///< bounds of z and g, the start
  std::vector<double> z;                   ///< the last iterate (Solution)
  std::vector<int> jr, jc, hr, hc;         ///< Jacobian and Hessian structure (rows, columns)
};

struct NlpSolverOptions {
  int max_iter = 50;
  double tol = 1e-6;             ///< Ipopt `tol`
  double acceptable_tol = 1e-4;  ///< Ipopt `acceptable_tol`
  int acceptable_iter = 5;       ///< Ipopt `acceptable_iter`
  double constr_viol_tol = 1e-6;
  bool quadratic = false;  ///< linear constraints, constant Hessian: Ipopt evaluates them once
  double mu_init = 0.1;
  std::string mu_strategy = "monotone";
  /// An iterate that stopped on the iteration limit is still used when its constraint violation
  /// (max over rows and bounds, in the problem's units) is below this.
  double usable_violation = 1e-3;
  int print_level = 0;
  enum class LinearSolver {
    kMumps,             ///< Ipopt's MUMPS (pivoting; any problem)
    kQuasiDefiniteLdl,  ///< static-pivoting LDLᵀ; convex problems only (see the file comment)
  };
  LinearSolver linear_solver = LinearSolver::kMumps;
  int min_refinement_steps = 1;         ///< Ipopt `min_refinement_steps` (Ipopt's default 1)
  bool warm_start = false;              ///< use SparseNlp::StartMultipliers when offered
  double warm_start_mu_init = 1e-4;     ///< Ipopt `mu_init` of a warm start
  double warm_start_bound_push = 1e-6;  ///< Ipopt `warm_start_{,mult_}bound_{push,frac}`
};

struct NlpResult {
  int status = -199;       ///< Ipopt::ApplicationReturnStatus
  int iterations = 0;      ///< Ipopt iterations of this solve
  bool usable = false;     ///< converged, or feasible within usable_violation
  double violation = 0.0;  ///< max violation of rows and bounds at the returned iterate
};

class NlpSolver {
 public:
  /// Creates and configures the Ipopt application (throws std::runtime_error if Ipopt refuses).
  explicit NlpSolver(const NlpSolverOptions& options);
  ~NlpSolver();
  NlpSolver(const NlpSolver&) = delete;
  NlpSolver& operator=(const NlpSolver&) = delete;

  /// Solves `nlp`, starting from nlp->Start(). Never throws: Ipopt exceptions and failures come
  /// back as a non-usable result.
  NlpResult Solve(SparseNlp* nlp) noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scw::controller::motion
