#include "tuning/sim/closed_loop.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "controller/motion/longitudinal.h"
#include "params/io/csv.h"
#include "plant/track/road_surface.h"
#include "plant/vehicle/vehicle.h"
#include "tuning/sim/events.h"
#include "tuning/sim/motion_factory.h"

namespace scw::tuning {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

bool Finite(const plant::Measurement& m) {
  bool ok = std::isfinite(m.x) && std::isfinite(m.y) && std::isfinite(m.psi) &&
            std::isfinite(m.v_x) && std::isfinite(m.v_y) && std::isfinite(m.yaw_rate) &&
            std::isfinite(m.a_x) && std::isfinite(m.a_y);
  for (double w : m.wheel_speed) ok = ok && std::isfinite(w);
  return ok;
}

/// Rising-edge counter and active time of one intervention flag.
void CountIntervention(bool now, bool* before, int* count, double* time, double dt) {
  if (now && !*before) ++*count;
  if (now) *time += dt;
  *before = now;
}

bool AnyActive(const PerWheel<controller::SlipPhase>& s) {
  for (auto p : s)
    if (p != controller::SlipPhase::kInactive) return true;
  return false;
}

}  // namespace

std::vector<std::string> TraceHeader() {
  std::vector<std::string> h = {"t_s",
                                "lap",
                                "s_m",
                                "x_m",
                                "y_m",
                                "psi_rad",
                                "vx_mps",
                                "vy_mps",
                                "yaw_rate_radps",
                                "ax_mps2",
                                "ay_mps2",
                                "beta_deg",
                                "lateral_error_m",
                                "heading_error_deg",
                                "v_target_mps",
                                "steer_req_rad",
                                "steer_out_rad",
                                "steer_meas_rad",
                                "throttle_req",
                                "throttle_out",
                                "long_fx_N",
                                "gear",
                                "engine_speed_radps",
                                "esc_active",
                                "cs_active",
                                "abs_active",
                                "tc_active",
                                "yaw_moment_Nm"};
  for (const char* w : kWheelNames) h.push_back(std::string("p_req_") + w + "_bar");
  for (const char* w : kWheelNames) h.push_back(std::string("p_out_") + w + "_bar");
  for (const char* w : kWheelNames) h.push_back(std::string("slip_") + w + "_pct");
  for (const char* w : kWheelNames) h.push_back(std::string("alpha_") + w + "_rad");
  for (const char* w : kWheelNames) h.push_back(std::string("fz_") + w + "_N");
  h.push_back("events");  // bit mask of the active events: 1 throttle, 2 steer, 4 rear grip, 8 gust
  return h;
}

