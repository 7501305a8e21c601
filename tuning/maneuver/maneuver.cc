#include "tuning/maneuver/maneuver.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <type_traits>

#include "controller/motion/longitudinal.h"
#include "controller/stability/stability_controller.h"
#include "params/io/csv.h"
#include "params/io/write.h"
#include "plant/vehicle/quasi_steady.h"
#include "plant/vehicle/vehicle.h"
#include "tuning/maneuver/maneuver_metrics.h"
#include "tuning/maneuver/programs.h"
#include "tuning/sim/control_loop.h"
#include "tuning/sim/plant_choice.h"
#include "tuning/sim/run_observers.h"
#include "tuning/sim/trace_schema.h"

namespace scw::tuning {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDeg = M_PI / 180.0;
constexpr double k80kmh = 80.0 / 3.6;
constexpr double k100kmh = 100.0 / 3.6;
/// Front share of the brake force of the brake programs (the longitudinal controller's default).
constexpr double kBrakeFrontShare = 0.58;
/// Wheel lock and spin are judged only above this speed [m/s]: every wheel stops at the end of a
/// stop, and slip means little at walking pace.
constexpr double kSlipJudgedAbove = 5.0;

/// What the robot commands at one tick.
struct Command {
  double steer = 0.0;        ///< [rad] road-wheel angle request
  double throttle = 0.0;     ///< [0..1] when not holding speed
  PerWheel<double> brake{};  ///< [bar]
  PerWheel<double> mu{1.0, 1.0, 1.0, 1.0};
  bool hold_speed = false;     ///< throttle from the speed hold at `v_target`
  double v_target = 0.0;       ///< [m/s]
  bool hold_heading = false;   ///< steer − heading_gain · (ψ − ψ_start)
  bool keep_throttle = false;  ///< hold the throttle of the previous tick (ISO 7401)
};

/// The robot's program: the command at time t [s] (t < 0 while settling).
using Program = std::function<Command(double t)>;
/// Ends a run early once true (checked after each tick).
using StopRule = std::function<bool(const ManeuverSignals&)>;

double Throttle(double integral, double e) { return std::clamp(integral + 0.2 * e, 0.0, 1.0); }

/// The car, the controller and everything shared by the runs of one maneuver.
class Rig {
 public:
  Rig(const ResolvedScenario& sc, const params::StabilityParams& stability,
      const ManeuverOptions& o)
      : sc_(sc),
        m_(sc.spec.maneuver),
        options_(o),
        stab_(PrepareStability(sc, stability)),
        ctl_(stab_, Options(sc)),
        // The simulated car: the scenario's plant section applied, on its plant model.
        plant_(sc.spec.plant.model, sc.plant_vehicle),
        lon_(sc.spec.motion.longitudinal, sc.longitudinal_model, stab_.tS),
        qs_(sc.vehicle),
        ts_(stab_.tS),
        ratio_(std::max(1L, std::lround(ts_ / plant_.time_step()))),
        log_every_(std::max(1L, std::lround(1.0 / (sc.spec.log_rate * ts_)))),
        brake_gain_{
            sc.plant_vehicle.brakes.torque_gain_front, sc.plant_vehicle.brakes.torque_gain_front,
            sc.plant_vehicle.brakes.torque_gain_rear, sc.plant_vehicle.brakes.torque_gain_rear} {}

  const params::ManeuverParams& m() const { return m_; }
  const params::VehicleParams& vehicle() const { return sc_.vehicle; }
  const plant::QuasiSteadyModel& qs() const { return qs_; }
  double direction() const { return m_.direction == "right" ? -1.0 : 1.0; }
  double handwheel(double road_wheel) const { return road_wheel * m_.steering_ratio; }

