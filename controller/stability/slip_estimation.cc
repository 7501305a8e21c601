#include "controller/stability/slip_estimation.h"

#include <algorithm>
#include <cmath>

#include "controller/common/interp.h"
#include "controller/common/low_pass.h"

namespace scw::controller {
namespace {
constexpr double kBlendPole = 0.8;  // hard-coded in the reference (spec §2.3)
}  // namespace

SlipEstimator::SlipEstimator(const params::StabilityParams& p)
    : geometry_(ChassisGeometry::From(p)),
      load_model_(LoadModel::From(p)),
      radius_front_(p.tires.front_left.radius.radius_20mps),
      radius_rear_(p.tires.rear_left.radius.radius_20mps),
      scaling_(p.tires.front_left.radius.velocity_scaling),
      v_min_(p.P_VDC_MinVelSlipCalc_mps),
      final_drive_(p.vehicle.drivetrain.transmission_ratio),
      gear_ratios_(p.vehicle.drivetrain.gear_ratios) {
  params::ValidateOrThrow(p);
}

double SlipEstimator::Radius(std::size_t wheel, double speed) const noexcept {
  return DynamicTyreRadius(IsFront(wheel) ? radius_front_ : radius_rear_, speed, scaling_);
}

double SlipEstimator::LowSpeedFade(double v_ref, double v_min) noexcept {
  const double x = std::max(v_ref - std::max(v_min - 2.0, 0.0), 0.0);
  const double x2 = x * x;
  const double x4 = x2 * x2;
  return std::clamp(x4 * x4 / 256.0, 0.0, 1.0);
}

double SlipEstimator::LongitudinalSlipPct(double omega, double radius, double v_tyre_x,
                                          double fade) noexcept {
  return 100.0 * fade *
         std::clamp((omega * radius - v_tyre_x) / std::max(3.0, v_tyre_x), -1.0, 1.0);
}

SlipEstimator::Output SlipEstimator::Step(const Input& in, State* s) const noexcept {
  Output out;
  const LowPass blend_filter(kBlendPole);
  const Wheels dx = YawSpeedOffsets(in.yaw_rate, geometry_);
  // All tyres share one velocity scaling: evaluate it once per speed.
  const double factor_vx = Interp(in.v_x, scaling_.velocity, scaling_.factor);
  const Wheels radius_vx = FromFrontRear(radius_front_ * factor_vx, radius_rear_ * factor_vx);

  // §2.3 reference speed.
  double v_front = in.v_x;
  if (in.wheel_speeds_valid) {
    const double c = std::cos(in.steering);
    const double sn = std::sin(in.steering);
    const double vy_front = in.v_y + geometry_.l_front * in.yaw_rate;
    double sum = 0.0;
    for (std::size_t i = 0; i < 2; ++i) {
      const double v_wheel = in.wheel_speed[i] * radius_vx[i];
      const double vx_w = (v_wheel - sn * vy_front) / c;
      sum += vx_w - dx[i];
    }
    v_front = 0.5 * sum;
  }
  const double ax_f = blend_filter.Step(in.a_x, &s->ax_filtered);
  const double f = std::max(
      {std::clamp(in.front_pressure_max_bar / 5.0, 0.0, 1.0), std::clamp(-(ax_f + 5.0), 0.0, 1.0),
       std::clamp(std::max(std::abs(s->prev_slip_fl), std::abs(s->prev_slip_fr)) / 5.0 - 1.0, 0.0,
                  1.0)});
  const double f_filt = blend_filter.Step(f, &s->blend_filtered);
  const double v_ref = f_filt * in.v_x + (1.0 - f_filt) * v_front;
  out.v_ref = v_ref;
  out.blend = f_filt;

  // §2.4 slips and slip angles against v_ref.
  const double fade = LowSpeedFade(v_ref, v_min_);
  out.fade = fade;
  const auto tyre = TyreVelocities(v_ref, in.v_y, in.yaw_rate, in.steering, geometry_);
  const double factor_ref = Interp(v_ref, scaling_.velocity, scaling_.factor);
  const Wheels radius_ref = FromFrontRear(radius_front_ * factor_ref, radius_rear_ * factor_ref);
  for (std::size_t i = 0; i < 4; ++i) {
    out.slip_angle[i] = fade * TyreSlipAngle(tyre[i]);
    out.slip_pct[i] = in.wheel_speeds_valid ? LongitudinalSlipPct(in.wheel_speed[i], radius_ref[i],
                                                                  tyre[i].longitudinal, fade)
                                            : 0.0;
  }

  // §2.5 virtual slips.
  if (in.engine_speed_valid) {
    Wheels omega_virt{};
    const int g = std::max(0, in.gear - 1);
    const double ratio = static_cast<std::size_t>(g) < gear_ratios_.size()
                             ? final_drive_ * gear_ratios_[static_cast<std::size_t>(g)]
                             : 0.0;
    const double r_rl = radius_vx[kRL];
    const double r_rr = radius_vx[kRR];
    if (std::abs(ratio) > 1e-9 && std::abs(r_rl) > 1e-9 && std::abs(r_rr) > 1e-9) {
      const double omega_rear = in.engine_speed / ratio;
      omega_virt = {in.wheel_speed[kFL], in.wheel_speed[kFR], omega_rear + dx[kRL] / r_rl,
                    omega_rear + dx[kRR] / r_rr};
    }
    for (std::size_t i = 0; i < 4; ++i) {
      out.virtual_slip_pct[i] =
          LongitudinalSlipPct(omega_virt[i], radius_ref[i], tyre[i].longitudinal, fade);
    }
    if (!in.wheel_speeds_valid) out.virtual_slip_pct[kFL] = out.virtual_slip_pct[kFR] = 0.0;
  } else {
    out.virtual_slip_pct = {out.slip_pct[kFL], out.slip_pct[kFR], 0.0, 0.0};
  }

  s->prev_slip_fl = out.slip_pct[kFL];
  s->prev_slip_fr = out.slip_pct[kFR];

  // §2.6 vertical loads.
  out.fz = in.fz_external_valid ? in.fz_external
                                : QuasiStaticVerticalLoads(load_model_, in.v_x, in.a_x, in.a_y);
  return out;
}

}  // namespace scw::controller
