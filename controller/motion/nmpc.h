// Nonlinear MPC on a single-track model (NMPC), the paper's third motion controller (§IV, after
// Bongard et al. 2025). Our own formulation, solved with Ipopt (analytic Jacobians, Hessian of the
// Lagrangian by central differences of the analytic Jacobians).
//
// Model (time domain, curvilinear frame of the reference Path, curvature κ frozen per interval):
//   state x = (n, μ, v_x, v_y, r): lateral offset of the CoG from the path [m] (> 0 left), heading
//   of the body relative to the path [rad], body-frame velocities [m/s], yaw rate [rad/s];
//   input u = (δ, a): front tyre steering angle [rad] (> 0 left) and longitudinal acceleration
//   request a = F_x/m [m/s²] (net of drag and rolling resistance, which the longitudinal
//   controller compensates; F_x acts along the body x axis at the CoG).
//     ṅ   = v_x sin μ + v_y cos μ
//     ṡ   = (v_x cos μ − v_y sin μ)/(1 − nκ)
//     μ̇   = r − κ ṡ
//     v̇_x = a − F_yf sin δ / m + v_y r
//     v̇_y = (F_yf cos δ + F_yr)/m − v_x r
//     ṙ   = (l_f F_yf cos δ − l_r F_yr)/I_z
//   Tyres per axle, simplified Magic Formula: F_y = D sin(C atan(B α)), D = μ_y F_z,
//   F_z = static share m g l_{r,f}/l + ½ρ A_{f,r} v_x² (downforce), α_f = δ − atan((v_y + l_f
//   r)/v_x), α_r = −atan((v_y − l_r r)/v_x). B, C, μ_y per axle from the MF5.2 coefficients at a
//   reference speed (SingleTrackParamsFrom). Lateral acceleration a_y = (F_yf cos δ + F_yr)/m.
//   Discretised by RK4 (`substeps` per interval dt, input held).
// Optimal control problem, N intervals of dt:
//   min Σ_k q_n n_k² + q_μ μ_k² + q_v (v_x,k − v_ref(s̄_k))² + r_δ Δδ² + r_a Δa² + r_a0 (a − a_ref)²
//       + ρ₂ ε_k² + ρ₁ ε_k                                    (terminal weights × terminal_factor)
//   s.t. x_0 = measured, x_{k+1} = Φ(x_k, u_k; κ_k), |δ| ≤ δ_max, |δ_k − δ_{k−1}| ≤ δ̇_max dt,
//        a_k ≤ ax_drive_max(v̄_k),  (a_k/ax_brake_max(v̄_k))² + (a_y,k/ay_max(v̄_k))² ≤ 1,
//        −right(s̄_k) + margin ≤ n_k ± ε_k ≤ left(s̄_k) − margin (soft), v_x ≥ 2 m/s,
//   with the limits of GgTable (the planner's limit_fraction × GG × plant g-g-v) × accel_fraction.
//   The frozen quantities (κ_k, v_ref, the limits, s̄_k) come from the previous plan shifted in time
//   (or the reference on the first call), which is also the primal warm start.
// Outputs (every sample_time, one solve each): δ_req = δ_0, a_x,req = a_0, ESC targets from the
// plan at node 1: a_y,req, ψ̇_req = r_1, β_req = atan(v_y,1/v_x,1). A failed solve uses the previous
// plan shifted in time; once it runs out a pure-pursuit-like law on the reference takes over until
// a solve succeeds. Both are counted in the diagnostics (the shared MPC wrapper, mpc_common.h).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "controller/motion/motion_controller.h"
#include "controller/motion/mpc_common.h"
#include "params/schema/mpc_params.h"
#include "params/schema/vehicle_params.h"

