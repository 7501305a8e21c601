// Point-mass tube MPC (PMPC) after Wischnewski et al. (2023, "Tube model predictive control for
// an autonomous race car"), the paper's default motion controller (§IV: "Tube MPC using a point
// mass model"). Our own formulation, solved as a QP with Ipopt.
//
// Model (curvilinear frame of the reference Path, time domain): state x = (n, w, v) with n [m]
// lateral offset of the CoG from the path (> 0 left), w = ṅ [m/s], v [m/s] speed along the path;
// input u = (a_t, a_n) [m/s²] tangential and normal acceleration of the point mass (a_n > 0 to the
// left, a_t > 0 forward). With the path curvature κ [1/m] and the centripetal demand
// c(n, v) = κ v²/(1 − nκ), over one step dt with u and c held:
//   n⁺ = n + dt·w + ½dt²·(a_n − c),   w⁺ = w + dt·(a_n − c),   v⁺ = v + dt·a_t.
// Per solve the model is linearised around the previous plan shifted in time (LTV-MPC; κ is the
// mean curvature of the path between the predicted stations), giving a convex QP:
//   min Σ_k q_n n_k² + q_w w_k² + q_v (v_k − v_ref(s̄_k))² + r_t (a_t − a_x,ref)² + r_n (a_n − c̄)²
//       + r_Δt Δa_t² + r_Δn Δa_n² + ρ₂ ε_k² + ρ₁ ε_k      (terminal weights × terminal_factor)
//   s.t. x_0 = measured, linearised dynamics,
//        −right(s̄_k) + tube ≤ n_k ± ε_k ≤ left(s̄_k) − tube       (soft track bounds, ε ≥ 0)
//        (a_t, a_n) inside an inscribed polygon of the planner's g-g law at v̄_k (GgTable: the
//        same speed-dependent limits, limit_fraction × GG, as the reference; the drive side uses
//        the drive exponent at v̄_k, the brake side the brake exponent),
//        scaled by nominal_fraction.
// Tube: the nominal plan keeps `tube_lateral` [m] off the track bounds; between solves an
// ancillary feedback law (100 Hz) steers the car back onto the nominal plan and may use the
// acceleration headroom (headroom − nominal_fraction)·limits reserved for it.
//
// Outputs (every sample_time = 0.01 s; the QP is re-solved every solve_period):
//   e_n = n − n̄(τ), e_ξ = ξ − ξ̄(τ) with ξ = heading error + β the course angle to the path,
//   L = max(L_min, t_la·v), a_n,cmd = ā_n(τ) − 2v²(e_n + L e_ξ)/L²  (clamped to headroom·ay_max),
//   δ = atan(l·a_n,cmd/v²) + K_us·a_n,cmd,  a_x,req = ā_t(τ) + k_v (v̄(τ) − v),
//   ESC target a_y,req = ā_n(τ) (the plan's lateral acceleration).
// limits = provided (the factory sets nominal_fraction = headroom = 1 and plans the reference at
// target_fraction of the limits): a_x,req is clamped into the g-g law at |a_n,cmd| as well
// (drive ≤ ax_drive·C(|a_n|/ay_max), brake ≥ −ax_brake·C(·)), so no request leaves the limits.
// A failed solve uses the previous plan shifted in time; once it runs out (horizon) a
// pure-pursuit-like law on the reference takes over until a solve succeeds. Both are counted
// (the shared MPC wrapper, mpc_common.h).
//
// Solver: Ipopt told what the problem is — a convex QP (constant Jacobian and Hessian, evaluated
// once per solve), factorised with the quasi-definite LDLᵀ instead of MUMPS (nlp_solver.h; MUMPS
// was 95 % of the solve time), warm-started from the previous plan and its multipliers shifted in
// time like the plan, no forced iterative refinement. The QP, its tolerance and so the plans are
// unchanged (differences at the solver tolerance); median solve time ~15 ms → ~1 ms.
//
// Workspace: every array of the QP is allocated in MakeState; Ipopt re-solves on the structures
// of the State's first solve and still allocates its iterates internally (see nlp_solver.h).
// Solve times are in State::diagnostics.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "controller/motion/motion_controller.h"
#include "controller/motion/mpc_common.h"
#include "params/schema/mpc_params.h"

