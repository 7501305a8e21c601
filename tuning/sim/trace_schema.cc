#include "tuning/sim/trace_schema.h"

#include "params/io/csv.h"

namespace scw::tuning {
namespace {

using Real = double (*)(const TickRecord&, std::size_t);
using Integer = int (*)(const TickRecord&);

constexpr TraceColumn Scalar(std::string_view name, std::string_view unit, Real value,
                             std::string_view doc) {
  return TraceColumn{name, unit, value, nullptr, 0, doc};
}
constexpr TraceColumn Count(std::string_view name, Integer value, std::string_view doc) {
  return TraceColumn{name, "-", nullptr, value, 0, doc};
}
constexpr TraceColumn Wheel(std::string_view name, std::string_view unit, Real value,
                            std::size_t wheel, std::string_view doc) {
  return TraceColumn{name, unit, value, nullptr, wheel, doc};
}

// Per-wheel values (one accessor for the four columns of a quantity).
double PressureRequested(const TickRecord& r, std::size_t i) {
  return r.input.brake_request_bar[i];
}
double PressureCommanded(const TickRecord& r, std::size_t i) { return r.output.brake_bar[i]; }
double SlipPercent(const TickRecord& r, std::size_t i) { return 100.0 * r.plant.kappa[i]; }
double SlipAngle(const TickRecord& r, std::size_t i) { return r.plant.alpha[i]; }
double VerticalLoad(const TickRecord& r, std::size_t i) { return r.plant.fz[i]; }
double LongitudinalForce(const TickRecord& r, std::size_t i) { return r.plant.fx[i]; }

}  // namespace

// The lambdas return exactly the expressions the trace always wrote (same operands, same order),
// so traces stay byte-identical.
// clang-format off
const std::array<TraceColumn, 54> kTraceColumns = {
    Scalar("t_s", "s", [](const TickRecord& r, std::size_t) { return r.t; }, "controller time of the tick"),
    Count("lap", [](const TickRecord& r) { return r.lap; }, "laps completed (0 on the first lap)"),
    Scalar("s_m", "m", [](const TickRecord& r, std::size_t) { return r.s; }, "arc length of the CoG projected on the track, in [0, L)"),
    Scalar("x_m", "m", [](const TickRecord& r, std::size_t) { return r.meas.x; }, "measured position x"),
    Scalar("y_m", "m", [](const TickRecord& r, std::size_t) { return r.meas.y; }, "measured position y"),
    Scalar("psi_rad", "rad", [](const TickRecord& r, std::size_t) { return r.meas.psi; }, "measured heading, > 0 anticlockwise"),
    Scalar("vx_mps", "m/s", [](const TickRecord& r, std::size_t) { return r.meas.v_x; }, "longitudinal speed at the CoG, body frame"),
    Scalar("vy_mps", "m/s", [](const TickRecord& r, std::size_t) { return r.meas.v_y; }, "lateral speed at the CoG, body frame, > 0 left"),
    Scalar("yaw_rate_radps", "rad/s", [](const TickRecord& r, std::size_t) { return r.meas.yaw_rate; }, "yaw rate, > 0 left"),
    Scalar("ax_mps2", "m/s^2", [](const TickRecord& r, std::size_t) { return r.meas.a_x; }, "longitudinal acceleration"),
    Scalar("ay_mps2", "m/s^2", [](const TickRecord& r, std::size_t) { return r.meas.a_y; }, "lateral acceleration, > 0 left"),
    Scalar("beta_deg", "deg", [](const TickRecord& r, std::size_t) { return r.beta * kRadToDeg; }, "sideslip angle at the CoG (TickRecord::beta)"),
    Scalar("lateral_error_m", "m", [](const TickRecord& r, std::size_t) { return r.motion.lateral_error; }, "distance to the reference line, > 0 left of it"),
    Scalar("heading_error_deg", "deg", [](const TickRecord& r, std::size_t) { return r.motion.heading_error * kRadToDeg; }, "heading relative to the reference line"),
    Scalar("v_target_mps", "m/s", [](const TickRecord& r, std::size_t) { return r.motion.v_target; }, "reference speed of the motion controller"),
    Scalar("steer_req_rad", "rad", [](const TickRecord& r, std::size_t) { return r.input.steering_request; }, "requested tyre angle (with a steering event's offset), > 0 left"),
    Scalar("steer_out_rad", "rad", [](const TickRecord& r, std::size_t) { return r.output.steering; }, "tyre angle the stability controller commanded"),
    Scalar("steer_meas_rad", "rad", [](const TickRecord& r, std::size_t) { return r.meas.steering_angle; }, "measured tyre angle"),
    Scalar("throttle_req", "0..1", [](const TickRecord& r, std::size_t) { return r.input.throttle_request; }, "requested throttle (a throttle event's value while it acts)"),
    Scalar("throttle_out", "0..1", [](const TickRecord& r, std::size_t) { return r.output.throttle; }, "throttle the stability controller commanded"),
    Scalar("long_fx_N", "N", [](const TickRecord& r, std::size_t) { return r.input.long_fx; }, "requested total longitudinal force, drive > 0"),
    Count("gear", [](const TickRecord& r) { return r.meas.gear; }, "engaged gear (1-based)"),
    Scalar("engine_speed_radps", "rad/s", [](const TickRecord& r, std::size_t) { return r.meas.engine_speed; }, "measured engine speed"),
    Count("esc_active", [](const TickRecord& r) { return r.output.esc_active ? 1 : 0; }, "1 while ESC acts"),
    Count("cs_active", [](const TickRecord& r) { return r.output.cs_active ? 1 : 0; }, "1 while countersteer acts"),
    Count("abs_active", [](const TickRecord& r) { return AnyActive(r.output.abs_state) ? 1 : 0; }, "1 while ABS acts on any wheel"),
    Count("tc_active", [](const TickRecord& r) { return AnyActive(r.output.tc_state) ? 1 : 0; }, "1 while TC acts on any wheel"),
    Scalar("yaw_moment_Nm", "N*m", [](const TickRecord& r, std::size_t) { return r.output.yaw_moment; }, "ESC yaw moment demand, > 0 turns left"),
    Wheel("p_req_fl_bar", "bar", &PressureRequested, kFL, "requested brake pressure"),
    Wheel("p_req_fr_bar", "bar", &PressureRequested, kFR, "requested brake pressure"),
    Wheel("p_req_rl_bar", "bar", &PressureRequested, kRL, "requested brake pressure"),
    Wheel("p_req_rr_bar", "bar", &PressureRequested, kRR, "requested brake pressure"),
    Wheel("p_out_fl_bar", "bar", &PressureCommanded, kFL, "brake pressure the stability controller commanded"),
    Wheel("p_out_fr_bar", "bar", &PressureCommanded, kFR, "brake pressure the stability controller commanded"),
    Wheel("p_out_rl_bar", "bar", &PressureCommanded, kRL, "brake pressure the stability controller commanded"),
    Wheel("p_out_rr_bar", "bar", &PressureCommanded, kRR, "brake pressure the stability controller commanded"),
    Wheel("slip_fl_pct", "%", &SlipPercent, kFL, "plant's longitudinal slip (relaxed, tyre frame), < 0 braking"),
    Wheel("slip_fr_pct", "%", &SlipPercent, kFR, "plant's longitudinal slip"),
    Wheel("slip_rl_pct", "%", &SlipPercent, kRL, "plant's longitudinal slip"),
    Wheel("slip_rr_pct", "%", &SlipPercent, kRR, "plant's longitudinal slip"),
    Wheel("alpha_fl_rad", "rad", &SlipAngle, kFL, "plant's slip angle (relaxed)"),
    Wheel("alpha_fr_rad", "rad", &SlipAngle, kFR, "plant's slip angle"),
    Wheel("alpha_rl_rad", "rad", &SlipAngle, kRL, "plant's slip angle"),
    Wheel("alpha_rr_rad", "rad", &SlipAngle, kRR, "plant's slip angle"),
    Wheel("fz_fl_N", "N", &VerticalLoad, kFL, "plant's vertical load"),
    Wheel("fz_fr_N", "N", &VerticalLoad, kFR, "plant's vertical load"),
    Wheel("fz_rl_N", "N", &VerticalLoad, kRL, "plant's vertical load"),
    Wheel("fz_rr_N", "N", &VerticalLoad, kRR, "plant's vertical load"),
    Count("events", [](const TickRecord& r) { return static_cast<int>(r.event_mask); }, "bit mask of the active events: 1 throttle, 2 steer, 4 rear grip, 8 gust"),
    Scalar("yaw_rate_ref_radps", "rad/s", [](const TickRecord& r, std::size_t) { return r.output.yaw_rate_ref; }, "ESC's yaw-rate reference (what yaw_rate_radps is steered towards), > 0 left"),
    Wheel("fx_fl_N", "N", &LongitudinalForce, kFL, "plant's tyre longitudinal force (tyre frame), < 0 braking"),
    Wheel("fx_fr_N", "N", &LongitudinalForce, kFR, "plant's tyre longitudinal force"),
    Wheel("fx_rl_N", "N", &LongitudinalForce, kRL, "plant's tyre longitudinal force"),
    Wheel("fx_rr_N", "N", &LongitudinalForce, kRR, "plant's tyre longitudinal force"),
};
// clang-format on

void WriteTraceRow(const TickRecord& r, io::CsvWriter* w) {
  for (const TraceColumn& c : kTraceColumns) {
    if (c.integer) {
      w->Add(c.integer(r));
    } else {
      w->Add(c.real(r, c.wheel));
    }
  }
  w->EndRow();
}

}  // namespace scw::tuning
