#include "tuning/sim/closed_loop.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "controller/motion/longitudinal.h"
#include "plant/track/road_surface.h"
#include "plant/vehicle/vehicle.h"
#include "tuning/sim/control_loop.h"
#include "tuning/sim/events.h"
#include "tuning/sim/motion_factory.h"
#include "tuning/sim/plant_choice.h"
#include "tuning/sim/run_observers.h"
#include "tuning/sim/trace_schema.h"

namespace scw::tuning {
namespace {

bool Finite(const plant::Measurement& m) {
  bool ok = std::isfinite(m.x) && std::isfinite(m.y) && std::isfinite(m.psi) &&
            std::isfinite(m.v_x) && std::isfinite(m.v_y) && std::isfinite(m.yaw_rate) &&
            std::isfinite(m.a_x) && std::isfinite(m.a_y);
  for (double w : m.wheel_speed) ok = ok && std::isfinite(w);
  return ok;
}

controller::motion::MotionInput MotionInputOf(double t, const plant::Measurement& meas) {
  return {t,        meas.x,        meas.y,   meas.psi, meas.v_x,
          meas.v_y, meas.yaw_rate, meas.a_x, meas.a_y, meas.steering_angle};
}

/// The request path between the motion controller and the stability controller. The
/// longitudinal controller turns the a_x request into throttle, pressures and long_fx; it is told
/// whether slip control and ESC acted on the previous tick (its feedback is left out while slip
/// control acts, and while ESC acts with motion.longitudinal.hold_during_esc). A throttle fault
/// overrides its output and a steering event offsets the steering request (tuning/sim/events.h).
/// The result, with the measurement, is what the stability controller sees.
class RequestPath {
 public:
  explicit RequestPath(const controller::motion::LongitudinalController& lon) : lon_(lon) {}

  /// The stability controller's input at time `t` [s]; `speed` [m/s] = hypot(v_x, v_y).
  controller::StabilityInput Input(double t, const plant::Measurement& meas, double speed,
                                   const controller::motion::MotionOutput& mo,
                                   const EventSchedule::Active& ev) {
    auto lo = lon_.Step(
        {mo.ax_request, meas.a_x, speed, meas.engine_speed, meas.gear, slip_active_, esc_active_},
        &state_);
    if (ev.throttle_fault) {  // the request path overridden: what the stability controller sees
      lo.throttle = ev.throttle;
      lo.brake_bar = {};
      lo.force = lon_.DriveForce(meas.engine_speed, meas.gear, ev.throttle);
    }
    controller::StabilityInput in;
    in.t = t;
    in.v_x = meas.v_x;
    in.v_y = meas.v_y;
    in.yaw_rate = meas.yaw_rate;
    in.a_x = meas.a_x;
    in.a_y = meas.a_y;
    in.steering_measured = meas.steering_angle;
    // Only with an offset: x + 0.0 is not always x (−0.0 + 0.0 = +0.0).
    in.steering_request =
        ev.steer_offset != 0.0 ? mo.steering_request + ev.steer_offset : mo.steering_request;
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
    return in;
  }

  /// What the stability controller did this tick; the longitudinal controller reads it next tick.
  void Feedback(const controller::StabilityOutput& out) {
    slip_active_ = out.slip_control_active;
    esc_active_ = out.esc_active;
  }

 private:
  const controller::motion::LongitudinalController& lon_;
  controller::motion::LongitudinalController::State state_;
  bool slip_active_ = false, esc_active_ = false;  // of the previous tick
};

/// What the plant feels at each of its steps: the road under the wheels and the events' rear grip
/// and wind, as its environment. On a uniform road with no such event the default environment is
/// exact and the cheaper step is taken (At returns false).
class RoadAndAir {
 public:
  /// contact_x/_y: the plant's tyre contact points (body frame, from the CoG).
  RoadAndAir(const PerWheel<double>& contact_x, const PerWheel<double>& contact_y,
             const plant::Track& track, const plant::RoadSurface& road)
      : contact_x_(contact_x), contact_y_(contact_y), track_(track), road_(road) {}

  /// For the control period about to be driven with the events `ev`.
  void Hold(const EventSchedule::Active& ev) noexcept {
    ev_ = ev;
    nominal_ = road_.uniform() && !(ev.rear_grip != 1.0 || ev.wind_x != 0.0 || ev.wind_y != 0.0);
  }