RunMetrics RunClosedLoop(const ResolvedScenario& sc, const params::StabilityParams& stability,
                         const RunOptions& options) {
  const params::StabilityParams stab = PrepareStability(sc, stability);
  controller::StabilityOptions sopt;
  sopt.release_compat = sc.spec.subsystems.release_compat;
  const controller::StabilityController ctl(stab, sopt);
  const plant::Vehicle car(sc.vehicle);
  const auto motion = MakeMotionController(sc);
  const controller::motion::MotionController& pp = *motion;
  const controller::motion::LongitudinalController lon(sc.spec.motion.longitudinal,
                                                       sc.longitudinal_model, sc.tracking.tS);
  const auto& ab = sc.spec.abort;
  const plant::Track& track = *sc.track;
  // The road under each wheel (the track's friction and patches, the scenario's patches): the
  // plant feels it at every plant step; on a uniform surface the default environment is exact.
  const plant::RoadSurface road(track, sc.spec.friction_patches);
  double road_hint = plant::Track::kNoHint;
  // The scenario's faults, grip events and gusts (tuning/sim/events.h).
  const EventSchedule events(sc.spec.events, track);
  EventSchedule::State event_state = events.MakeState();
  const double h = car.time_step();
  const double ts = stab.tS;
  const long ratio = std::max(1L, std::lround(ts / h));
  // The motion controller may run slower than the stability controller (MPCs); its output is
  // held between its steps.
  const long motion_every = std::max(1L, std::lround(pp.sample_time() / ts));
  controller::motion::MotionOutput mo;
  const long log_every = std::max(1L, std::lround(1.0 / (sc.spec.log_rate * ts)));
  const double timeout = ab.timeout_factor * sc.spec.laps * std::max(sc.ideal_lap_time, 1.0);

  RunMetrics m;
  m.laps_planned = sc.spec.laps;
  m.distance_planned = sc.spec.laps * track.length();

  // Flying start on the reference line at the reference speed.
  const auto start = sc.path->Sample(0.0);
  plant::State st = car.MakeState({start.x, start.y, start.psi, start.v});
  plant::SensorNoiseState noise(static_cast<std::uint64_t>(sc.spec.seed));
  auto motion_state = pp.MakeState();
  controller::StabilityController::State ctl_state;
  controller::motion::LongitudinalController::State lon_state;
  plant::Actuators act;
  controller::StabilityOutput out;
  bool slip_active = false;
  bool esc_active = false;  // of the previous step (motion.longitudinal.hold_during_esc)

  // Laps by unwrapped progress along the track (robust to a start just before the line).
  double s_hint = plant::Track::kNoHint, last_s = 0.0, progress = 0.0, prev_progress = 0.0;
  double prev_t = 0.0, lap_start = 0.0;
  int laps_done = 0;
  const double length = track.length();
  PerWheel<double> lock_time{}, spin_time{};
  bool esc_b = false, cs_b = false, abs_b = false, tc_b = false;
  const PerWheel<double> brake_gain = {
      sc.vehicle.brakes.torque_gain_front, sc.vehicle.brakes.torque_gain_front,
      sc.vehicle.brakes.torque_gain_rear, sc.vehicle.brakes.torque_gain_rear};

  for (long tick = 0;; ++tick) {
    const double t = static_cast<double>(tick) * ts;
    const plant::Measurement meas = car.Measure(st, sc.vehicle.sensors.noise ? &noise : nullptr);
    if ((st.status & plant::kStatusNonFinite) || !Finite(meas)) {
      m.status = RunStatus::kNonFinite;
      break;
    }
    const auto tp = track.Project(meas.x, meas.y, meas.psi, s_hint);
    if (tick > 0) {
      double ds = tp.s - last_s;
      if (ds > 0.5 * length) ds -= length;
      if (ds < -0.5 * length) ds += length;
      progress += ds;
    }
    const double s_before = last_s;
    s_hint = last_s = tp.s;
    if (progress >= (laps_done + 1) * length && progress > prev_progress) {
      // Crossing time interpolated within the tick.
      const double target = (laps_done + 1) * length;
      const double t_cross =
          prev_t + (t - prev_t) * (target - prev_progress) / (progress - prev_progress);
      m.lap_times.push_back(t_cross - lap_start);
      lap_start = t_cross;
      ++laps_done;
    }
    prev_progress = progress;
    prev_t = t;
    m.time = t;
    m.end_s = tp.s;
    m.end_lap = laps_done;
    m.distance = std::max(0.0, progress);
    if (laps_done >= sc.spec.laps) {
      m.status = RunStatus::kCompleted;
      m.distance = m.distance_planned;
      break;
    }
    EventSchedule::Active ev;
    if (!events.empty()) {
      if (tick > 0) events.Update(s_before, tp.s, laps_done + 1, t, &event_state);
      ev = events.At(t, event_state);
    }

    // Motion control.
    controller::motion::MotionInput mi{
        t,        meas.x,        meas.y,   meas.psi, meas.v_x,
        meas.v_y, meas.yaw_rate, meas.a_x, meas.a_y, meas.steering_angle};
    if (tick % motion_every == 0) mo = pp.Step(mi, motion_state.get());
    const double speed = std::hypot(meas.v_x, meas.v_y);
    auto lo = lon.Step(
        {mo.ax_request, meas.a_x, speed, meas.engine_speed, meas.gear, slip_active, esc_active},
        &lon_state);
    if (ev.throttle_fault) {  // the request path overridden: what the stability controller sees
      lo.throttle = ev.throttle;
      lo.brake_bar = {};
      lo.force = lon.DriveForce(meas.engine_speed, meas.gear, ev.throttle);
    }
    const double steering_request =
        ev.steer_offset != 0.0 ? mo.steering_request + ev.steer_offset : mo.steering_request;

    // Stability control.
    controller::StabilityInput in;
    in.t = t;
    in.v_x = meas.v_x;
    in.v_y = meas.v_y;
    in.yaw_rate = meas.yaw_rate;
    in.a_x = meas.a_x;
    in.a_y = meas.a_y;
    in.steering_measured = meas.steering_angle;
    in.steering_request = steering_request;
    in.ay_request = mo.ay_request;
    in.yaw_rate_request = mo.yaw_rate_request;
    in.beta_request = mo.beta_request;
    in.brake_request_bar = lo.brake_bar;
    in.throttle_request = lo.throttle;
    in.gear_request = meas.gear_request;
    in.gear = meas.gear;
    in.engine_speed = meas.engine_speed;
    in.wheel_speed = meas.wheel_speed;
    in.brake_measured_bar = meas.brake_pressure;
    in.long_fx = lo.force;
    if (options.on_controller_input) options.on_controller_input(in);
    out = ctl.Step(in, &ctl_state);
    if (options.on_controller_output) options.on_controller_output(out);
    slip_active = out.slip_control_active;
    esc_active = out.esc_active;
    act.steer_req = out.steering;
    act.brake_pressure_req = out.brake_bar;
    act.throttle = out.throttle;

    // Metrics and abort conditions.
    const double beta = std::atan2(meas.v_y, std::max(std::abs(meas.v_x), 1.0));
    m.max_abs_sideslip = std::max(m.max_abs_sideslip, std::abs(beta));
    m.max_abs_lateral_error = std::max(m.max_abs_lateral_error, std::abs(mo.lateral_error));
    m.max_abs_heading_error = std::max(m.max_abs_heading_error, std::abs(mo.heading_error));
    m.max_speed = std::max(m.max_speed, speed);
    m.sideslip_excess_integral +=
        std::max(0.0, std::abs(beta) * kRadToDeg - options.sideslip_allowed_deg) * ts;
    for (std::size_t i = 0; i < 4; ++i) {
      const double slip_pct = 100.0 * st.out.kappa[i];
      double& mx = IsFront(i) ? m.max_slip_front : m.max_slip_rear;
      mx = std::max(mx, std::abs(slip_pct));
      lock_time[i] = slip_pct < -ab.lock_slip_pct ? lock_time[i] + ts : 0.0;
      spin_time[i] = slip_pct > ab.spin_slip_pct ? spin_time[i] + ts : 0.0;
      if (out.esc_active && IsFront(i))
        m.esc_brake_energy += std::max(0.0, out.brake_bar[i] - in.brake_request_bar[i]) *
                              brake_gain[i] * std::abs(meas.wheel_speed[i]) * ts;
      if (out.abs_state[i] != controller::SlipPhase::kInactive)
        m.abs_pressure_released += std::max(0.0, in.brake_request_bar[i] - out.brake_bar[i]) * ts;
    }
    if (AnyActive(out.tc_state))
      m.tc_throttle_cut += std::max(0.0, in.throttle_request - out.throttle) * ts;
    CountIntervention(out.esc_active, &esc_b, &m.esc_count, &m.esc_time, ts);
    CountIntervention(out.cs_active, &cs_b, &m.cs_count, &m.cs_time, ts);
    CountIntervention(AnyActive(out.abs_state), &abs_b, &m.abs_count, &m.abs_time, ts);
    CountIntervention(AnyActive(out.tc_state), &tc_b, &m.tc_count, &m.tc_time, ts);

    if (options.trace && tick % log_every == 0) {
      io::CsvWriter& w = *options.trace;
      w.Add(t);
      w.Add(laps_done);
      w.Add(tp.s);
      w.Add(meas.x);
      w.Add(meas.y);
      w.Add(meas.psi);
      w.Add(meas.v_x);
      w.Add(meas.v_y);
      w.Add(meas.yaw_rate);
      w.Add(meas.a_x);
      w.Add(meas.a_y);
      w.Add(beta * kRadToDeg);
      w.Add(mo.lateral_error);
      w.Add(mo.heading_error * kRadToDeg);
      w.Add(mo.v_target);
      w.Add(steering_request);
      w.Add(out.steering);
      w.Add(meas.steering_angle);
      w.Add(lo.throttle);
      w.Add(out.throttle);
      w.Add(lo.force);
      w.Add(meas.gear);
      w.Add(meas.engine_speed);
      w.Add(out.esc_active ? 1 : 0);
      w.Add(out.cs_active ? 1 : 0);
      w.Add(AnyActive(out.abs_state) ? 1 : 0);
      w.Add(AnyActive(out.tc_state) ? 1 : 0);
      w.Add(out.yaw_moment);
      for (double p : in.brake_request_bar) w.Add(p);
      for (double p : out.brake_bar) w.Add(p);
      for (double k : st.out.kappa) w.Add(100.0 * k);
      for (double a : st.out.alpha) w.Add(a);
      for (double f : st.out.fz) w.Add(f);
      w.Add(static_cast<int>(ev.mask));
      w.EndRow();
    }

    if (std::abs(beta) * kRadToDeg > ab.max_sideslip_deg) {
      m.status = RunStatus::kSideslip;
      break;
    }
    if (std::abs(mo.lateral_error) > ab.max_lateral_error) {
      m.status = RunStatus::kLateralError;
      break;
    }
    if (ab.off_track && (tp.n > track.WidthLeftAt(tp.s) || -tp.n > track.WidthRightAt(tp.s))) {
      m.status = RunStatus::kOffTrack;
      break;
    }
    bool locked = false, spun = false;
    for (std::size_t i = 0; i < 4; ++i) {
      locked = locked || lock_time[i] > ab.slip_time;
      spun = spun || spin_time[i] > ab.slip_time;
    }
    if (locked || spun) {
      m.status = locked ? RunStatus::kWheelLock : RunStatus::kWheelSpin;
      break;
    }
    if (t > timeout) {
      m.status = RunStatus::kTimeout;
      break;
    }

    const bool event_env = ev.rear_grip != 1.0 || ev.wind_x != 0.0 || ev.wind_y != 0.0;
    if (road.uniform() && !event_env) {
      for (long k = 0; k < ratio; ++k) car.Step(act, &st);
    } else {
      for (long k = 0; k < ratio; ++k) {
        plant::Environment env;
        if (!road.uniform()) {
          const auto cp =
              track.Project(st.x[plant::kX], st.x[plant::kY], st.x[plant::kPsi], road_hint);
          road_hint = cp.s;
          env = road.UnderWheels(cp, car.contact_x(), car.contact_y());
        }
        env.mu[2] *= ev.rear_grip;
        env.mu[3] *= ev.rear_grip;
        env.wind_x = ev.wind_x;
        env.wind_y = ev.wind_y;
        car.Step(act, env, &st);
      }
    }
  }
  return m;
}

}  // namespace scw::tuning
