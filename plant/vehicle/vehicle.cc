#include "plant/vehicle/vehicle.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "plant/common/fast_math.h"
#include "plant/tire/magic_formula.h"

namespace scw::plant {
namespace {

const params::VehicleParams& Validated(const params::VehicleParams& p) {
  params::ValidateOrThrow(p, p.name);
  return p;
}

// Coulomb friction with stiction on a spinning body: `w_free` is the speed after the step without
// friction, `dw` the largest speed change friction can cause in the step. Friction stops the body
// but never reverses it.
inline double ApplyFriction(double w_free, double dw) noexcept {
  if (std::abs(w_free) <= dw) return 0.0;
  return w_free > 0.0 ? w_free - dw : w_free + dw;
}

// Smooth sign for the continuous right-hand side.
inline double SmoothSign(double w) noexcept { return std::clamp(w * 10.0, -1.0, 1.0); }

constexpr int kOmega = kOmegaFL;
constexpr int kKappa = kKappaFL;
constexpr int kAlpha = kAlphaFL;
constexpr double kMaxRoadFriction = 10.0;  // road factors outside (0, 10) count as 1

}  // namespace

struct Vehicle::Eval {
  PerWheel<double> fz{}, fx_t{}, fy_t{};
  double fx = 0.0, fy = 0.0, mz = 0.0;  // body totals incl. drag
  double vx_dot = 0.0, vy_dot = 0.0, r_dot = 0.0;
  PerWheel<double> torque{};    // wheel torque without friction [N*m]
  PerWheel<double> friction{};  // friction torque capacity >= 0 [N*m]
  double engine_inertia = 0.0;  // engine inertia reflected to the rear axle [kg m^2]
  double engine_torque = 0.0, axle_torque = 0.0;
  double cos_steer = 1.0, sin_steer = 0.0;  // of the road-wheel angle, reused by SlipKinematics
};

Vehicle::Vehicle(const params::VehicleParams& p)
    : p_(Validated(p)),
      h_(p_.simulation.time_step),
      engine_(p_.engine),
      gearbox_(p_.gearbox),
      diff_(p_.differential),
      steering_(p_.steering, p_.simulation.time_step),
      brakes_(p_.brakes, p_.simulation.time_step) {
  const auto& c = p_.chassis;
  m_ = c.mass;
  iz_ = c.yaw_inertia;
  g_ = c.gravity;
  l_ = c.wheelbase;
  lf_ = c.cg_to_front_axle;
  lr_ = l_ - lf_;
  hcg_ = c.cg_height;
  px_ = {lf_, lf_, -lr_, -lr_};
  py_ = {0.5 * c.track_front, -0.5 * c.track_front, 0.5 * c.track_rear, -0.5 * c.track_rear};
  radius_ = FromFrontRear(p_.wheels.radius_front, p_.wheels.radius_rear);
  inertia_ = FromFrontRear(p_.wheels.inertia_front, p_.wheels.inertia_rear);
  kb_ = FromFrontRear(p_.brakes.torque_gain_front, p_.brakes.torque_gain_rear);
  fz_static_ = FromFrontRear(0.5 * m_ * g_ * lr_ / l_, 0.5 * m_ * g_ * lf_ / l_);
  const auto& gr = p_.grip;
  for (std::size_t i = 0; i < 4; ++i) {
    lambda_x_[i] = gr.mu * (IsFront(i) ? gr.front_mu_x : gr.rear_mu_x) * gr.wheel_mu_x[i];
    lambda_y_[i] = gr.mu * (IsFront(i) ? gr.front_mu_y : gr.rear_mu_y) * gr.wheel_mu_y[i];
  }
  curve_grip_ = p_.tires.grip_scaling == "curve";
  tire_set_ = TireSet4({&p_.tires.front, &p_.tires.front, &p_.tires.rear, &p_.tires.rear});
  share_f_ = c.roll_stiffness_share_front;
  inv_bf_ = 1.0 / c.track_front;
  inv_br_ = 1.0 / c.track_rear;
  drag_k_ = 0.5 * p_.aero.air_density * p_.aero.drag_area;
  lift_kf_ = 0.5 * p_.aero.air_density * p_.aero.downforce_area_front;
  lift_kr_ = 0.5 * p_.aero.air_density * p_.aero.downforce_area_rear;
  side_k_ = 0.5 * p_.aero.air_density * p_.aero.side_force_area;
  side_arm_ = p_.aero.side_force_arm;
  inv_tau_lt_ = 1.0 / c.load_transfer_time_constant;
  lt_gain_ = 1.0 - std::exp(-h_ * inv_tau_lt_);
  lt_second_order_ = c.load_transfer_frequency > 0.0;
  const double w_n = 2.0 * std::numbers::pi * c.load_transfer_frequency;
  lt_w2_ = w_n * w_n;
  lt_2zw_ = 2.0 * c.load_transfer_damping_ratio * w_n;
  crr_ = p_.wheels.rolling_resistance;
  clutch_slip_speed_ = RpmToRadPerSec(p_.engine.clutch_slip_rpm);
  engine_inertia_ = p_.engine.inertia;
}

PerWheel<double> Vehicle::WheelLoads(const StateVector& x) const noexcept {
  return Loads(x, x[kVx] * x[kVx]);
}

PerWheel<double> Vehicle::Loads(const StateVector& x, double air_speed_sq) const noexcept {
  const double down_f = 0.5 * lift_kf_ * air_speed_sq;  // per wheel
  const double down_r = 0.5 * lift_kr_ * air_speed_sq;
  const double d_long = 0.5 * m_ * hcg_ * x[kAxLoadTransfer] / l_;  // per wheel, to the rear
  const double may_h = m_ * x[kAyLoadTransfer] * hcg_;
  const double d_lat_f = share_f_ * may_h * inv_bf_;  // to the right wheel when a_y > 0
  const double d_lat_r = (1.0 - share_f_) * may_h * inv_br_;
  const double f = fz_static_[kFL] + down_f - d_long;
  const double r = fz_static_[kRL] + down_r + d_long;
  return {std::max(0.0, f - d_lat_f), std::max(0.0, f + d_lat_f), std::max(0.0, r - d_lat_r),
          std::max(0.0, r + d_lat_r)};
}

double Vehicle::KinematicEngineSpeed(const StateVector& x, int gear) const noexcept {
  return 0.5 * (x[kOmegaRL] + x[kOmegaRR]) * gearbox_.overall[gear - 1];
}

void Vehicle::SlipKinematics(const StateVector& x, double c, double s, PerWheel<double>* kappa,
                             PerWheel<double>* alpha, PerWheel<double>* inv_tau_k,
                             PerWheel<double>* inv_tau_a) const noexcept {
  using fast_math_detail::Select;
  using fast_math_detail::Splat;
  const auto& k = p_.tires.kinematics;
  const double vx = x[kVx], vy = x[kVy], r = x[kYawRate];
  // Two wheels per Double2 (the front pair, then the rear pair), each lane the scalar formula's
  // operations in its order; the atan chains of all four overlap (plant/common/fast_math.h).
  const auto max = [](Double2 a, double b) { return Select<Double2>(a < Splat(b), Splat(b), a); };
  for (std::size_t j = 0; j < 2; ++j) {
    const std::size_t i = 2 * j;
    const Double2 vxw = vx - r * Double2{py_[i], py_[i + 1]};
    const Double2 vyw = vy + r * Double2{px_[i], px_[i + 1]};
    Double2 vxt = vxw, vyt = vyw;
    if (j == 0) {  // the front wheels, rotated by the road-wheel angle
      vxt = c * vxw + s * vyw;
      vyt = -s * vxw + c * vyw;
    }
    const Double2 avx = fast_math_detail::Abs(vxt);
    const Double2 omega_r =
        Double2{x[kOmega + i], x[kOmega + i + 1]} * Double2{radius_[i], radius_[i + 1]};
    const Double2 slip = (omega_r - vxt) / max(avx, k.slip_speed_min_long);
    const Double2 clamped =
        Select<Double2>(slip < Splat(-k.slip_limit), Splat(-k.slip_limit),
                        Select<Double2>(Splat(k.slip_limit) < slip, Splat(k.slip_limit), slip));
    const Double2 tan_alpha = vyt / max(avx, k.slip_speed_min_lat);
    const Double2 v_relax = max(avx, k.relaxation_speed_min);
    const Double2 itk = v_relax / k.relaxation_length_long;
    const Double2 ita = v_relax / k.relaxation_length_lat;
    const Double2 alpha_pair = -FastAtan(tan_alpha);
    for (std::size_t l = 0; l < 2; ++l) {
      (*kappa)[i + l] = clamped[l];
      (*alpha)[i + l] = alpha_pair[l];
      (*inv_tau_k)[i + l] = itk[l];
      (*inv_tau_a)[i + l] = ita[l];
    }
  }
}

template <bool kEnv>
void Vehicle::Evaluate(const StateVector& x, const PlantInputs& u, const Environment* env,
                       Eval* e) const noexcept {
  // Air (kEnv only; the nominal path keeps its still-air instructions): u_x is the longitudinal
  // air speed, w_y the wind's body-frame lateral component. Exactly zero (or non-finite) wind is
  // still air, bit for bit.
  double ux = 0.0, wy = 0.0;
  bool wind = false;
  if constexpr (kEnv) {
    ux = x[kVx];
    const double wx_w = env->wind_x, wy_w = env->wind_y;
    wind = (wx_w != 0.0 || wy_w != 0.0) && std::isfinite(wx_w) && std::isfinite(wy_w);
    if (wind) {
      const double cp = std::cos(x[kPsi]), sp = std::sin(x[kPsi]);
      ux -= cp * wx_w + sp * wy_w;
      wy = -sp * wx_w + cp * wy_w;
    }
    e->fz = Loads(x, ux * ux);
  } else {
    e->fz = WheelLoads(x);
  }
  e->cos_steer = std::cos(u.steer);
  e->sin_steer = std::sin(u.steer);
  const double c = e->cos_steer, s = e->sin_steer;
  std::array<TireInput, 4> tire_in;
  for (std::size_t i = 0; i < 4; ++i) {
    const double alpha = x[kAlpha + i];
    double road = 1.0;  // the road's factor multiplies the vehicle's
    if constexpr (kEnv) {
      const double m = env->mu[i];
      if (m > 0.0 && m < kMaxRoadFriction) road = m;
    }
    tire_in[i] = WheelTireInput(i, e->fz[i], x[kKappa + i], IsLeft(i) ? alpha : -alpha, road);
  }
  std::array<TireForce, 4> tire_f;
  TireForces4(tire_in, tire_set_, &tire_f);
  double fx = 0.0, fy = 0.0, mz = 0.0;
  for (std::size_t i = 0; i < 4; ++i) {
    const bool left = IsLeft(i);
    const TireForce& f = tire_f[i];
    const double fyt = left ? f.fy : -f.fy;
    e->fx_t[i] = f.fx;
    e->fy_t[i] = fyt;
    double fxv = f.fx, fyv = fyt;
    if (IsFront(i)) {
      fxv = c * f.fx - s * fyt;
      fyv = s * f.fx + c * fyt;
    }
    fx += fxv;
    fy += fyv;
    mz += px_[i] * fyv - py_[i] * fxv;
  }
  const double vx = x[kVx], vy = x[kVy], r = x[kYawRate];
  if constexpr (kEnv) {
    fx -= drag_k_ * ux * std::abs(ux);
    if (wind) {
      const double uy = vy - wy;
      const double side = side_k_ * wy * std::sqrt(ux * ux + uy * uy);
      fy += side;
      mz += side_arm_ * side;
    }
  } else {
    fx -= drag_k_ * vx * std::abs(vx);
  }
  e->fx = fx;
  e->fy = fy;
  e->mz = mz;
  e->vx_dot = fx / m_ + r * vy;
  e->vy_dot = fy / m_ - r * vx;
  e->r_dot = mz / iz_;

  // Driveline.
  const int g = std::clamp(u.gear, 1, gearbox_.gears);
  const double ratio = gearbox_.overall[g - 1];
  const double w_kin = 0.5 * (x[kOmegaRL] + x[kOmegaRR]) * ratio;
  e->engine_torque = 0.0;
  e->engine_inertia = 0.0;
  if (!u.torque_cut) {
    if (w_kin >= clutch_slip_speed_) {
      e->engine_torque = engine_.Torque(w_kin, u.throttle);
      e->engine_inertia = engine_inertia_ * ratio * ratio;
    } else {
      // Launch clutch slipping: the engine runs at the slip speed and pushes only forward.
      e->engine_torque = std::max(0.0, engine_.Torque(clutch_slip_speed_, u.throttle));
    }
  }
  e->axle_torque = e->engine_torque * ratio * gearbox_.eta[g - 1];

  for (std::size_t i = 0; i < 4; ++i) {
    e->torque[i] = -e->fx_t[i] * radius_[i];
    e->friction[i] = kb_[i] * u.brake_pressure[i] + crr_ * e->fz[i] * radius_[i];
  }
  e->torque[kRL] += 0.5 * e->axle_torque;
  e->torque[kRR] += 0.5 * e->axle_torque;
  if (!diff_.spool) {
    const double lsd = LsdTorque(x[kOmegaRL], x[kOmegaRR], e->axle_torque, diff_);
    e->torque[kRL] -= lsd;
    e->torque[kRR] += lsd;
  }
}

StateVector Vehicle::Derivatives(const StateVector& x, const PlantInputs& u) const noexcept {
  Eval e;
  Evaluate<false>(x, u, nullptr, &e);
  StateVector d;
  const double cp = std::cos(x[kPsi]), sp = std::sin(x[kPsi]);
  d[kX] = x[kVx] * cp - x[kVy] * sp;
  d[kY] = x[kVx] * sp + x[kVy] * cp;
  d[kPsi] = x[kYawRate];
  d[kVx] = e.vx_dot;
  d[kVy] = e.vy_dot;
  d[kYawRate] = e.r_dot;
  for (std::size_t i : {kFL, kFR})
    d[kOmega + i] = (e.torque[i] - e.friction[i] * SmoothSign(x[kOmega + i])) / inertia_[i];
  const double t_rl = e.torque[kRL] - e.friction[kRL] * SmoothSign(x[kOmegaRL]);
  const double t_rr = e.torque[kRR] - e.friction[kRR] * SmoothSign(x[kOmegaRR]);
  const double i_r = inertia_[kRL];
  const double wm_dot = (t_rl + t_rr) / (2.0 * i_r + e.engine_inertia);
  const double wd_dot = diff_.spool ? 0.0 : (t_rl - t_rr) / (2.0 * i_r);
  d[kOmegaRL] = wm_dot + wd_dot;
  d[kOmegaRR] = wm_dot - wd_dot;
  PerWheel<double> kk, ka, itk, ita;
  SlipKinematics(x, e.cos_steer, e.sin_steer, &kk, &ka, &itk, &ita);
  for (std::size_t i = 0; i < 4; ++i) {
    d[kKappa + i] = (kk[i] - x[kKappa + i]) * itk[i];
    d[kAlpha + i] = (ka[i] - x[kAlpha + i]) * ita[i];
  }
  if (lt_second_order_) {
    d[kAxLoadTransfer] = x[kAxLoadTransferRate];
    d[kAyLoadTransfer] = x[kAyLoadTransferRate];
    d[kAxLoadTransferRate] =
        lt_w2_ * (e.fx / m_ - x[kAxLoadTransfer]) - lt_2zw_ * x[kAxLoadTransferRate];
    d[kAyLoadTransferRate] =
        lt_w2_ * (e.fy / m_ - x[kAyLoadTransfer]) - lt_2zw_ * x[kAyLoadTransferRate];
  } else {
    d[kAxLoadTransfer] = (e.fx / m_ - x[kAxLoadTransfer]) * inv_tau_lt_;
    d[kAyLoadTransfer] = (e.fy / m_ - x[kAyLoadTransfer]) * inv_tau_lt_;
    d[kAxLoadTransferRate] = 0.0;
    d[kAyLoadTransferRate] = 0.0;
  }
  return d;
}

State Vehicle::MakeState(const InitialCondition& ic) const {
  State s;
  s.x[kX] = ic.x;
  s.x[kY] = ic.y;
  s.x[kPsi] = ic.psi;
  s.x[kVx] = ic.speed;
  for (std::size_t i = 0; i < 4; ++i) s.x[kOmega + i] = ic.speed / radius_[i];
  s.steering = steering_.MakeState(0.0);
  s.brakes = brakes_.MakeState();
  const int gear = GearForSpeed(s.x[kOmegaRL], p_.gearbox.initial_gear, gearbox_);
  s.gearbox = GearboxState{gear, gear, ShiftPhase::kEngaged, 0.0};
  s.out.fz = WheelLoads(s.x);
  s.out.engine_speed = std::max(KinematicEngineSpeed(s.x, gear), clutch_slip_speed_);
  return s;
}

template <bool kEnv>
void Vehicle::StepOn(const Actuators& u, const Environment* env, State* state) const noexcept {
  State& s = *state;
  const double h = h_;
  if (s.status & kStatusNonFinite) {
    s.time += h;
    return;
  }
  // 1. Actuators and gearbox (discrete, held over the step).
  PlantInputs in;
  in.steer = steering_.Step(u.steer_req, &s.steering);
  in.brake_pressure = brakes_.Step(u.brake_pressure_req, &s.brakes);
  in.throttle = std::isfinite(u.throttle) ? std::clamp(u.throttle, 0.0, 1.0) : 0.0;
  s.throttle = in.throttle;
  s.gearbox = Next(s.gearbox, KinematicEngineSpeed(s.x, s.gearbox.engaged), h, gearbox_);
  in.gear = s.gearbox.engaged;
  in.torque_cut = s.gearbox.phase == ShiftPhase::kShifting;

  // 2. Forces at the start of the step.
  Eval e;
  Evaluate<kEnv>(s.x, in, env, &e);

  // 3. Velocities explicit, positions with the new velocities (symplectic Euler).
  StateVector& x = s.x;
  const StateVector x_old = x;
  x[kVx] += h * e.vx_dot;
  x[kVy] += h * e.vy_dot;
  x[kYawRate] += h * e.r_dot;
  x[kPsi] += h * x[kYawRate];
  const double cp = std::cos(x[kPsi]), sp = std::sin(x[kPsi]);
  x[kX] += h * (x[kVx] * cp - x[kVy] * sp);
  x[kY] += h * (x[kVx] * sp + x[kVy] * cp);

  // Wheels: driving/tyre torques explicit, friction (brakes, rolling resistance) implicit.
  for (std::size_t i : {kFL, kFR}) {
    const double inv_i = 1.0 / inertia_[i];
    x[kOmega + i] =
        ApplyFriction(x[kOmega + i] + h * e.torque[i] * inv_i, h * e.friction[i] * inv_i);
  }
  const double i_r = inertia_[kRL];
  const double inv_im = 1.0 / (2.0 * i_r + e.engine_inertia);  // mean (axle) mode
  if (diff_.spool) {
    const double wm = 0.5 * (x[kOmegaRL] + x[kOmegaRR]);
    const double w = ApplyFriction(wm + h * (e.torque[kRL] + e.torque[kRR]) * inv_im,
                                   h * (e.friction[kRL] + e.friction[kRR]) * inv_im);
    x[kOmegaRL] = w;
    x[kOmegaRR] = w;
  } else {
    // Mean/difference modes; the friction impulse of one wheel moves both modes. Wheels are
    // projected one after the other (exact unless both stop in the same step).
    const double inv_id = 1.0 / (2.0 * i_r);
    const double g_self = inv_im + inv_id, g_cross = inv_im - inv_id;
    double wl = x[kOmegaRL] + h * ((e.torque[kRL] + e.torque[kRR]) * inv_im +
                                   (e.torque[kRL] - e.torque[kRR]) * inv_id);
    double wr = x[kOmegaRR] + h * ((e.torque[kRL] + e.torque[kRR]) * inv_im -
                                   (e.torque[kRL] - e.torque[kRR]) * inv_id);
    auto project = [&](double* w_self, double* w_other, double friction) {
      const double w_new = ApplyFriction(*w_self, h * friction * g_self);
      const double impulse = (w_new - *w_self) / g_self;
      *w_self = w_new;
      *w_other += g_cross * impulse;
    };
    project(&wl, &wr, e.friction[kRL]);
    project(&wr, &wl, e.friction[kRR]);
    x[kOmegaRL] = wl;
    x[kOmegaRR] = wr;
  }

  if (lt_second_order_) {
    // Roll/pitch modes: rate first, then the acceleration with the new rate.
    const double a_in[2] = {e.fx / m_, e.fy / m_};
    for (int k = 0; k < 2; ++k) {
      double& a = x[kAxLoadTransfer + k];
      double& rate = x[kAxLoadTransferRate + k];
      rate += h * (lt_w2_ * (a_in[k] - a) - lt_2zw_ * rate);
      a += h * rate;
    }
  } else {
    // Load-transfer lag (exact for the held accelerations).
    x[kAxLoadTransfer] += lt_gain_ * (e.fx / m_ - x[kAxLoadTransfer]);
    x[kAyLoadTransfer] += lt_gain_ * (e.fy / m_ - x[kAyLoadTransfer]);
  }

  // 4. Tyre relaxation, backward Euler towards the slips of the new velocities.
  PerWheel<double> kk, ka, itk, ita;
  SlipKinematics(x, e.cos_steer, e.sin_steer, &kk, &ka, &itk, &ita);
  for (std::size_t i = 0; i < 4; i += 2) {  // two wheels per Double2, the same operations
    const Double2 tk = h * Double2{itk[i], itk[i + 1]};
    const Double2 ta = h * Double2{ita[i], ita[i + 1]};
    const Double2 k_new =
        (Double2{x[kKappa + i], x[kKappa + i + 1]} + tk * Double2{kk[i], kk[i + 1]}) / (1.0 + tk);
    const Double2 a_new =
        (Double2{x[kAlpha + i], x[kAlpha + i + 1]} + ta * Double2{ka[i], ka[i + 1]}) / (1.0 + ta);
    x[kKappa + i] = k_new[0];
    x[kKappa + i + 1] = k_new[1];
    x[kAlpha + i] = a_new[0];
    x[kAlpha + i + 1] = a_new[1];
  }

  // All finite <=> the sum of x_i - x_i is 0 (inf - inf and NaN give NaN); two lanes at a time
  // and without a branch per element, the same verdict as x.allFinite().
  Double2 nan_probe = {0.0, 0.0};
  for (int i = 0; i < kNumStates; i += 2) {
    const Double2 v = {x[i], x[i + 1]};
    nan_probe += v - v;
  }
  if (!(nan_probe[0] + nan_probe[1] == 0.0)) {
    x = x_old;
    s.status |= kStatusNonFinite;
  }

  // Diagnostics.
  StepOutputs& o = s.out;
  o.a_x = e.fx / m_;
  o.a_y = e.fy / m_;
  o.fz = e.fz;
  o.fx = e.fx_t;
  o.fy = e.fy_t;
  for (std::size_t i = 0; i < 4; ++i) {
    o.kappa[i] = x_old[kKappa + i];
    o.alpha[i] = x_old[kAlpha + i];
    o.brake_torque[i] = kb_[i] * in.brake_pressure[i];
  }
  o.engine_torque = e.engine_torque;
  o.axle_torque = e.axle_torque;
  o.engine_speed = std::max(KinematicEngineSpeed(x, s.gearbox.engaged), clutch_slip_speed_);
  s.time += h;
}

template void Vehicle::StepOn<false>(const Actuators&, const Environment*, State*) const noexcept;
template void Vehicle::StepOn<true>(const Actuators&, const Environment*, State*) const noexcept;

Measurement MeasureState(const State& s, const params::SensorParams& sensors,
                         SensorNoiseState* noise) noexcept {
  Measurement m;
  m.time = s.time;
  m.x = s.x[kX];
  m.y = s.x[kY];
  m.psi = s.x[kPsi];
  m.v_x = s.x[kVx];
  m.v_y = s.x[kVy];
  m.yaw_rate = s.x[kYawRate];
  m.a_x = s.out.a_x;
  m.a_y = s.out.a_y;
  for (std::size_t i = 0; i < 4; ++i) m.wheel_speed[i] = s.x[kOmega + i];
  m.steering_angle = s.steering.angle;
  m.brake_pressure = s.brakes.pressure;
  m.gear = s.gearbox.engaged;
  m.gear_request = s.gearbox.requested;
  m.engine_speed = s.out.engine_speed;
  m.wheel_load = s.out.fz;
  m.throttle = s.throttle;
  m.status = s.status;
  if (noise != nullptr) AddSensorNoise(sensors, &m, noise);
  return m;
}

Measurement Vehicle::Measure(const State& s, SensorNoiseState* noise) const noexcept {
  return MeasureState(s, p_.sensors, noise);
}

}  // namespace scw::plant
