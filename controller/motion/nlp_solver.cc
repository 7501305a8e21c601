#include "controller/motion/nlp_solver.h"

#include <HSLLoader.h>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <IpBlas.hpp>
#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>
#include <IpUtils.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

// Ipopt 3.11 times each task of each iteration (IpTimedTask.hpp, Start and End) with
// Ipopt::CpuTime() and Ipopt::SysTime(), each a getrusage system call: ~40 per iteration, a fifth
// of a PMPC lap's time spent in the kernel. The library offers no option to turn the timing off
// (3.13's timing_statistics), but it calls both functions through its PLT, so these definitions,
// linked into every program that uses NlpSolver, take their place. Ipopt's CPU and system times
// therefore read 0 in its statistics; the wall-clock times are read as before (vDSO, no system
// call), and NlpSolver never sets max_cpu_time, the only decision Ipopt takes on them.
namespace Ipopt {
Number CpuTime() { return 0.0; }
Number SysTime() { return 0.0; }
// The wall clock likewise (~160 readings per solve): Ipopt 3.11 uses it for its timing statistics
// only; solve times are measured by MpcController itself.
Number WallclockTime() { return 0.0; }

// Ipopt's vector operations reach the reference BLAS (Debian's libblas3, one element at a time)
// through three wrappers that it calls through its PLT at every iteration: the max-norm
// (IpBlasIdamax, a tenth of a PMPC solve with the copies), copies and scaling. These exact
// replacements take their place for Ipopt alone (other users of BLAS, e.g. MUMPS, are not
// affected): the same index, the same copied and the same scaled values, bit for bit, for every
// input the reference routines accept (NaN, -0, strides).
namespace {

// Reference IDAMAX: the first index (1-based) of the largest |x_i|; comparisons with NaN are
// false, so a NaN first element stays the answer and later NaNs are skipped.
Index IdamaxReference(Index n, const Number* x, Index inc) {
  Index best = 1;
  Number m = std::fabs(x[0]);
  for (Index i = 1; i < n; ++i)
    if (std::fabs(x[static_cast<std::ptrdiff_t>(i) * inc]) > m) {
      best = i + 1;
      m = std::fabs(x[static_cast<std::ptrdiff_t>(i) * inc]);
    }
  return best;
}

}  // namespace

Index IpBlasIdamax(Index size, const Number* x, Index incX) {
  if (size < 1 || incX <= 0) return 0;
  if (size == 1) return 1;
  if (incX != 1 || !(std::fabs(x[0]) == std::fabs(x[0]))) return IdamaxReference(size, x, incX);
  // The largest |x_i| over the non-NaN entries (x[0] is one), with the reference's strict
  // comparison in four lanes (two SSE2 registers), then its first occurrence: the reference's
  // answer.
  using D2 = double __attribute__((vector_size(16)));
  using M2 = std::int64_t __attribute__((vector_size(16)));
  constexpr M2 kMagnitude = {INT64_MAX, INT64_MAX};
  const auto load_abs = [&](Index i) {
    D2 v;
    std::memcpy(&v, x + i, sizeof v);
    return reinterpret_cast<D2>(reinterpret_cast<M2>(v) & kMagnitude);
  };
  D2 m0 = {std::fabs(x[0]), std::fabs(x[0])}, m1 = m0;
  Index i = 1;
  for (; i + 4 <= size; i += 4) {
    const D2 v0 = load_abs(i), v1 = load_abs(i + 2);
    m0 = v0 > m0 ? v0 : m0;
    m1 = v1 > m1 ? v1 : m1;
  }
  Number top = std::max(std::max(m0[0], m0[1]), std::max(m1[0], m1[1]));
  for (; i < size; ++i) top = std::fabs(x[i]) > top ? std::fabs(x[i]) : top;
  for (Index k = 0; k < size; ++k)
    if (std::fabs(x[k]) == top) return k + 1;
  return 1;  // not reached: top is one of the |x_i|
}

void IpBlasDcopy(Index size, const Number* x, Index incX, Number* y, Index incY) {
  if (incX <= 0) {  // Ipopt's own case: every y_i set to *x
    for (; size != 0; --size, y += incY) *y = *x;
    return;
  }
  if (size <= 0) return;
  const auto n = static_cast<std::size_t>(size);
  if (incX == 1 && incY == 1) {
    std::memmove(y, x, n * sizeof(Number));  // BLAS arguments never overlap; memmove if they did
    return;
  }
  // Reference DCOPY: element by element; a negative increment of y starts at its far end.
  std::ptrdiff_t ix = 0;
  std::ptrdiff_t iy = incY < 0 ? (1 - static_cast<std::ptrdiff_t>(size)) * incY : 0;
  for (Index i = 0; i < size; ++i, ix += incX, iy += incY) y[iy] = x[ix];
}

void IpBlasDscal(Index size, Number alpha, Number* x, Index incX) {
  if (size <= 0 || incX <= 0) return;  // the reference's early return
  if (incX == 1) {
    for (Index i = 0; i < size; ++i) x[i] *= alpha;
    return;
  }
  for (Index i = 0; i < size; ++i) x[static_cast<std::ptrdiff_t>(i) * incX] *= alpha;
}

}  // namespace Ipopt

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
  /// Before each solve of the same problem (ReOptimizeTNLP reuses this object).
  void Reset() {
    violation_ = 1e300;
    finalized_ = false;
  }

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