namespace scw::controller::motion {

struct AxleTire {
  double mu = 1.5;  ///< peak friction μ_y [-]
  double b = 10.0;  ///< stiffness factor B [1/rad]
  double c = 1.5;   ///< shape factor C [-]
};

struct SingleTrackParams {
  double mass = 720.0;            ///< [kg]
  double yaw_inertia = 1000.0;    ///< [kg m²]
  double lf = 1.786;              ///< CoG to front axle [m]
  double lr = 1.329;              ///< CoG to rear axle [m]
  double gravity = 9.81;          ///< [m/s²]
  double downforce_front = 1.03;  ///< ½ρA_f [kg/m]: front downforce = this × v_x²
  double downforce_rear = 1.46;   ///< ½ρA_r [kg/m]
  AxleTire front, rear;
};

/// The single-track parameters of a plant vehicle: geometry, mass, downforce, and per axle the
/// simplified Magic Formula (C = PCY1, μ_y = (PDY1 + PDY2 dfz)·LMUY·grip, B = K_y/(C μ_y F_z) with
/// K_y the MF5.2 cornering stiffness) at the per-tyre load of `reference_speed` [m/s].
SingleTrackParams SingleTrackParamsFrom(const params::VehicleParams& v,
                                        double reference_speed = 50.0);

/// Axle cornering stiffness B·C·D [N/rad] at speed v.
double CorneringStiffness(const SingleTrackParams& p, bool front, double v) noexcept;
/// Linear single-track understeer gradient K_us = m/l (l_r/C_f − l_f/C_r) [rad/(m/s²)] at speed v.
double UndersteerGradient(const SingleTrackParams& p, double v) noexcept;

struct SingleTrackModel {
  static constexpr int kNx = 5, kNu = 2, kNz = 7;
  static constexpr int kN = 0, kMu = 1, kVx = 2, kVy = 3, kR = 4, kDelta = 0, kA = 1;
  using StateVec = Eigen::Matrix<double, kNx, 1>;
  using InputVec = Eigen::Matrix<double, kNu, 1>;
  using Jac = Eigen::Matrix<double, kNx, kNz>;  ///< ∂/∂(x, u)
  using Row = Eigen::Matrix<double, 1, kNz>;

  /// ẋ = f(x, u; κ), optionally its Jacobian.
  static StateVec Derivatives(const SingleTrackParams& p, const StateVec& x, const InputVec& u,
                              double kappa, Jac* jac = nullptr) noexcept;
  /// a_y = (F_yf cos δ + F_yr)/m [m/s²], optionally its gradient.
  static double LateralAcceleration(const SingleTrackParams& p, const StateVec& x,
                                    const InputVec& u, Row* grad = nullptr) noexcept;
  /// Progress ṡ along the path [m/s].
  static double PathSpeed(const StateVec& x, double kappa) noexcept;
  /// RK4 over dt in `substeps` steps with u held, optionally its Jacobian ∂x⁺/∂(x, u).
  static StateVec Discrete(const SingleTrackParams& p, const StateVec& x, const InputVec& u,
                           double kappa, double dt, int substeps, Jac* jac = nullptr) noexcept;
};

/// The scenario's settings (params::NmpcParams, keys motion.nmpc.*) plus the vehicle's steering
/// limit.
struct NmpcOptions : params::NmpcParams {
  double max_steering = 0.3;  ///< [rad] (the vehicle's)
};

class SingleTrackMpc final : public MpcController {
 public:
  struct Workspace;
  struct Plan {
    std::vector<double> x;      ///< (N+1)·5 states, node-major
    std::vector<double> u;      ///< N·2 inputs
    std::vector<double> s;      ///< N+1 predicted path stations (unwrapped) [m]
    std::vector<double> kappa;  ///< N frozen curvatures [1/m]
    double t0 = 0.0;
    bool valid = false;
    void Resize(int steps);  ///< N = steps, zeros, not valid
  };
  struct State : MpcState<Plan> {
    explicit State(const SingleTrackMpc& c);
    ~State() override;
    double prev_delta = 0.0, prev_a = 0.0;  ///< inputs applied last [rad, m/s²]
    std::unique_ptr<Workspace> ws;
  };

  /// Throws scw::ConfigError listing every inconsistent option, limit, corridor size and a missing
  /// path.
  SingleTrackMpc(const NmpcOptions& options, const SingleTrackParams& model, GgTable limits,
                 Corridor corridor, std::shared_ptr<const Path> path);
  ~SingleTrackMpc() override;

  std::string name() const override { return "nmpc"; }
  double sample_time() const noexcept override { return options_.sample_time; }
  std::unique_ptr<MotionState> MakeState() const override;
  MotionOutput Step(const MotionInput& in, MotionState* state) const noexcept override;

  const NmpcOptions& options() const noexcept { return options_; }
  const SingleTrackParams& model() const noexcept { return model_; }

 private:
  bool Solve(const MotionInput& in, double s, const SingleTrackModel::StateVec& x0,
             State* st) const;
  NmpcOptions options_;
  SingleTrackParams model_;
};

}  // namespace scw::controller::motion
