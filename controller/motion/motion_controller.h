// Interface of the motion controllers (pure pursuit, point-mass MPC, single-track NMPC): they
// follow a reference Path and request steering and longitudinal acceleration, plus optional ESC
// targets. The stability controller sits between them and the car.
//
// An object is immutable after construction (parameters, the shared Path); its mutable data lives
// in a MotionState made by MakeState() (allocated once per run, never in Step). Step is noexcept
// and allocation-free for the pure-pursuit controller; solver-based controllers keep their
// workspace in their state.
#pragma once

#include <limits>
#include <memory>
#include <string>

#include "controller/motion/path.h"

namespace scw::controller::motion {

/// What a motion controller reads (world pose from localisation, body-frame motion).
struct MotionInput {
  double t = 0.0;         ///< [s] simulation time
  double x = 0.0;         ///< [m]
  double y = 0.0;         ///< [m]
  double psi = 0.0;       ///< [rad] heading
  double v_x = 0.0;       ///< [m/s] body frame
  double v_y = 0.0;       ///< [m/s] body frame, > 0 left
  double yaw_rate = 0.0;  ///< [rad/s]
  double a_x = 0.0;       ///< [m/s²]
  double a_y = 0.0;       ///< [m/s²]
  double steering = 0.0;  ///< [rad] measured steering (tyre angle)
};

struct MotionOutput {
  double steering_request = 0.0;  ///< δ_req [rad], > 0 left
  double ax_request = 0.0;        ///< a_x,req [m/s²]
  /// ESC targets; NaN = not provided.
  double ay_request = std::numeric_limits<double>::quiet_NaN();        ///< [m/s²]
  double yaw_rate_request = std::numeric_limits<double>::quiet_NaN();  ///< [rad/s]
  double beta_request = std::numeric_limits<double>::quiet_NaN();      ///< [rad]
  // Diagnostics (path tracking).
  double s = 0.0;              ///< [m] matched arc length
  double lateral_error = 0.0;  ///< [m] > 0 left of the path
  double heading_error = 0.0;  ///< [rad]
  double v_target = 0.0;       ///< [m/s]
};

struct MotionState {
  virtual ~MotionState() = default;
  double s_hint = -1.0;  ///< last matched s (local projection search)
};

/// Matches the vehicle on the path (local search from the state's hint), keeps the hint and fills
/// the tracking diagnostics (s, lateral and heading error) of `out`. Shared by every controller.
inline PathProjection MatchOnPath(const Path& path, const MotionInput& in, double window,
                                  MotionState* st, MotionOutput* out) noexcept {
  const PathProjection here = path.Project(in.x, in.y, in.psi, st->s_hint, window);
  st->s_hint = here.s;
  out->s = here.s;
  out->lateral_error = here.lateral_error;
  out->heading_error = here.heading_error;
  return here;
}

class MotionController {
 public:
  virtual ~MotionController() = default;
  virtual std::string name() const = 0;
  /// Sample time the controller is designed for [s].
  virtual double sample_time() const noexcept = 0;
  virtual std::unique_ptr<MotionState> MakeState() const = 0;
  virtual MotionOutput Step(const MotionInput& in, MotionState* state) const noexcept = 0;
};

}  // namespace scw::controller::motion