// The symbolic phase of one sparsity pattern: the AMD ordering, the permuted upper triangle and
// the elimination tree with the column counts of L. Ipopt re-runs MA27AD at the start of every
// solve and MA27BD at every iteration, always for the same KKT pattern of a given problem; the
// ordering and the tree depend on that pattern alone, so they are computed once per pattern and
// kept here. The numeric phase reads them in the same order as when it computed them itself, so
// the factor is bit-identical either way.
struct SymbolicData {
  std::vector<ipfint> irn, icn;  ///< the pattern as Ipopt passed it (1-based): the key
  std::vector<ipfint> perm;      ///< perm[k] = original index of the k-th pivot
  std::vector<ipfint> ap, ai, entry, parent, colcount;
  // The row patterns of L in the order the up-looking factorisation visits them: row k has the
  // columns row_col[t] for t in [row_ptr[k], row_ptr[k+1]), its entry at row_pos[t] of L's
  // storage; li is L's row index array. All of it follows from the pattern alone.
  std::vector<ipfint> row_ptr, row_col, row_pos, li;
  ipfint lnz = 0;
  double ops = 0.0;
  std::uint64_t stamp = 0;  ///< identifies the entry in IKEEP (never reused)
};

// The patterns seen in this process, most recently used last. MA27AD/BD/CD run only inside
// NlpSolver::Solve, which holds the process-wide Ipopt lock, so the cache needs no lock of its
// own. A handful of patterns (one per MPC problem size in use) is typical; the oldest is dropped
// beyond kCapacity, and a factorisation whose entry was dropped recomputes its symbolic phase.
class SymbolicCache {
 public:
  static constexpr std::size_t kCapacity = 16;

  // The entry for the pattern, computed when new (nullptr when AMD or the allocation fails).
  const SymbolicData* Get(ipfint n, ipfint nz, const ipfint* irn, const ipfint* icn) {
    for (std::size_t i = entries_.size(); i-- > 0;) {
      SymbolicData& e = *entries_[i];
      if (static_cast<ipfint>(e.perm.size()) == n && static_cast<ipfint>(e.irn.size()) == nz &&
          std::equal(irn, irn + nz, e.irn.begin()) && std::equal(icn, icn + nz, e.icn.begin())) {
        std::rotate(entries_.begin() + static_cast<std::ptrdiff_t>(i),
                    entries_.begin() + static_cast<std::ptrdiff_t>(i) + 1, entries_.end());
        return entries_.back().get();
      }
    }
    auto e = std::make_unique<SymbolicData>();
    if (!Compute(n, nz, irn, icn, e.get())) return nullptr;
    e->stamp = ++last_stamp_;
    if (entries_.size() >= kCapacity) entries_.erase(entries_.begin());
    entries_.push_back(std::move(e));
    return entries_.back().get();
  }