  /// Drives one run: from a straight start at `speed`, `settle` seconds before t = 0, to
  /// `duration` after it (or until `stop`).
  ManeuverRun Drive(std::string label, double level, double speed, double settle, double duration,
                    const Program& program, const StopRule& stop = {}) {
    ManeuverRun run;
    run.label = std::move(label);
    run.level = level;
    RunMetrics& metrics = run.metrics;
    ManeuverSignals& sig = run.signals;
    plant::SensorNoiseState noise(static_cast<std::uint64_t>(sc_.spec.seed));
    controller::StabilityController::State cs;
    const int index = run_index_++;
    const long n_settle = std::lround(settle / ts_);

    // The robot as a driver of the shared control loop (tuning/sim/control_loop.h).
    struct Driver {
      Rig& rig;
      const Program& program;
      const StopRule& stop;
      double duration;
      long n_settle;
      int index;
      RunMetrics& metrics;
      ManeuverSignals& sig;
      MetricsAccumulator acc;
      TraceRecorder trace;
      double integral = -1.0;  // speed hold's integrator, initialised at the first tick
      double distance = 0.0;
      double last_throttle = 0.0;
      // Of the tick in progress.
      double t = 0.0, speed_now = 0.0, steer = 0.0;
      Command c{};
      bool uniform = true;

      bool Begin(long tick) {
        t = static_cast<double>(tick - n_settle) * rig.ts_;
        return !(t > duration + 1e-9);
      }
      static bool Finite(const plant::Measurement& meas) {
        return std::isfinite(meas.v_x) && std::isfinite(meas.v_y) && std::isfinite(meas.yaw_rate) &&
               std::isfinite(meas.psi);
      }
      void NonFinite() { metrics.status = RunStatus::kNonFinite; }
      bool Input(long tick, const plant::Measurement& meas, controller::StabilityInput* in) {
        speed_now = std::hypot(meas.v_x, meas.v_y);
        c = program(t);
        double throttle = c.keep_throttle ? last_throttle : c.throttle;
        if (c.hold_speed) {
          if (integral < 0.0) integral = rig.FeedForwardThrottle(meas, c.v_target);
          const double e = c.v_target - speed_now;
          integral = std::clamp(integral + 0.5 * e * rig.ts_, 0.0, 1.0);
          throttle = Throttle(integral, e);
        } else {
          integral = -1.0;
        }
        last_throttle = throttle;
        steer = c.steer;
        if (c.hold_heading) steer -= rig.m_.heading_gain * meas.psi;
        const double lock = rig.sc_.vehicle.steering.max_angle;
        steer = std::clamp(steer, -lock, lock);
        const bool braking = c.brake[0] + c.brake[1] + c.brake[2] + c.brake[3] > 0.0;
        in->t = static_cast<double>(tick) * rig.ts_;
        in->v_x = meas.v_x;
        in->v_y = meas.v_y;
        in->yaw_rate = meas.yaw_rate;
        in->a_x = meas.a_x;
        in->a_y = meas.a_y;
        in->steering_measured = meas.steering_angle;
        in->steering_request = steer;
        in->brake_request_bar = c.brake;
        in->throttle_request = throttle;
        in->gear_request = meas.gear_request;
        in->gear = meas.gear;
        in->engine_speed = meas.engine_speed;
        in->wheel_speed = meas.wheel_speed;
        in->brake_measured_bar = meas.brake_pressure;
        in->long_fx = braking ? BrakeForceOf(c.brake, rig.sc_.vehicle)
                              : rig.lon_.DriveForce(meas.engine_speed, meas.gear, throttle);
        return true;
      }
      bool Output(long tick, const plant::Measurement& meas, const controller::StabilityInput& in,
                  const controller::StabilityOutput& out, const plant::StepOutputs& plant_out) {
        const double beta = std::atan2(meas.v_y, std::max(std::abs(meas.v_x), 1.0));
        controller::motion::MotionOutput mo;
        mo.steering_request = steer;
        mo.lateral_error = meas.y;
        mo.heading_error = meas.psi;
        mo.v_target = c.hold_speed ? c.v_target : kNaN;
        const TickRecord record{t,  index, distance, meas.y, beta, speed_now,
                                0u, meas,  mo,       in,     out,  plant_out};
        acc.Add(record, &metrics);
        trace.Record(tick, record);
        sig.t.push_back(t);
        sig.steer.push_back(steer);
        sig.yaw_rate.push_back(meas.yaw_rate);
        sig.a_x.push_back(meas.a_x);
        sig.a_y.push_back(meas.a_y);
        sig.beta.push_back(beta);
        sig.speed.push_back(speed_now);
        sig.heading.push_back(meas.psi);
        sig.x.push_back(meas.x);
        sig.y.push_back(meas.y);
        // Signed: the rear wheel with the larger |slip| (a braking slip reads negative).
        const double rl = plant_out.kappa[2], rr = plant_out.kappa[3];
        sig.max_slip_rear.push_back(100.0 * (std::abs(rl) >= std::abs(rr) ? rl : rr));
        if (speed_now > kSlipJudgedAbove) rig.CountLockSpin(plant_out);
        if (stop && t >= 0.0 && stop(sig)) return false;
        uniform = c.mu[0] == 1.0 && c.mu[1] == 1.0 && c.mu[2] == 1.0 && c.mu[3] == 1.0;
        return true;
      }
      // The road under each wheel (split mu, mu jump) as the plant's environment.
      bool Environment(const plant::State&, plant::Environment* env) const {
        if (uniform) return false;
        env->mu = c.mu;
        return true;
      }
      void End(long) { distance += speed_now * rig.ts_; }
    };
    Driver driver{*this,
                  program,
                  stop,
                  duration,
                  n_settle,
                  index,
                  metrics,
                  sig,
                  MetricsAccumulator(ts_, options_.sideslip_allowed_deg, brake_gain_),
                  TraceRecorder(options_.trace, log_every_)};
    plant_.Visit([&](const auto& car) {
      using Car = std::remove_cvref_t<decltype(car)>;
      plant::StateOf<Car> st = car.MakeState({0.0, 0.0, 0.0, speed});
      const ControlLoop<Car> loop{
          car, ctl_, ratio_, &st, sc_.plant_vehicle.sensors.noise ? &noise : nullptr, &cs};
      loop.Run(driver);
    });
    ToStartFrame(&sig);
    return run;
  }

  /// One tick's wheel slips (the plant's) into the lock/spin timers.
  void CountLockSpin(const plant::StepOutputs& plant_out) {
    for (std::size_t i = 0; i < 4; ++i) {
      const double slip = 100.0 * plant_out.kappa[i];
      lock_[i] = slip < -sc_.spec.abort.lock_slip_pct ? lock_[i] + ts_ : 0.0;
      spin_[i] = slip > sc_.spec.abort.spin_slip_pct ? spin_[i] + ts_ : 0.0;
      max_lock_ = std::max(max_lock_, lock_[i]);
      max_spin_ = std::max(max_spin_, spin_[i]);
    }
  }

