// Pure-pursuit tracking controller of the paper's stack (stability-control spec §6.1, parameters
// §7.3: params/schema/tracking_params.h).
//
// Per step (tS):
//   s      = projection of the CoG onto the path
//   idx    = projection of the point max(v_x, 3)·t_long,ff ahead along the heading
//   e_v,f  = Tustin lag (T_v) of v_target(idx) − v_x
//   a_x,req = a_x,target(idx) + k_v·e_v,f           (≤ −4.5 m/s² when v_target < 0.05 m/s)
//   L      = L_min + t_lat·v_x + min(g_κ/max(|κ(idx)|, 1e-8), L_κ,max)      [m]
//   (x_L, y_L) = path point at s + L;  d_y = lateral offset of it in the vehicle frame
//   κ_PP   = LPF(exp(−tS/T_κ)) of 2·d_y/L²
//   δ      = w_ff·atan(l·κ(s + v_x·t_lat,ff)) + atan(l·κ_PP) + δ_offset, clamped to the limits
//   ESC target a_y,req = κ_PP·v_x²
// Deviation from the car (documented, docs/quirks.md §10.2 #11): the curvature lookahead term
// g_κ/|κ| is capped at L_κ,max (default 20 m; the car's term reaches 4000 m on straights), and the
// target point wraps around the closed track instead of being extrapolated past the line's end.
#pragma once

#include "controller/common/low_pass.h"
#include "controller/common/tustin_lag.h"
#include "controller/motion/motion_controller.h"
#include "params/schema/tracking_params.h"

namespace scw::controller::motion {

/// What pure pursuit publishes as the lateral-acceleration request (the ESC's yaw reference).
enum class EscTarget {
  /// κ_PP v² with κ_PP the filtered feedback curvature only: the car's node (spec §6.1 step 12).
  /// In corners it is about half the real a_y (the feed-forward steering is not in it).
  kFeedback,
  /// tan(δ_ff + δ_fb) / l · v²: the total commanded curvature, feed-forward included.
  kTotal,
};

struct PurePursuitOptions {
  double max_curvature_lookahead = 20.0;  ///< [m] cap of g_κ/|κ|
  EscTarget esc_target = EscTarget::kFeedback;
  double projection_window =
      20.0;  ///< [m] local search window of the path matching (the car moves < 1 m per step)
};

class PurePursuit final : public MotionController {
 public:
  struct State : MotionState {
    TustinLag::State vel_error{};
    double kappa_filtered = 0.0;
  };

  /// Validates the parameters and that a path is given (throws scw::ConfigError).
  PurePursuit(const params::TrackingParams& p, std::shared_ptr<const Path> path,
              PurePursuitOptions options = {});

  std::string name() const override { return "pure_pursuit"; }
  double sample_time() const noexcept override { return p_.tS; }
  std::unique_ptr<MotionState> MakeState() const override;
  MotionOutput Step(const MotionInput& in, MotionState* state) const noexcept override;

 private:
  params::TrackingParams p_;
  std::shared_ptr<const Path> path_;
  PurePursuitOptions options_;
  TustinLag vel_lag_;
  LowPass kappa_filter_;
};

}  // namespace scw::controller::motion