  // The entry stamped `stamp` with these sizes, or nullptr (dropped since, or never made).
  const SymbolicData* Find(std::uint64_t stamp, ipfint n, ipfint nz) const {
    for (const auto& e : entries_)
      if (e->stamp == stamp && static_cast<ipfint>(e->perm.size()) == n &&
          static_cast<ipfint>(e->irn.size()) == nz)
        return e.get();
    return nullptr;
  }

 private:
  static bool Compute(ipfint n, ipfint nz, const ipfint* irn, const ipfint* icn, SymbolicData* d) {
    const auto un = static_cast<std::size_t>(n), unz = static_cast<std::size_t>(nz);
    std::vector<Eigen::Triplet<double, ipfint>> t;
    t.reserve(unz);
    for (ipfint e = 0; e < nz; ++e) t.emplace_back(irn[e] - 1, icn[e] - 1, 1.0);
    Eigen::SparseMatrix<double, Eigen::ColMajor, ipfint> pattern(n, n);
    pattern.setFromTriplets(t.begin(), t.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, ipfint> order;
    Eigen::AMDOrdering<ipfint>()(pattern, order);  // order.indices()[new] = old
    d->irn.assign(irn, irn + nz);
    d->icn.assign(icn, icn + nz);
    d->perm.resize(un);
    std::vector<ipfint> iperm(un), flag(un);
    for (ipfint k = 0; k < n; ++k) {
      d->perm[static_cast<std::size_t>(k)] = order.indices()[k];
      iperm[static_cast<std::size_t>(order.indices()[k])] = k;
    }
    d->ap.resize(un + 1);
    d->ai.resize(unz);
    d->entry.resize(unz);
    d->parent.resize(un);
    d->colcount.resize(un);
    PermutedUpper(n, nz, irn, icn, iperm.data(), d->ap.data(), d->ai.data(), d->entry.data());
    d->lnz =
        Symbolic(n, d->ap.data(), d->ai.data(), d->parent.data(), d->colcount.data(), flag.data());
    d->ops = 0.0;
    for (ipfint c : d->colcount) d->ops += static_cast<double>(c) * c;
    RowPatterns(n, d, flag.data());
    return true;
  }

  // The traversal of the numeric phase (Factorise) without its arithmetic: records each row's
  // pattern in visiting order and where its entries go.
  static void RowPatterns(ipfint n, SymbolicData* d, ipfint* flag) {
    const auto un = static_cast<std::size_t>(n), lnz = static_cast<std::size_t>(d->lnz);
    std::vector<ipfint> lp(un + 1), count(un, 0), pattern(un);
    lp[0] = 0;
    for (std::size_t k = 0; k < un; ++k) lp[k + 1] = lp[k] + d->colcount[k];
    d->row_ptr.assign(un + 1, 0);
    d->row_col.resize(lnz);
    d->row_pos.resize(lnz);
    d->li.resize(lnz);
    std::size_t t = 0;
    for (ipfint k = 0; k < n; ++k) {
      ipfint top = n;
      flag[k] = k;
      for (ipfint p = d->ap[static_cast<std::size_t>(k)];
           p < d->ap[static_cast<std::size_t>(k) + 1]; ++p) {
        ipfint i = d->ai[static_cast<std::size_t>(p)];
        ipfint len = 0;
        for (; flag[i] != k; i = d->parent[static_cast<std::size_t>(i)]) {
          pattern[static_cast<std::size_t>(len++)] = i;
          flag[i] = k;
        }
        while (len > 0)
          pattern[static_cast<std::size_t>(--top)] = pattern[static_cast<std::size_t>(--len)];
      }
      for (; top < n; ++top) {
        const auto i = static_cast<std::size_t>(pattern[static_cast<std::size_t>(top)]);
        const ipfint p2 = lp[i] + count[i]++;
        d->row_col[t] = static_cast<ipfint>(i);
        d->row_pos[t] = p2;
        d->li[static_cast<std::size_t>(p2)] = k;
        ++t;
      }
      d->row_ptr[static_cast<std::size_t>(k) + 1] = static_cast<ipfint>(t);
    }
  }

  std::vector<std::unique_ptr<SymbolicData>> entries_;
  std::uint64_t last_stamp_ = 0;
};

SymbolicCache& Cache() {
  static SymbolicCache cache;
  return cache;
}

// IKEEP has 3n entries (MA27's contract; Ipopt allocates them): the ordering fills the first n,
// the cache entry's stamp is kept in the next two (low and high 31 bits).
void PutStamp(ipfint n, std::uint64_t stamp, ipfint* ikeep) {
  ikeep[n] = static_cast<ipfint>(stamp & 0x7fffffffu);
  ikeep[n + 1] = static_cast<ipfint>((stamp >> 31) & 0x7fffffffu);
}
std::uint64_t GetStamp(ipfint n, const ipfint* ikeep) {
  return static_cast<std::uint64_t>(ikeep[n]) | (static_cast<std::uint64_t>(ikeep[n + 1]) << 31);
}

void Analyse(ipfint* N, ipfint* NZ, const ipfint* irn, const ipfint* icn, ipfint*, ipfint*,
             ipfint* ikeep, ipfint*, ipfint* nsteps, ipfint*, ipfint*, double*, ipfint* info,
             double* ops) {
  const ipfint n = *N, nz = *NZ;
  std::fill(info, info + 20, 0);
  if (n < 1) {
    info[0] = -1;  // MA27: N out of range
    return;
  }
  for (ipfint e = 0; e < nz; ++e)
    if (irn[e] < 1 || irn[e] > n || icn[e] < 1 || icn[e] > n) {
      info[0] = 1;  // MA27: entries out of range
      return;
    }
  try {
    const SymbolicData* d = Cache().Get(n, nz, irn, icn);
    if (d == nullptr) {
      info[0] = -1;
      return;
    }
    std::copy(d->perm.begin(), d->perm.end(), ikeep);
    PutStamp(n, d->stamp, ikeep);
    *nsteps = 1;
    *ops = d->ops;
    info[4] = nz + d->lnz + 3 * n;                              // LA: see Factorise
    info[5] = kHeader + 2 * (n + 1) + 2 * nz + 6 * n + d->lnz;  // LIW
  } catch (...) {
    info[0] = -1;
  }
}

void Factorise(ipfint* N, ipfint* NZ, const ipfint* irn, const ipfint* icn, double* a, ipfint* LA,
               ipfint* iw, ipfint* LIW, ipfint* ikeep, ipfint*, ipfint* maxfrt, ipfint*, ipfint*,
               double*, ipfint* info) {
  const ipfint n = *N, nz = *NZ;
  std::fill(info, info + 20, 0);
  if (n < 1) {
    info[0] = -1;
    return;
  }
  // IW: header, Lp (n+1), perm (n), then either Li (lnz) followed by the numeric scratch (cached
  // symbolic phase), or the symbolic arrays followed by Li, moved down at the end (no entry).
  ipfint* lp = iw + kHeader;
  ipfint* perm = lp + n + 1;
  const ipfint *ap, *ai, *entry, *parent, *colcount;
  ipfint *lnzc, *flag, *pattern, *li;
  ipfint lnz = 0;
  ipfint fixed_iw = 0;
  const SymbolicData* d = Cache().Find(GetStamp(n, ikeep), n, nz);
  if (d != nullptr) {
    ap = d->ap.data();
    ai = d->ai.data();
    entry = d->entry.data();
    parent = d->parent.data();
    colcount = d->colcount.data();
    lnz = d->lnz;
    li = perm + n;
    lnzc = li + lnz;
    flag = lnzc + n;
    pattern = flag + n;
    fixed_iw = static_cast<ipfint>(pattern + n - iw);
    if (*LIW < fixed_iw) {
      info[0] = -3;
      info[1] = fixed_iw;
      return;
    }
    std::copy(d->perm.begin(), d->perm.end(), perm);
  } else {
    ipfint* w_ap = perm + n;
    ipfint* w_ai = w_ap + n + 1;
    ipfint* w_entry = w_ai + nz;
    ipfint* iperm = w_entry + nz;
    ipfint* w_parent = iperm + n;
    lnzc = w_parent + n;
    flag = lnzc + n;
    pattern = flag + n;
    li = pattern + n;
    fixed_iw = static_cast<ipfint>(li - iw);
    if (*LIW < fixed_iw) {
      info[0] = -3;
      info[1] = fixed_iw + nz + n;
      return;
    }
    for (ipfint k = 0; k < n; ++k) {
      perm[k] = ikeep[k];
      iperm[ikeep[k]] = k;
    }
    PermutedUpper(n, nz, irn, icn, iperm, w_ap, w_ai, w_entry);
    lnz = Symbolic(n, w_ap, w_ai, w_parent, lnzc, flag);
    if (*LIW < fixed_iw + lnz) {
      info[0] = -3;
      info[1] = fixed_iw + lnz;
      return;
    }
    ap = w_ap;
    ai = w_ai;
    entry = w_entry;
    parent = w_parent;
    colcount = lnzc;  // read into Lp below, before the numeric phase reuses lnzc
  }
  const ipfint need_a = nz + lnz + 2 * n + n;
  if (*LA < need_a) {
    info[0] = -4;
    info[1] = need_a;
    return;
  }
  double* lx = a + nz;
  double* dg = lx + lnz;
  double* y = dg + n;
  double* sign = y + n;
  lp[0] = 0;
  for (ipfint k = 0; k < n; ++k) lp[k + 1] = lp[k] + colcount[k];
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
  if (d != nullptr) {
    // The same operations in the same order as below, with the row patterns read from the
    // symbolic phase instead of found by walking the elimination tree.
    std::copy(d->li.begin(), d->li.end(), li);
    const ipfint* row_ptr = d->row_ptr.data();
    const ipfint* row_col = d->row_col.data();
    const ipfint* row_pos = d->row_pos.data();
    for (ipfint k = 0; k < n; ++k) {
      for (ipfint p = ap[k]; p < ap[k + 1]; ++p) y[ai[p]] += a[entry[p]];
      double dk = y[k] + sign[k] * kStaticReg;
      y[k] = 0.0;
      for (ipfint t = row_ptr[k]; t < row_ptr[k + 1]; ++t) {
        const ipfint i = row_col[t];
        const double yi = y[i];
        y[i] = 0.0;
        const ipfint p2 = row_pos[t];
        for (ipfint p = lp[i]; p < p2; ++p) y[li[p]] -= lx[p] * yi;
        const double l_ki = yi / dg[i];
        dk -= l_ki * yi;
        lx[p2] = l_ki;
      }
      if (!std::isfinite(dk)) finite = false;
      if (!(sign[k] * dk > kDynamicEps)) dk = sign[k] * kDynamicDelta;
      dg[k] = dk;
      if (dk < 0.0) ++negative;
    }
  }
  for (ipfint k = 0; d == nullptr && k < n; ++k) {
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
      const double l_ki = yi / dg[i];
      dk -= l_ki * yi;
      li[p2] = k;
      lx[p2] = l_ki;
      ++lnzc[i];
    }
    if (!std::isfinite(dk)) finite = false;  // NaN/inf in the matrix: report it as singular
    if (!(sign[k] * dk > kDynamicEps)) dk = sign[k] * kDynamicDelta;
    dg[k] = dk;
    if (dk < 0.0) ++negative;
  }
  // CD needs only the header, Lp, perm and Li: Li must follow perm.
  if (li != perm + n) std::copy(li, li + lnz, perm + n);
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

// What Ipopt fixes when it first sees a problem and keeps under warm_start_same_structure: the
// sizes, the sparsity of the Jacobian and the Hessian, and per variable and row which bounds are
// finite and whether they coincide (a fixed variable is removed, an equal pair makes an equality
// row). Ipopt's "no bound" is |bound| >= 1e19 (nlp_lower_bound_inf, nlp_upper_bound_inf).
struct Structure {
  NlpSizes sizes;
  std::vector<int> jac_rows, jac_cols, hess_rows, hess_cols;
  std::vector<unsigned char> bound_kind;  // per variable, then per row