  /// The longest time a wheel stayed locked / spinning (above kSlipJudgedAbove) in the runs since
  /// the last call, then reset.
  std::pair<double, double> TakeLockSpin() {
    const std::pair<double, double> r{max_lock_, max_spin_};
    max_lock_ = max_spin_ = 0.0;
    lock_ = spin_ = {};
    return r;
  }

  /// Road-wheel angle of the steady circle at `speed` and lateral acceleration `a_y` (signed).
  double CircleSteer(double speed, double a_y, const char* key) const {
    const plant::QuasiSteadyState s = qs_.Solve(speed, 0.0, a_y);
    if (!s.feasible)
      throw ConfigError("scenario " + sc_.spec.name, std::string("maneuver.") + key,
                        "the car cannot hold " + params::FormatDouble(std::abs(a_y)) +
                            " m/s^2 at " + params::FormatDouble(speed) +
                            " m/s (scw vehicle balance lists its limits)");
    return s.steer;
  }

 private:
  static controller::StabilityOptions Options(const ResolvedScenario& sc) {
    controller::StabilityOptions o;
    o.release_compat = sc.spec.subsystems.release_compat;
    return o;
  }

  /// The throttle that holds `v` against the road load on a straight (engine map of the
  /// longitudinal model), the speed hold's starting integrator.
  double FeedForwardThrottle(const plant::Measurement& meas, double v) const {
    const double load = qs_.RoadLoad(v);
    double lo = 0.0, hi = 1.0;
    for (int k = 0; k < 30; ++k) {
      const double mid = 0.5 * (lo + hi);
      (lon_.DriveForce(meas.engine_speed, meas.gear, mid) < load ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }

  /// Positions and heading relative to the car's pose at t = 0.
  static void ToStartFrame(ManeuverSignals* s) {
    if (s->t.empty()) return;
    std::size_t k0 = 0;
    while (k0 + 1 < s->t.size() && s->t[k0] < 0.0) ++k0;
    const double x0 = s->x[k0], y0 = s->y[k0], psi0 = s->heading[k0];
    const double c = std::cos(psi0), sn = std::sin(psi0);
    for (std::size_t k = 0; k < s->t.size(); ++k) {
      const double dx = s->x[k] - x0, dy = s->y[k] - y0;
      s->x[k] = c * dx + sn * dy;
      s->y[k] = -sn * dx + c * dy;
      s->heading[k] -= psi0;
    }
  }

  const ResolvedScenario& sc_;
  const params::ManeuverParams& m_;
  ManeuverOptions options_;
  params::StabilityParams stab_;
  controller::StabilityController ctl_;
  PlantChoice plant_;
  controller::motion::LongitudinalController lon_;
  plant::QuasiSteadyModel qs_;
  double ts_;
  long ratio_, log_every_;
  PerWheel<double> brake_gain_;
  int run_index_ = 0;
  PerWheel<double> lock_{}, spin_{};
  double max_lock_ = 0.0, max_spin_ = 0.0;
};

void Value(ManeuverRun* r, std::string key, double value, std::string doc) {
  r->values.push_back({std::move(key), value, std::move(doc)});
}
void Setup(ManeuverResult* r, std::string key, double value, std::string doc) {
  r->setup.push_back({std::move(key), value, std::move(doc)});
}
void Criterion(ManeuverRun* r, std::string key, double value, double limit, bool upper,
               std::string source) {
  r->criteria.push_back({std::move(key), value, limit, upper, std::move(source)});
}

/// Index of the first sample at or after t.
std::size_t At(const ManeuverSignals& s, double t) {
  std::size_t k = 0;
  while (k + 1 < s.t.size() && s.t[k] < t) ++k;
  return k;
}

double MaxAbsFrom(const std::vector<double>& t, const std::vector<double>& y, double from) {
  double m = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k)
    if (t[k] >= from) m = std::max(m, std::abs(y[k]));
  return m;
}

std::string Fixed(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

/// The criteria every run gets from the scenario's abort limits (the workspace's, not a
/// standard's): no spin (|β| below abort.max_sideslip_deg), no wheel locked or spinning longer
/// than abort.slip_time above 5 m/s.
void SafetyCriteria(const ResolvedScenario& sc, ManeuverRun* r, std::pair<double, double> lock_spin,
                    bool lock, bool spin) {
  const auto& ab = sc.spec.abort;
  Criterion(r, "max_abs_sideslip_deg", r->metrics.max_abs_sideslip / kDeg, ab.max_sideslip_deg,
            true, "workspace (abort.max_sideslip_deg)");
  if (lock)
    Criterion(r, "wheel_lock_time_s", lock_spin.first, ab.slip_time, true,
              "workspace (abort.slip_time at abort.lock_slip_pct)");
  if (spin)
    Criterion(r, "wheel_spin_time_s", lock_spin.second, ab.slip_time, true,
              "workspace (abort.slip_time at abort.spin_slip_pct)");
}

// ---------------------------------------------------------------------------------------------
// The maneuvers.

void SineWithDwellTest(Rig& rig, const ResolvedScenario& sc, ManeuverResult* res) {
  const auto& m = rig.m();
  const double v = m.speed > 0.0 ? m.speed : k80kmh;
  const double dir = rig.direction();
  res->standard = "FMVSS 126 / UN R140 sine with dwell";
  res->series = "amplitude factor [A]";
  // Slowly increasing steer at 13.5 deg/s at the handwheel, speed held, until 0.45 g.
  const double rate = 13.5 * kDeg / m.steering_ratio;
  const ManeuverRun sis = rig.Drive(
      "slowly increasing steer", 0.0, v, 1.0, 0.6 / rate,
      [&](double t) {
        Command c;
        c.steer = dir * RampSteer(t, rate);
        c.hold_speed = true;
        c.v_target = v;
        return c;
      },
      [&](const ManeuverSignals& s) { return dir * s.a_y.back() > 0.45 * kStandardGravity; });
  (void)rig.TakeLockSpin();
  std::vector<double> ay, steer;
  for (std::size_t k = 0; k < sis.signals.t.size(); ++k)
    if (sis.signals.t[k] >= 0.0) {
      ay.push_back(dir * sis.signals.a_y[k]);
      steer.push_back(dir * sis.signals.steer[k]);
    }
  const LineFit fit = FitLine(ay, steer, 0.1 * kStandardGravity, 0.375 * kStandardGravity);
  const double a = fit.intercept + fit.slope * 0.3 * kStandardGravity;
  if (!(a > 0.0) || fit.samples < 2)
    throw ConfigError("scenario " + sc.spec.name, "maneuver.speed",
                      "the slowly increasing steer did not reach 0.375 g at " +
                          params::FormatDouble(v) + " m/s: no angle A");
  Setup(res, "speed_mps", v, "test speed (coasting from the beginning of steer)");
  Setup(res, "steering_ratio", m.steering_ratio, "handwheel per road-wheel angle");
  Setup(res, "A_deg", a / kDeg, "road-wheel angle for 0.3 g in the slowly increasing steer");
  Setup(res, "A_handwheel_deg", rig.handwheel(a) / kDeg, "A at the handwheel");
  Setup(res, "steering_lock_deg", rig.vehicle().steering.max_angle / kDeg,
        "the car's road-wheel steering limit (larger amplitudes are clipped)");
  Setup(res, "frequency_Hz", m.frequency, "sine frequency");
  Setup(res, "dwell_s", m.dwell, "dwell at the second peak");
  std::vector<double> factors =
      SineWithDwellFactors(m.amplitude_factors, rig.handwheel(a) / kDeg, m.extend_to_270deg);
  // Amplitudes beyond the steering lock drive the same clipped program: the series ends at the
  // first amplitude that reaches the lock.
  const double lock = rig.vehicle().steering.max_angle;
  for (std::size_t i = 0; i < factors.size(); ++i)
    if (factors[i] * a >= lock) {
      factors.resize(i + 1);
      break;
    }
  for (double f : factors) {
    const SineWithDwell swd{dir * f * a, m.frequency, m.dwell};
    ManeuverRun r = rig.Drive(Fixed(f, 2) + " A", f, v, 0.5, swd.Duration() + 1.8, [&](double t) {
      Command c;
      c.steer = swd.At(t);
      c.hold_speed = t < 0.0;  // coast from the beginning of steer
      c.v_target = v;
      return c;
    });
    const auto lock_spin = rig.TakeLockSpin();
    const ManeuverSignals& s = r.signals;
    const SineWithDwellMetrics sm =
        ComputeSineWithDwell(s.t, s.steer, s.yaw_rate, s.a_y, 5.0 * kDeg / m.steering_ratio,
                             swd.DwellStart() + swd.dwell, swd.Reversal(), dir);
    Value(&r, "amplitude_deg", f * a / kDeg, "road-wheel amplitude");
    Value(&r, "amplitude_handwheel_deg", rig.handwheel(f * a) / kDeg, "at the handwheel");
    Value(&r, "t_bos_s", sm.t_bos, "beginning of steer (5 deg at the handwheel)");
    Value(&r, "t_cos_s", sm.t_cos, "completion of steer");
    Value(&r, "peak_yaw_rate_degps", sm.peak_yaw_rate / kDeg,
          "first yaw-rate peak after the steering reversal");
    Value(&r, "ratio_1_00_pct", sm.ratio_1_00, "yaw rate 1.00 s after COS / peak");
    Value(&r, "ratio_1_75_pct", sm.ratio_1_75, "yaw rate 1.75 s after COS / peak");
    Value(&r, "lateral_displacement_m", sm.lateral_displacement,
          "at BOS + 1.07 s, towards the first steer");
    Value(&r, "speed_at_bos_mps", Interpolate(s.t, s.speed, sm.t_bos), "speed at BOS");
    Criterion(&r, "ratio_1_00_pct", sm.ratio_1_00, 35.0, true, "FMVSS 126 S5.2.1");
    Criterion(&r, "ratio_1_75_pct", sm.ratio_1_75, 20.0, true, "FMVSS 126 S5.2.2");
    if (f >= 5.0 - 1e-9)
      Criterion(&r, "lateral_displacement_m", sm.lateral_displacement, 1.83, false,
                "FMVSS 126 S5.2.3");
    (void)lock_spin;
    res->runs.push_back(std::move(r));
  }
}

void StepSteerTest(Rig& rig, ManeuverResult* res) {
  const auto& m = rig.m();
  const double v = m.speed > 0.0 ? m.speed : k80kmh;
  const double dir = rig.direction();
  const double delta = rig.CircleSteer(v, dir * m.lateral_acceleration, "lateral_acceleration");
  res->standard = "ISO 7401 step steer";
  Setup(res, "speed_mps", v, "test speed (throttle held from the step on)");
  Setup(res, "steer_deg", delta / kDeg,
        "road-wheel step: the steady-state angle for the target lateral acceleration");
  Setup(res, "steer_handwheel_deg", rig.handwheel(delta) / kDeg, "at the handwheel");
  Setup(res, "rise_time_s", m.steer_rise_time, "steering ramp time");
  ManeuverRun r = rig.Drive(Fixed(m.lateral_acceleration, 1) + " m/s^2", m.lateral_acceleration, v,
                            1.5, 4.0, [&](double t) {
                              Command c;
                              c.steer = StepSteer(t, delta, m.steer_rise_time);
                              c.hold_speed = t < 0.0;
                              c.v_target = v;
                              c.keep_throttle = t >= 0.0;
                              return c;
                            });
  (void)rig.TakeLockSpin();
  const ManeuverSignals& s = r.signals;
  // The response from the tick before the step on.
  const std::size_t k0 = At(s, 0.0) > 0 ? At(s, 0.0) - 1 : 0;
  auto tail = [&](const std::vector<double>& y) {
    return std::vector<double>(y.begin() + static_cast<long>(k0), y.end());
  };
  const auto t = tail(s.t), steer = tail(s.steer);
  const StepResponse yr = ComputeStepResponse(t, steer, tail(s.yaw_rate), 1.0);
  const StepResponse ar = ComputeStepResponse(t, steer, tail(s.a_y), 1.0);
  Value(&r, "yaw_rate_response_time_s", yr.response_time, "50 % steer to 90 % of steady yaw rate");
  Value(&r, "yaw_rate_peak_time_s", yr.peak_time, "50 % steer to the yaw-rate peak");
  Value(&r, "yaw_rate_overshoot_pct", yr.overshoot_pct, "peak over steady yaw rate");
  Value(&r, "yaw_rate_gain_1ps", yr.gain, "steady yaw rate / road-wheel angle");
  Value(&r, "lateral_acceleration_response_time_s", ar.response_time,
        "50 % steer to 90 % of steady a_y");
  Value(&r, "lateral_acceleration_overshoot_pct", ar.overshoot_pct, "peak over steady a_y");
  Value(&r, "lateral_acceleration_gain_mps2_per_rad", ar.gain, "steady a_y / road-wheel angle");
  Value(&r, "steady_yaw_rate_degps", yr.steady_state / kDeg, "mean over the last second");
  Value(&r, "steady_lateral_acceleration_mps2", ar.steady_state, "mean over the last second");
  res->runs.push_back(std::move(r));
}

void SteadyStateCircularTest(Rig& rig, ManeuverResult* res) {
  const auto& m = rig.m();
  const double v = m.speed > 0.0 ? m.speed : k80kmh;
  const double dir = rig.direction();
  res->standard = "ISO 4138 steady-state circular (constant speed, slowly increasing steer)";
  // Quasi-steady through the fit range: 4 s from straight to the angle the quasi-steady model
  // needs for 2.5 m/s^2; then 2 deg/s (road wheel) to the limit.
  const double fast = 2.0 * kDeg;
  const double slow_until = std::abs(rig.CircleSteer(v, 2.5, "speed"));
  const double t_slow = 4.0;
  const double rate = slow_until / t_slow;
  const double lock = rig.vehicle().steering.max_angle;
  ManeuverRun r = rig.Drive(
      "constant speed", 0.0, v, 1.0, t_slow + (lock - slow_until) / fast,
      [&](double t) {
        Command c;
        c.steer = dir * (t < t_slow ? RampSteer(t, rate) : slow_until + fast * (t - t_slow));
        c.hold_speed = true;
        c.v_target = v;
        return c;
      },
      [&](const ManeuverSignals& s) {
        // Stop one second after the lateral acceleration stopped growing, or past 3 m/s^2 once the
        // speed can no longer be held.
        const std::size_t n = s.t.size();
        const std::size_t back = static_cast<std::size_t>(std::lround(1.0 / (s.t[1] - s.t[0])));
        return n > back + 1 && dir * s.a_y[n - 1] <= dir * s.a_y[n - 1 - back] &&
               dir * s.a_y[n - 1] > 3.0;
      });
  (void)rig.TakeLockSpin();
  const ManeuverSignals& s = r.signals;
  std::vector<double> ay, steer, speed;
  for (std::size_t k = 0; k < s.t.size(); ++k)
    if (s.t[k] >= 0.0) {
      ay.push_back(dir * s.a_y[k]);
      steer.push_back(dir * s.steer[k]);
      speed.push_back(s.speed[k]);
    }
  const LineFit fit = FitLine(ay, steer, 0.5, 1.5);
  const LineFit vfit = FitLine(ay, speed, 0.5, 1.5);
  const double v_mean = vfit.intercept + vfit.slope * 1.0;
  const double l = rig.vehicle().chassis.wheelbase;
  const double gradient = fit.slope - l / (v_mean * v_mean);
  Setup(res, "speed_mps", v, "test speed (held by throttle)");
  Setup(res, "steer_rate_degps", rate / kDeg, "road-wheel steer rate through the fit range");
  Setup(res, "fast_from_deg", slow_until / kDeg, "then 2 deg/s from this road-wheel angle on");
  Setup(res, "fit_range_mps2", 1.0, "a_y 0.5 to 1.5 m/s^2 (as scw vehicle balance)");
  Value(&r, "understeer_gradient_mrad_per_mps2", 1e3 * gradient,
        "d(steer)/d(a_y) - l/v^2 in 0.5..1.5 m/s^2 (> 0 understeers)");
  Value(&r, "balance_gradient_mrad_per_mps2", 1e3 * rig.qs().UndersteerGradient(v_mean),
        "scw vehicle balance at the same speed");
  Value(&r, "max_lateral_acceleration_mps2", MaxAbsFrom(s.t, s.a_y, 0.0), "largest |a_y|");
  Value(&r, "steer_at_max_deg", MaxAbsFrom(s.t, s.steer, 0.0) / kDeg,
        "road-wheel angle at the end");
  res->runs.push_back(std::move(r));
}

/// The in-turn tests: settle on the circle at `lateral_acceleration`, then the program at t = 0
/// with the steering held. `what` fills the command after t = 0.
ManeuverRun InTurnRun(Rig& rig, const std::string& label, double level, double v, double delta,
                      double duration, const std::function<void(double, Command*)>& what) {
  return rig.Drive(
      label, level, v, 3.0, duration,
      [&](double t) {
        Command c;
        c.steer = delta;
        c.hold_speed = t < 0.0;
        c.v_target = v;
        if (t >= 0.0) what(t, &c);
        return c;
      },
      [](const ManeuverSignals& s) { return s.speed.back() < 3.0; });
}

void InTurnValues(const ResolvedScenario& sc, ManeuverRun* r, std::pair<double, double> lock_spin) {
  const ManeuverSignals& s = r->signals;
  const std::size_t k0 = At(s, 0.0), k1 = At(s, 1.0);
  const double r0 = s.yaw_rate[k0], r1 = s.yaw_rate[k1];
  Value(r, "yaw_rate_t0_degps", r0 / kDeg, "yaw rate at t0 (the change of input)");
  Value(r, "yaw_rate_ratio_1s", r1 / r0, "yaw rate at t0 + 1 s / at t0");
  Value(r, "yaw_rate_vs_circle_1s", r1 / (r0 * s.speed[k1] / s.speed[k0]),
        "yaw rate at t0 + 1 s / the initial circle's at that speed (> 1 turns in)");
  Value(r, "sideslip_change_1s_deg", (s.beta[k1] - s.beta[k0]) / kDeg, "beta(t0 + 1 s) - beta(t0)");
  Value(r, "heading_change_1s_deg", (s.heading[k1] - s.heading[k0]) / kDeg,
        "heading turned in the first second");
  Value(r, "mean_ax_1s_mps2", (s.speed[k1] - s.speed[k0]) / (s.t[k1] - s.t[k0]),
        "mean acceleration over the first second");
  Value(r, "max_abs_sideslip_after_t0_deg", MaxAbsFrom(s.t, s.beta, 0.0) / kDeg,
        "largest |beta| after t0");
  Value(r, "max_slip_rear_after_t0_pct", MaxAbsFrom(s.t, s.max_slip_rear, 0.0),
        "largest rear |slip| after t0");
  SafetyCriteria(sc, r, lock_spin, true, true);
}

void BrakingInTurnTest(Rig& rig, const ResolvedScenario& sc, ManeuverResult* res) {
  const auto& m = rig.m();
  const double v = m.speed > 0.0 ? m.speed : k80kmh;
  const double delta =
      rig.CircleSteer(v, rig.direction() * m.lateral_acceleration, "lateral_acceleration");
  res->standard = "ISO 7975 braking in a turn";
  res->series = "deceleration [m/s^2]";
  Setup(res, "speed_mps", v, "speed on the initial circle");
  Setup(res, "lateral_acceleration_mps2", m.lateral_acceleration, "on the initial circle");
  Setup(res, "radius_m", v * v / m.lateral_acceleration, "of the initial circle");
  Setup(res, "steer_deg", delta / kDeg, "road-wheel angle, held");
  Setup(res, "brake_front_share", kBrakeFrontShare, "of the brake force");
  for (double d : m.decelerations) {
    const PerWheel<double> p = BrakePressuresFor(d, kBrakeFrontShare, rig.vehicle());
    ManeuverRun r =
        InTurnRun(rig, Fixed(d, 1) + " m/s^2", d, v, delta, 3.0, [&](double t, Command* c) {
          const double u = std::min(1.0, t / 0.1);  // 0.1 s pedal ramp
          for (std::size_t i = 0; i < 4; ++i) c->brake[i] = u * p[i];
        });
    Value(&r, "pressure_front_bar", p[0], "requested front pressure");
    Value(&r, "pressure_rear_bar", p[2], "requested rear pressure");
    InTurnValues(sc, &r, rig.TakeLockSpin());
    res->runs.push_back(std::move(r));
  }
}

void PowerInTurnTest(Rig& rig, const ResolvedScenario& sc, ManeuverResult* res, bool on) {
  const auto& m = rig.m();
  const double v = m.speed > 0.0 ? m.speed : k80kmh;
  const double delta =
      rig.CircleSteer(v, rig.direction() * m.lateral_acceleration, "lateral_acceleration");
  res->standard = on ? "ISO 9816 in-turn power change (power on: full throttle)"
                     : "ISO 9816 power-off in a turn";
  Setup(res, "speed_mps", v, "speed on the initial circle");
  Setup(res, "lateral_acceleration_mps2", m.lateral_acceleration, "on the initial circle");
  Setup(res, "radius_m", v * v / m.lateral_acceleration, "of the initial circle");
  Setup(res, "steer_deg", delta / kDeg, "road-wheel angle, held");
  ManeuverRun r = InTurnRun(rig, on ? "full throttle" : "throttle off", m.lateral_acceleration, v,
                            delta, 3.0, [&](double, Command* c) { c->throttle = on ? 1.0 : 0.0; });
  InTurnValues(sc, &r, rig.TakeLockSpin());
  res->runs.push_back(std::move(r));
}

/// Split-mu and mu-jump tests: the straight runs with the heading robot.
void StraightValues(Rig& rig, ManeuverRun* r) {
  const ManeuverSignals& s = r->signals;
  double max_heading = 0.0, max_lateral = 0.0, max_correction = 0.0;
  for (std::size_t k = 0; k < s.t.size(); ++k) {
    if (s.t[k] < 0.0) continue;
    max_heading = std::max(max_heading, std::abs(s.heading[k]));
    max_lateral = std::max(max_lateral, std::abs(s.y[k]));
    max_correction = std::max(max_correction, std::abs(s.steer[k]));
  }
  Value(r, "max_yaw_deviation_deg", max_heading / kDeg, "largest |heading change|");
  Value(r, "max_lateral_deviation_m", max_lateral, "largest |lateral offset| from the start line");
  Value(r, "max_steering_correction_deg", max_correction / kDeg,
        "largest road-wheel angle the heading robot needed");
  Value(r, "max_steering_correction_handwheel_deg", rig.handwheel(max_correction) / kDeg,
        "the same at the handwheel");
}

void SplitMuBrakingTest(Rig& rig, const ResolvedScenario& sc, ManeuverResult* res) {
  const auto& m = rig.m();
  const double v = m.speed > 0.0 ? m.speed : k100kmh;
  res->standard = "ISO 14512 straight-line braking on split mu";
  const PerWheel<double> full =
      BrakePressuresFor(2.0 * kStandardGravity, kBrakeFrontShare, rig.vehicle());
  const PerWheel<double> split{m.mu_low, m.mu_high, m.mu_low, m.mu_high};
  Setup(res, "speed_mps", v, "speed at the start of braking");
  Setup(res, "mu_left", m.mu_low, "friction factor under the left wheels");
  Setup(res, "mu_right", m.mu_high, "friction factor under the right wheels");
  Setup(res, "pressure_front_bar", full[0], "full braking: the pressures for 2 g (capped)");
  Setup(res, "pressure_rear_bar", full[2], "");
  Setup(res, "heading_gain", m.heading_gain, "steering robot, rad per rad of heading");
  ManeuverRun r = rig.Drive(
      "split mu", m.mu_low, v, 1.0, 20.0,
      [&](double t) {
        Command c;
        c.mu = split;
        c.hold_speed = t < 0.0;
        c.v_target = v;
        c.hold_heading = true;
        if (t >= 0.0) {
          const double u = std::min(1.0, t / 0.1);
          for (std::size_t i = 0; i < 4; ++i) c.brake[i] = u * full[i];
        }
        return c;
      },
      [](const ManeuverSignals& s) { return s.speed.back() < 0.5; });
  const ManeuverSignals& s = r.signals;
  const std::size_t k0 = At(s, 0.0);
  const std::size_t kn = s.t.size() - 1;
  const double dist = std::hypot(s.x[kn] - s.x[k0], s.y[kn] - s.y[k0]);
  Value(&r, "stopping_distance_m", dist, "from the start of braking to 0.5 m/s");
  Value(&r, "stopping_time_s", s.t[kn] - s.t[k0], "");
  Value(&r, "mean_deceleration_mps2", (s.speed[k0] - s.speed[kn]) / (s.t[kn] - s.t[k0]), "");
  StraightValues(rig, &r);
  SafetyCriteria(sc, &r, rig.TakeLockSpin(), true, false);
  res->runs.push_back(std::move(r));
}

void AccelerationTest(Rig& rig, const ResolvedScenario& sc, ManeuverResult* res, bool jump) {
  const auto& m = rig.m();
  const double v = m.speed > 0.0 ? m.speed : 10.0;
  const double t_jump = 1.0;
  res->standard =
      jump ? "mu jump under full throttle (high to low mu)" : "full throttle on split mu";
  const PerWheel<double> split{m.mu_low, m.mu_high, m.mu_low, m.mu_high};
  const PerWheel<double> high{m.mu_high, m.mu_high, m.mu_high, m.mu_high};
  const PerWheel<double> low{m.mu_low, m.mu_low, m.mu_low, m.mu_low};
  Setup(res, "speed_mps", v, "speed at the start of full throttle");
  Setup(res, "mu_low", m.mu_low, jump ? "after the jump" : "under the left wheels");
  Setup(res, "mu_high", m.mu_high, jump ? "before the jump" : "under the right wheels");
  if (jump) Setup(res, "t_jump_s", t_jump, "time of the jump after full throttle");
  Setup(res, "heading_gain", m.heading_gain, "steering robot, rad per rad of heading");
  ManeuverRun r = rig.Drive(jump ? "mu jump" : "split mu", m.mu_low, v, 1.0, 4.0, [&](double t) {
    Command c;
    c.mu = jump ? (t < t_jump ? high : low) : split;
    c.hold_speed = t < 0.0;
    c.v_target = v;
    c.hold_heading = true;
    c.throttle = 1.0;
    return c;
  });
  const ManeuverSignals& s = r.signals;
  const std::size_t k0 = At(s, 0.0), kn = s.t.size() - 1;
  Value(&r, "mean_ax_mps2", (s.speed[kn] - s.speed[k0]) / (s.t[kn] - s.t[k0]),
        "mean acceleration over the run");
  Value(&r, "speed_reached_mps", s.speed[kn], "at the end");
  Value(&r, "max_slip_rear_pct", MaxAbsFrom(s.t, s.max_slip_rear, 0.0), "largest rear |slip|");
  if (jump) {
    const std::size_t kj = At(s, t_jump);
    Value(&r, "max_slip_rear_after_jump_pct", MaxAbsFrom(s.t, s.max_slip_rear, t_jump), "");
    Value(&r, "mean_ax_after_jump_mps2", (s.speed[kn] - s.speed[kj]) / (s.t[kn] - s.t[kj]), "");
  }
  Value(&r, "tc_time_s", r.metrics.tc_time, "time TC acted");
  StraightValues(rig, &r);
  SafetyCriteria(sc, &r, rig.TakeLockSpin(), false, true);
  res->runs.push_back(std::move(r));
}

}  // namespace

bool ManeuverCriterion::passed() const { return upper ? value <= limit : value >= limit; }

double ManeuverCriterion::miss() const {
  if (passed()) return 0.0;
  if (!std::isfinite(value) || limit == 0.0) return 1.0;
  return std::min(1.0, std::abs(value - limit) / std::abs(limit));
}

RunMetrics ManeuverResult::Summary() const {
  RunMetrics s;
  for (const ManeuverRun& r : runs) {
    const RunMetrics& m = r.metrics;
    if (m.aborted()) s.status = m.status;
    s.time += m.time;
    s.max_abs_sideslip = std::max(s.max_abs_sideslip, m.max_abs_sideslip);
    s.max_abs_lateral_error = std::max(s.max_abs_lateral_error, m.max_abs_lateral_error);
    s.max_abs_heading_error = std::max(s.max_abs_heading_error, m.max_abs_heading_error);
    s.max_slip_front = std::max(s.max_slip_front, m.max_slip_front);
    s.max_slip_rear = std::max(s.max_slip_rear, m.max_slip_rear);
    s.max_speed = std::max(s.max_speed, m.max_speed);
    s.sideslip_excess_integral += m.sideslip_excess_integral;
    s.esc_time += m.esc_time;
    s.cs_time += m.cs_time;
    s.abs_time += m.abs_time;
    s.tc_time += m.tc_time;
    s.esc_count += m.esc_count;
    s.cs_count += m.cs_count;
    s.abs_count += m.abs_count;
    s.tc_count += m.tc_count;
    s.esc_brake_energy += m.esc_brake_energy;
    s.abs_pressure_released += m.abs_pressure_released;
    s.tc_throttle_cut += m.tc_throttle_cut;
    s.criteria_checked += m.criteria_checked;
    s.criteria_failed += m.criteria_failed;
    s.criteria_miss += m.criteria_miss;
  }
  return s;
}

const std::vector<std::string>& ManeuverNames() {
  static const std::vector<std::string> names = {
      "sine_with_dwell",     "step_steer",       "steady_state_circular", "braking_in_turn",
      "power_off_in_turn",   "power_on_in_turn", "split_mu_braking",      "split_mu_acceleration",
      "mu_jump_acceleration"};
  return names;
}

ManeuverResult RunManeuver(const ResolvedScenario& sc, const params::StabilityParams& stability,
                           const ManeuverOptions& options) {
  Rig rig(sc, stability, options);
  ManeuverResult res;
  res.name = sc.spec.maneuver.name;
  const std::string& n = res.name;
  if (n == "sine_with_dwell") {
    SineWithDwellTest(rig, sc, &res);
  } else if (n == "step_steer") {
    StepSteerTest(rig, &res);
  } else if (n == "steady_state_circular") {
    SteadyStateCircularTest(rig, &res);
  } else if (n == "braking_in_turn") {
    BrakingInTurnTest(rig, sc, &res);
  } else if (n == "power_off_in_turn" || n == "power_on_in_turn") {
    PowerInTurnTest(rig, sc, &res, n == "power_on_in_turn");
  } else if (n == "split_mu_braking") {
    SplitMuBrakingTest(rig, sc, &res);
  } else if (n == "split_mu_acceleration" || n == "mu_jump_acceleration") {
    AccelerationTest(rig, sc, &res, n == "mu_jump_acceleration");
  } else {
    throw ConfigError("scenario " + sc.spec.name, "maneuver.name", "unknown maneuver '" + n + "'");
  }
  for (ManeuverRun& r : res.runs) {
    RunMetrics& m = r.metrics;
    m.laps_planned = 0;
    for (const ManeuverCriterion& c : r.criteria) {
      ++m.criteria_checked;
      if (!c.passed()) {
        ++m.criteria_failed;
        m.criteria_miss += c.miss();
      }
    }
    if (!r.signals.t.empty()) m.time = r.signals.t.back();
  }
  return res;
}

}  // namespace scw::tuning