namespace scw::controller::motion {

/// The point-mass model (pure functions; indices: x = (n, w, v), u = (a_t, a_n)).
struct PointMassModel {
  using StateVec = Eigen::Vector3d;
  using InputVec = Eigen::Vector2d;
  static constexpr int kN = 0, kW = 1, kV = 2, kAt = 0, kAn = 1;
  /// One step of length dt on a path of curvature kappa (see the file comment).
  static StateVec Step(const StateVec& x, const InputVec& u, double kappa, double dt) noexcept;
  /// ∂Step/∂x and ∂Step/∂u (analytic).
  static void Jacobians(const StateVec& x, const InputVec& u, double kappa, double dt,
                        Eigen::Matrix3d* a, Eigen::Matrix<double, 3, 2>* b) noexcept;
};

/// The scenario's settings (params::PmpcParams, keys motion.pmpc.*) plus what the vehicle and the
/// tracking loop fix.
struct PmpcOptions : params::PmpcParams {
  double sample_time = 0.01;         ///< feedback law period [s] (the tracking loop's)
  double wheelbase = 3.115;          ///< l [m] (the vehicle's)
  double understeer_gradient = 0.0;  ///< K_us [rad/(m/s²)] (the vehicle's)
  double max_steering = 0.3;         ///< [rad] (the vehicle's)
  bool mumps = false;      ///< factorise with MUMPS instead of the quasi-definite LDLᵀ (checks)
  bool warm_start = true;  ///< start from the shifted multipliers of the plan in use
};

class PointMassMpc final : public MpcController {
 public:
  struct Workspace;
  /// The current plan: nodes k = 0..N of the state and intervals k = 0..N−1 of the input.
  struct Plan {
    std::vector<double> n, w, v, s;  ///< N+1 [m, m/s, m/s, m] (s unwrapped from s_0)
    std::vector<double> at, an;      ///< N [m/s²]
    std::vector<double> kappa;       ///< N curvature used per interval [1/m]
    double t0 = 0.0;                 ///< time of node 0 [s]
    bool valid = false;
    void Resize(int steps);  ///< N = steps, zeros, not valid
  };
  struct State : MpcState<Plan> {
    explicit State(const PointMassMpc& c);
    ~State() override;
    double last_solve_t = -1e300;
    double prev_at = 0.0, prev_an = 0.0;  ///< inputs applied at the last solve [m/s²]
    std::unique_ptr<Workspace> ws;
  };

  /// Throws scw::ConfigError listing every inconsistent option, limit, corridor size and a missing
  /// path.
  PointMassMpc(const PmpcOptions& options, GgTable limits, Corridor corridor,
               std::shared_ptr<const Path> path);
  ~PointMassMpc() override;

  std::string name() const override { return "pmpc"; }
  double sample_time() const noexcept override { return options_.sample_time; }
  std::unique_ptr<MotionState> MakeState() const override;
  MotionOutput Step(const MotionInput& in, MotionState* state) const noexcept override;

  const PmpcOptions& options() const noexcept { return options_; }
  /// The inscribed g-g polygon in normalised coordinates (x = a_t/a_lim, r = |a_n|/ay_max):
  /// x ≤ c_j + m_j r for the segments j (same for drive and brake, m_j ≤ 0).
  /// Index of the first side of the inscribed polygon used for exponent p in the slope/offset
  /// tables (the largest grid exponent ≤ p).
  std::size_t PolygonBase(double p) const noexcept;

 private:
  bool Solve(const MotionInput& in, double s, double n, double w, double v, State* st) const;
  PmpcOptions options_;
  /// options_.esc_target, read once (not per step): which a_y request the ESC gets.
  enum class EscTarget { kPlan, kCommanded, kSteering };
  EscTarget esc_target_ = EscTarget::kPlan;
  /// options_.limits == "provided": the feedback's a_x is held inside the g-g law at its a_n.
  bool provided_limits_ = false;
  std::vector<double> slope_, offset_;
};

}  // namespace scw::controller::motion