  // Reads `nlp`'s structure; `bounds` receives z_l, z_u, g_l, g_u (n, n, m, m).
  void Read(SparseNlp* nlp, std::vector<double>* bounds) {
    sizes = nlp->Sizes();
    const auto n = static_cast<std::size_t>(sizes.n), m = static_cast<std::size_t>(sizes.m);
    jac_rows.resize(static_cast<std::size_t>(sizes.nnz_jac));
    jac_cols.resize(jac_rows.size());
    hess_rows.resize(static_cast<std::size_t>(sizes.nnz_hess));
    hess_cols.resize(hess_rows.size());
    nlp->JacobianStructure(jac_rows.data(), jac_cols.data());
    nlp->HessianStructure(hess_rows.data(), hess_cols.data());
    bounds->resize(2 * (n + m));
    double* b = bounds->data();
    nlp->Bounds(b, b + n, b + 2 * n, b + 2 * n + m);
    bound_kind.resize(n + m);
    auto kind = [](double lo, double up) {
      return static_cast<unsigned char>((lo > -1e19 ? 1 : 0) | (up < 1e19 ? 2 : 0) |
                                        (lo == up ? 4 : 0));
    };
    for (std::size_t i = 0; i < n; ++i) bound_kind[i] = kind(b[i], b[n + i]);
    for (std::size_t i = 0; i < m; ++i) bound_kind[n + i] = kind(b[2 * n + i], b[2 * n + m + i]);
  }