  /// The environment of the plant step from state `st`; false: the nominal road in still air.
  bool At(const plant::State& st, plant::Environment* env) {
    if (nominal_) return false;
    if (!road_.uniform()) {
      const auto cp = track_.Project(st.x[plant::kX], st.x[plant::kY], st.x[plant::kPsi], hint_);
      hint_ = cp.s;
      *env = road_.UnderWheels(cp, contact_x_, contact_y_);
    }
    env->mu[2] *= ev_.rear_grip;
    env->mu[3] *= ev_.rear_grip;
    env->wind_x = ev_.wind_x;
    env->wind_y = ev_.wind_y;
    return true;
  }

 private:
  const PerWheel<double>& contact_x_;
  const PerWheel<double>& contact_y_;
  const plant::Track& track_;
  const plant::RoadSurface& road_;
  EventSchedule::Active ev_;
  bool nominal_ = true;
  double hint_ = plant::Track::kNoHint;  ///< last projection of the plant step (local search)
};

}  // namespace

std::vector<std::string> TraceHeader() {
  std::vector<std::string> h;
  h.reserve(kTraceColumns.size());
  for (const TraceColumn& c : kTraceColumns) h.emplace_back(c.name);
  return h;
}

namespace {

/// The closed loop of RunClosedLoop on plant `car` (plant::Vehicle or another plant model of
/// plant/vehicle/plant_model.h).
template <class Car>
RunMetrics RunOn(const Car& car, const ResolvedScenario& sc,
                 const params::StabilityParams& stability, const RunOptions& options) {
  const params::StabilityParams stab = PrepareStability(sc, stability);
  controller::StabilityOptions sopt;
  sopt.release_compat = sc.spec.subsystems.release_compat;
  const controller::StabilityController ctl(stab, sopt);
  const auto motion = MakeMotionController(sc);
  const controller::motion::MotionController& pp = *motion;
  const controller::motion::LongitudinalController lon(sc.spec.motion.longitudinal,
                                                       sc.longitudinal_model, sc.tracking.tS);
  const auto& ab = sc.spec.abort;
  const plant::Track& track = *sc.track;
  // The road under each wheel (the track's friction and patches, the scenario's patches): the
  // plant feels it at every plant step; on a uniform surface the default environment is exact.
  const plant::RoadSurface road(track, sc.spec.friction_patches);
  // The scenario's faults, grip events and gusts (tuning/sim/events.h).
  const EventSchedule events(sc.spec.events, track);
  const double ts = stab.tS;
  const long ratio = std::max(1L, std::lround(ts / car.time_step()));
  // The motion controller may run slower than the stability controller (MPCs); its output is
  // held between its steps.
  const long motion_every = std::max(1L, std::lround(pp.sample_time() / ts));
  const long log_every = std::max(1L, std::lround(1.0 / (sc.spec.log_rate * ts)));
  const double timeout = ab.timeout_factor * sc.spec.laps * std::max(sc.ideal_lap_time, 1.0);
  const PerWheel<double> brake_gain = {
      sc.plant_vehicle.brakes.torque_gain_front, sc.plant_vehicle.brakes.torque_gain_front,
      sc.plant_vehicle.brakes.torque_gain_rear, sc.plant_vehicle.brakes.torque_gain_rear};

  // The observers of the run (tuning/sim/run_observers.h, tuning/sim/trace_schema.h).
  LapCounter laps(track.length());
  MetricsAccumulator metrics(ts, options.sideslip_allowed_deg, brake_gain);
  AbortMonitor aborts(ab, timeout, ts, track);
  TraceRecorder trace(options.trace, log_every);

  RunMetrics m;
  m.laps_planned = sc.spec.laps;
  m.distance_planned = sc.spec.laps * track.length();

  // Flying start on the reference line at the reference speed.
  const auto start = sc.path->Sample(0.0);
  plant::StateOf<Car> st = car.MakeState({start.x, start.y, start.psi, start.v});
  plant::SensorNoiseState noise(static_cast<std::uint64_t>(sc.spec.seed));
  controller::StabilityController::State ctl_state;

  // The closed loop as a driver of the shared control loop (tuning/sim/control_loop.h): lap
  // progress, events, motion control and the request path make the stability controller's input;
  // the observers see each tick.
  struct Driver {
    const ResolvedScenario& sc;
    const RunOptions& options;
    const plant::Track& track;
    const EventSchedule& events;
    const controller::motion::MotionController& pp;
    double ts;
    long motion_every;
    LapCounter& laps;
    MetricsAccumulator& metrics;
    AbortMonitor& aborts;
    TraceRecorder& trace;
    RunMetrics& m;
    RoadAndAir road_and_air;
    RequestPath requests;
    EventSchedule::State event_state = events.MakeState();
    std::unique_ptr<controller::motion::MotionState> motion_state = pp.MakeState();
    controller::motion::MotionOutput mo{};
    double s_hint = plant::Track::kNoHint;
    // Of the tick in progress.
    double t = 0.0, speed = 0.0;
    plant::TrackProjection tp{};
    EventSchedule::Active ev{};

    bool Begin(long tick) {
      t = static_cast<double>(tick) * ts;
      return true;
    }
    bool Finite(const plant::Measurement& meas) const { return tuning::Finite(meas); }
    void NonFinite() { m.status = RunStatus::kNonFinite; }
    bool Input(long tick, const plant::Measurement& meas, controller::StabilityInput* in) {
      tp = track.Project(meas.x, meas.y, meas.psi, s_hint);
      const double s_before = laps.s();
      laps.Update(t, tp.s);
      s_hint = tp.s;
      if (laps.laps() >= sc.spec.laps) {
        m.status = RunStatus::kCompleted;
        return false;
      }
      ev = EventSchedule::Active{};
      if (!events.empty()) {
        if (tick > 0) events.Update(s_before, tp.s, laps.laps() + 1, t, &event_state);
        ev = events.At(t, event_state);
      }
      // Motion control (held between its steps), the request path.
      if (tick % motion_every == 0) mo = pp.Step(MotionInputOf(t, meas), motion_state.get());
      speed = std::hypot(meas.v_x, meas.v_y);
      *in = requests.Input(t, meas, speed, mo, ev);
      if (options.on_controller_input) options.on_controller_input(*in);
      return true;
    }
    bool Output(long tick, const plant::Measurement& meas, const controller::StabilityInput& in,
                const controller::StabilityOutput& out, const plant::StepOutputs& plant_out) {
      if (options.on_controller_output) options.on_controller_output(out);
      requests.Feedback(out);
      // The observers see the tick (the trace row of an aborting tick is still written).
      const double beta = std::atan2(meas.v_y, std::max(std::abs(meas.v_x), 1.0));
      const TickRecord record{t,       laps.laps(), tp.s, tp.n, beta, speed,
                              ev.mask, meas,        mo,   in,   out,  plant_out};
      metrics.Add(record, &m);
      trace.Record(tick, record);
      if (const auto abort = aborts.Check(record)) {
        m.status = *abort;
        return false;
      }
      road_and_air.Hold(ev);
      return true;
    }
    bool Environment(const plant::State& state, plant::Environment* env) {
      return road_and_air.At(state, env);
    }
    void End(long) {}
  };
  Driver driver{sc,
                options,
                track,
                events,
                pp,
                ts,
                motion_every,
                laps,
                metrics,
                aborts,
                trace,
                m,
                RoadAndAir(car.contact_x(), car.contact_y(), track, road),
                RequestPath(lon)};
  const ControlLoop<Car> loop{
      car, ctl, ratio, &st, sc.plant_vehicle.sensors.noise ? &noise : nullptr, &ctl_state};
  loop.Run(driver);
  laps.WriteTo(&m);
  // A completed run drove exactly the planned distance (its last tick lies beyond the line).
  if (!m.aborted()) m.distance = m.distance_planned;
  return m;
}

}  // namespace

RunMetrics RunClosedLoop(const ResolvedScenario& sc, const params::StabilityParams& stability,
                         const RunOptions& options) {
  if (!sc.track)  // a maneuver (kind: maneuver) drives no track: tuning/maneuver/maneuver.h
    throw ConfigError(sc.source, "kind",
                      "'" + sc.spec.kind +
                          "' has no track to lap: run it with scw maneuver or "
                          "in a scenario set");
  // The scenario's plant model (plant.model): the loop is compiled per plant.
  const PlantChoice plant(sc.spec.plant.model, sc.plant_vehicle);
  return plant.Visit([&](const auto& car) { return RunOn(car, sc, stability, options); });
}

}  // namespace scw::tuning
