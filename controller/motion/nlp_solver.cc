#include "controller/motion/nlp_solver.h"

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
  Adapter(SparseNlp* nlp, std::vector<double>* bounds) : nlp_(nlp), bounds_(bounds) {}

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
  bool get_starting_point(Index, bool init_x, Number* x, bool init_z, Number*, Number*, Index,
                          bool init_lambda, Number*) override {
    if (init_z || init_lambda) return false;
    if (init_x) nlp_->Start(x);
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
  void finalize_solution(Ipopt::SolverReturn, Index n, const Number* x, const Number*,
                         const Number*, Index m, const Number* g, const Number*, Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    if (x == nullptr) return;
    nlp_->Solution(x);
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
  Index n_ = 0, m_ = 0;
  double violation_ = 1e300;
  bool finalized_ = false;
};

}  // namespace

// Debian's Ipopt uses the sequential MUMPS build (MPI stub library), which keeps global state and
// is not thread-safe: parallel runs of the batch evaluator crashed in it. All Ipopt calls of the
// process therefore go through one lock; runs with MPCs still execute in parallel everywhere
// else (plant, stability controller), and results do not depend on the order.
static std::mutex& IpoptMutex() {
  static std::mutex m;
  return m;
}

struct NlpSolver::Impl {
  NlpSolverOptions options;
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app;
  std::vector<double> bounds;
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
  opts->SetStringValue("linear_solver", "mumps");
  opts->SetIntegerValue("mumps_mem_percent", 10);
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
    Ipopt::SmartPtr<Adapter> adapter = new Adapter(nlp, &impl_->bounds);
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