  bool operator==(const Structure& o) const {
    return sizes.n == o.sizes.n && sizes.m == o.sizes.m && sizes.nnz_jac == o.sizes.nnz_jac &&
           sizes.nnz_hess == o.sizes.nnz_hess && jac_rows == o.jac_rows && jac_cols == o.jac_cols &&
           hess_rows == o.hess_rows && hess_cols == o.hess_cols && bound_kind == o.bound_kind;
  }
};

struct NlpSolver::Impl {
  NlpSolverOptions options;
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app;
  std::vector<double> bounds;
  std::vector<double> start_mult;  ///< z_l, z_u, lambda of the next warm start
  // The problem Ipopt last solved, kept for ReOptimizeTNLP: the same SparseNlp with the same
  // structure is re-solved on Ipopt's existing spaces, matrices and symbolic factorisation
  // (warm_start_same_structure) instead of rebuilding them in every solve.
  Ipopt::SmartPtr<Adapter> adapter;
  const SparseNlp* last_nlp = nullptr;
  Structure last, current;
  bool reusable = false;              ///< Ipopt's state after the last solve may be reused
  bool last_unscaled = false;         ///< the fresh solve's start needed no NLP scaling
  std::vector<double> z0, grad, jac;  ///< scratch of Unscaled
};

namespace {

// Ipopt's gradient-based NLP scaling (its default nlp_scaling_method, nlp_scaling_max_gradient
// 100) is determined from the starting point by a fresh solve and kept by a re-solve on the same
// structure. Whether the start needs no scaling at all: |df/dz_i| <= 100 for every variable and
// |dg_r/dz_i| <= 100 for every Jacobian entry (Ipopt takes these maxima over the free variables,
// per row; over all entries the answer is "no scaling" at most as often). A re-solve is
// only used when its fresh solve and it both need none, so that it is bit for bit the fresh
// solve.
bool Unscaled(SparseNlp* nlp, const Structure& st, std::vector<double>* z0,
              std::vector<double>* grad, std::vector<double>* jac) {
  constexpr double kMaxGradient = 100.0;  // Ipopt's nlp_scaling_max_gradient default
  const auto n = static_cast<std::size_t>(st.sizes.n);
  z0->resize(n);
  grad->resize(n);
  jac->resize(st.jac_rows.size());
  nlp->Start(z0->data());
  nlp->Gradient(z0->data(), grad->data());
  for (double g : *grad)
    if (!(std::abs(g) <= kMaxGradient)) return false;
  nlp->JacobianValues(z0->data(), jac->data());
  for (double v : *jac)
    if (!(std::abs(v) <= kMaxGradient)) return false;
  return true;
}

}  // namespace

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
  Impl& im = *impl_;
  try {
    std::lock_guard<std::mutex> lock(IpoptMutex());
    const NlpSolverOptions& o = im.options;
    auto opts = im.app->Options();
    im.current.Read(nlp, &im.bounds);
    const bool unscaled = Unscaled(nlp, im.current, &im.z0, &im.grad, &im.jac);
    const bool same =
        im.reusable && nlp == im.last_nlp && im.current == im.last && im.last_unscaled && unscaled;
    im.reusable = false;  // until this solve ends normally
    bool warm = false;
    if (o.warm_start) {
      const NlpSizes sz = im.current.sizes;
      im.start_mult.resize(2 * static_cast<std::size_t>(sz.n) + sz.m);
      double* w = im.start_mult.data();
      warm = nlp->StartMultipliers(w, w + sz.n, w + 2 * sz.n);
      if (!warm) im.start_mult.clear();
      opts->SetStringValue("warm_start_init_point", warm ? "yes" : "no");
      opts->SetNumericValue("mu_init", warm ? o.warm_start_mu_init : o.mu_init);
    }
    opts->SetStringValue("warm_start_same_structure", same ? "yes" : "no");
    Ipopt::ApplicationReturnStatus st;
    if (same) {
      im.adapter->Reset();
      st = im.app->ReOptimizeTNLP(Ipopt::SmartPtr<Ipopt::TNLP>(GetRawPtr(im.adapter)));
    } else {
      im.adapter = new Adapter(nlp, &im.bounds, &im.start_mult);
      std::swap(im.last, im.current);
      im.last_nlp = nlp;
      im.last_unscaled = unscaled;
      st = im.app->OptimizeTNLP(Ipopt::SmartPtr<Ipopt::TNLP>(GetRawPtr(im.adapter)));
    }
    r.status = static_cast<int>(st);
    auto stats = im.app->Statistics();
    if (Ipopt::IsValid(stats)) r.iterations = stats->IterationCount();
    r.violation = im.adapter->violation();
    const bool converged = st == Ipopt::Solve_Succeeded || st == Ipopt::Solved_To_Acceptable_Level;
    const bool feasible_stop = st == Ipopt::Maximum_Iterations_Exceeded ||
                               st == Ipopt::Search_Direction_Becomes_Too_Small ||
                               st == Ipopt::Restoration_Failed;
    r.usable = im.adapter->finalized() && (converged || feasible_stop) &&
               r.violation <= o.usable_violation;
    // Ipopt's internal structures stay valid after an ordinary end of the algorithm (converged,
    // stopped, infeasible, diverging); after an error (invalid problem or option, exception,
    // memory) the next solve starts afresh.
    im.reusable = static_cast<int>(st) > static_cast<int>(Ipopt::Not_Enough_Degrees_Of_Freedom);
  } catch (...) {
    r.usable = false;
    im.reusable = false;
  }
  return r;
}

}  // namespace scw::controller::motion
