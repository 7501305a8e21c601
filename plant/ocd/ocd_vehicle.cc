#include "plant/ocd/ocd_vehicle.h"

// OCD's headers. Its type-support layer must see tum_types before tsl_logger, and its vehicle
// model needs tsl's value logger declared first: the order the snapshot's headers expect.
// clang-format off
#include "tum_types_cpp/common.hpp"
#include "tum_types_cpp/data_per_wheel.hpp"
#include "tsl_logger_cpp/value_logger.hpp"
#include "tsl_logger_cpp/reference_logger.hpp"
#include "param_management_cpp/param_reference_manager.hpp"
#include "ocd_aerodynamics_models_cpp/default.hpp"
#include "ocd_drivetrain_rwd_lsd_cpp/drivetrain_rwd_lsd_model.hpp"
#include "ocd_steering_actuator_model_base_cpp/base_class.hpp"
#include "ocd_tire_models_cpp/mf_52.hpp"
#include "ocd_vehicle_dynamics_double_track_cpp/vehicle_dynamics_model.hpp"
#include "ocd_vehicle_model_cpp/vehicle_model.hpp"
// clang-format on

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

namespace scw::plant::ocd {
namespace {

namespace tt = tam::types::common;

/// The road-wheel angle straight through OCD's steering-actuator interface: scw's actuator model
/// already delayed, lagged and rate-limited it, so OCD must not act a second time. One state (the
/// angle, kept constant: OCD's composition integrates a state per sub-model) and no parameters.
struct PassThroughInput {
  double steering_angle_rad = 0.0;
};
struct PassThroughStateNames {
  static constexpr std::array<std::string_view, 1> value = {"angle_rad"};
};
class PassThroughSteering
    : public tam::ocd::interfaces::SteeringActuatorModelBase<PassThroughInput, void, 1,
                                                             PassThroughStateNames> {
 public:
  void set_x_vec(const StateVectorType& x) override { x_ = x; }
  void set_driver_input(const PassThroughInput& in) override { angle_ = in.steering_angle_rad; }
  void set_load(const tt::DataPerWheel<double>&) override {}
  void evaluate() override {}
  tt::DataPerWheel<double> get_steering_angles() const override { return {angle_, angle_, 0, 0}; }
  void get_feedback() const override {}
  StateVectorType get_x_vec() const override { return x_; }
  StateVectorType get_x_dot_vec() const override { return StateVectorType::Zero(); }
  tam::tsl::LoggerAccessInterface::SharedPtr get_logger() const override { return logger_; }
  tam::pmg::MgmtInterface::SharedPtr get_param_manager() const override { return params_; }

 private:
  StateVectorType x_ = StateVectorType::Zero();
  double angle_ = 0.0;
  std::shared_ptr<tam::tsl::ReferenceLogger> logger_ =
      std::make_shared<tam::tsl::ReferenceLogger>();
  std::shared_ptr<tam::pmg::ParamReferenceManager> params_ =
      std::make_shared<tam::pmg::ParamReferenceManager>();
};
static_assert(tam::ocd::interfaces::concepts::SteeringActuatorModel<PassThroughSteering>);

using Composition = tam::ocd::VehicleModel<
    tam::ocd::drivetrain::DrivetrainModel_RWD_LSD, PassThroughSteering,
    tam::ocd::vehicle_dynamics::VehicleDynamicsDoubleTrackModel<
        tam::ocd::tire_models::MF52, tam::ocd::aerodynamics::DefaultAerodynamicsModel>>;

double ValueOf(const tam::pmg::ParameterValue& v) { return v.as_double(); }

PerWheel<double> Wheels(const tt::DataPerWheel<double>& d) {
  return {d.front_left, d.front_right, d.rear_left, d.rear_right};
}

double Mapped(const std::vector<OcdParameter>& all, const std::string& name) {
  for (const OcdParameter& q : all)
    if (q.name == name) return q.value.at(0);
  throw std::out_of_range("no mapped OCD parameter " + name);
}

// Heave, pitch and wheel positions of OCD's static equilibrium under the downforce at `speed`,
// relative to its own at rest (the zero state), for the linear springs of its model:
//   sprung body  sum dF_susp = F_a,  2 dF_f l_f - 2 dF_r l_r = -tau   (per-corner dF_f, dF_r)
//   wheels       dF_susp = c_t dz_w;  springs  dF_f = c_f (dz - dtheta l_f,s - dz_w,f), rear with
//                +dtheta l_r,s
// with F_a = 1/2 c_l rho A v^2 (< 0: down) and tau = -F_a d at the CoG.
struct Settled {
  double z = 0.0, theta = 0.0, zw_f = 0.0, zw_r = 0.0;
};
Settled SettledUnderDownforce(const std::vector<OcdParameter>& q, double speed) {
  const std::string vd = "vehicle_dynamics_double_track.";
  const std::string ae = vd + "aerodynamics.";
  const double m = Mapped(q, vd + "mass_vehicle_kg");
  const double mt_f = Mapped(q, vd + "mass_wheel_kg.front");
  const double l = Mapped(q, vd + "wheelbase_m");
  const double lf = Mapped(q, vd + "cog.distance_from_front_axle_m");
  const double lr = l - lf;
  const double ms = m - 2.0 * mt_f - 2.0 * Mapped(q, vd + "mass_wheel_kg.rear");
  const double lr_s = (m * lr - 2.0 * mt_f * l) / ms;
  const double lf_s = l - lr_s;
  const double cf = Mapped(q, vd + "suspension.vehicle_spring_stiffness_Npm.front");
  const double cr = Mapped(q, vd + "suspension.vehicle_spring_stiffness_Npm.rear");
  const double ctf = Mapped(q, vd + "tire.spring_stiffness_Npm.front");
  const double ctr = Mapped(q, vd + "tire.spring_stiffness_Npm.rear");
  const double fa = 0.5 * Mapped(q, ae + "c_l") * Mapped(q, ae + "air_density_kgpm3") *
                    Mapped(q, ae + "A_m2") * speed * speed;
  const double tau = -fa * Mapped(q, ae + "d_aero_center_cog_m");
  const double df = (fa * lr - tau) / (2.0 * l);
  const double dr = (fa * lf + tau) / (2.0 * l);
  Settled s;
  s.zw_f = df / ctf;
  s.zw_r = dr / ctr;
  const double a_f = df / cf + s.zw_f;
  const double a_r = dr / cr + s.zw_r;
  s.theta = (a_r - a_f) / l;
  s.z = a_f + s.theta * lf_s;
  return s;
}

}  // namespace

struct OcdModel {
  Composition model;
  tam::pmg::MgmtInterface::SharedPtr params = model.get_param_manager();
};

void OcdModelDelete::operator()(OcdModel* m) const noexcept { delete m; }

OcdVehicle::OcdVehicle(const params::VehicleParams& p)
    : p_(p),
      h_(p.simulation.time_step),
      engine_(p.engine),
      gearbox_(p.gearbox),
      steering_(p.steering, p.simulation.time_step),
      brakes_(p.brakes, p.simulation.time_step) {
  params::ValidateOrThrow(p_, p_.name);
  const std::vector<Problem> problems = CheckRepresentable(p_);
  if (!problems.empty()) throw ConfigError(p_.name + " (plant.model=ocd)", problems);
  parameters_ = MapVehicle(p_);
  const auto& c = p_.chassis;
  const double lr = c.wheelbase - c.cg_to_front_axle;
  px_ = {c.cg_to_front_axle, c.cg_to_front_axle, -lr, -lr};
  py_ = {0.5 * c.track_front, -0.5 * c.track_front, 0.5 * c.track_rear, -0.5 * c.track_rear};
  radius_ = FromFrontRear(p_.wheels.radius_front, p_.wheels.radius_rear);
  kb_ = FromFrontRear(p_.brakes.torque_gain_front, p_.brakes.torque_gain_rear);
  curve_grip_ = p_.tires.grip_scaling == "curve";
  for (std::size_t i = 0; i < 4; ++i) {
    const std::string pre =
        std::string("vehicle_dynamics_double_track.z.tire_model.") + kOcdWheelNames[i] + ".";
    lmux_name_[i] = pre + "LMUX";
    lmuy_name_[i] = pre + "LMUY";
    lmux_[i] = Mapped(parameters_, lmux_name_[i]);
    lmuy_[i] = Mapped(parameters_, lmuy_name_[i]);
  }
  clutch_slip_speed_ = RpmToRadPerSec(p_.engine.clutch_slip_rpm);
  engine_inertia_ = p_.engine.inertia;
}

double OcdVehicle::KinematicEngineSpeed(const StateVector& x, int gear) const noexcept {
  return 0.5 * (x[kOmegaRL] + x[kOmegaRR]) * gearbox_.overall[gear - 1];
}

OcdState OcdVehicle::MakeState(const InitialCondition& ic) const {
  OcdState s;
  s.model.reset(new OcdModel);
  tam::pmg::MgmtInterface& pm = *s.model->params;
  for (const OcdParameter& q : parameters_) {
    if (q.value.size() == 1)
      pm.set_value(q.name, q.value[0]);
    else
      pm.set_value(q.name, q.value);
  }
  // The start: pose, speed along the heading, wheels rolling freely, body settled on its springs.
  const Settled settled = SettledUnderDownforce(parameters_, ic.speed);
  const std::string vd = "initial_state.vehicle_dynamics.";
  const std::string dt = "initial_state.drivetrain.";
  pm.set_value(vd + "x_m", ic.x);
  pm.set_value(vd + "y_m", ic.y);
  pm.set_value(vd + "psi_rad", ic.psi);
  pm.set_value(vd + "v_x_mps", ic.speed);
  pm.set_value(vd + "z_m", settled.z);
  pm.set_value(vd + "theta_rad", settled.theta);
  for (const char* w : {"FL", "FR"}) pm.set_value(vd + "z_w_" + w + "_m", settled.zw_f);
  for (const char* w : {"RL", "RR"}) pm.set_value(vd + "z_w_" + w + "_m", settled.zw_r);
  pm.set_value(dt + "omega_FL_radps", ic.speed / radius_[kFL]);
  pm.set_value(dt + "omega_FR_radps", ic.speed / radius_[kFR]);
  pm.set_value(dt + "omega_rear_axle_radps", ic.speed / radius_[kRL]);
  pm.set_value(dt + "omega_diff_rear_radps", 0.0);
  s.model->model.reset();

  s.x[kX] = ic.x;
  s.x[kY] = ic.y;
  s.x[kPsi] = ic.psi;
  s.x[kVx] = ic.speed;
  for (std::size_t i = 0; i < 4; ++i) s.x[kOmegaFL + i] = ic.speed / radius_[i];
  s.steering = steering_.MakeState(0.0);
  s.brakes = brakes_.MakeState();
  const int gear = GearForSpeed(s.x[kOmegaRL], p_.gearbox.initial_gear, gearbox_);
  s.gearbox = GearboxState{gear, gear, ShiftPhase::kEngaged, 0.0};
  const double g = p_.chassis.gravity, m = p_.chassis.mass, l = p_.chassis.wheelbase;
  const double lf = p_.chassis.cg_to_front_axle;
  const double down = 0.5 * p_.aero.air_density * ic.speed * ic.speed;
  s.out.fz = FromFrontRear(0.5 * (m * g * (l - lf) / l + down * p_.aero.downforce_area_front),
                           0.5 * (m * g * lf / l + down * p_.aero.downforce_area_rear));
  s.out.engine_speed = std::max(KinematicEngineSpeed(s.x, gear), clutch_slip_speed_);
  return s;
}

void OcdVehicle::StepIn(const Actuators& u, const Environment* env,
                        OcdState* state) const noexcept {
  OcdState& s = *state;
  const double h = h_;
  if ((s.status & kStatusNonFinite) || !s.model) {
    s.status |= kStatusNonFinite;
    s.time += h;
    return;
  }
  // 1. scw's actuators and gearbox (discrete, held over the step).
  const double steer = steering_.Step(u.steer_req, &s.steering);
  const PerWheel<double> pressure = brakes_.Step(u.brake_pressure_req, &s.brakes);
  const double throttle = std::isfinite(u.throttle) ? std::clamp(u.throttle, 0.0, 1.0) : 0.0;
  s.throttle = throttle;
  s.gearbox = Next(s.gearbox, KinematicEngineSpeed(s.x, s.gearbox.engaged), h, gearbox_);
  const int g = std::clamp(s.gearbox.engaged, 1, gearbox_.gears);
  const bool torque_cut = s.gearbox.phase == ShiftPhase::kShifting;

  // 2. scw's engine at the rear wheels' speed: OCD's transmission torque and engine inertia.
  const double ratio = gearbox_.overall[g - 1];
  const double w_kin = KinematicEngineSpeed(s.x, g);
  double engine_torque = 0.0, engine_inertia = 0.0;
  if (!torque_cut) {
    if (w_kin >= clutch_slip_speed_) {
      engine_torque = engine_.Torque(w_kin, throttle);
      engine_inertia = engine_inertia_ * ratio * ratio;
    } else {  // launch clutch slipping: only forward torque, engine inertia decoupled
      engine_torque = std::max(0.0, engine_.Torque(clutch_slip_speed_, throttle));
    }
  }
  const double axle_torque = engine_torque * ratio * gearbox_.eta[g - 1];
  PerWheel<double> brake_torque;
  for (std::size_t i = 0; i < 4; ++i) brake_torque[i] = kb_[i] * pressure[i];

  // 3. OCD's inputs and one OCD step.
  Composition& m = s.model->model;
  m.set_steering_input(PassThroughInput{steer});
  try {
    tam::ocd::types::ExternalInfluences ext;
    if (env != nullptr) {
      const double wx = env->wind_x, wy = env->wind_y;
      if ((wx != 0.0 || wy != 0.0) && std::isfinite(wx) && std::isfinite(wy)) {
        const double cp = std::cos(s.x[kPsi]), sp = std::sin(s.x[kPsi]);
        ext.wind_mps = {cp * wx + sp * wy, -sp * wx + cp * wy, 0.0};
      }
      PerWheel<double> road{1.0, 1.0, 1.0, 1.0};
      for (std::size_t i = 0; i < 4; ++i) {
        const double mu = env->mu[i];
        if (mu > 0.0 && mu < 10.0) road[i] = mu;
      }
      if (curve_grip_) {
        ext.lambda_mue = {road[0], road[1], road[2], road[3]};
      } else {
        for (std::size_t i = 0; i < 4; ++i) {
          if (road[i] == s.road_mu[i]) continue;
          s.model->params->set_value(lmux_name_[i], lmux_[i] * road[i]);
          s.model->params->set_value(lmuy_name_[i], lmuy_[i] * road[i]);
          s.road_mu[i] = road[i];
        }
      }
    } else if (!curve_grip_ && s.road_mu != PerWheel<double>{1.0, 1.0, 1.0, 1.0}) {
      for (std::size_t i = 0; i < 4; ++i) {
        s.model->params->set_value(lmux_name_[i], lmux_[i]);
        s.model->params->set_value(lmuy_name_[i], lmuy_[i]);
      }
      s.road_mu = {1.0, 1.0, 1.0, 1.0};
    }
    m.set_external_influences(ext);
    Composition::DrivetrainDriverInputType drive;
    drive.transmission_output_torque_Nm = axle_torque;
    drive.current_engine_inertia_at_wheels_kgm2 = engine_inertia;
    drive.brake_torque_per_wheel_Nm = {brake_torque[0], brake_torque[1], brake_torque[2],
                                       brake_torque[3]};
    m.set_drivetrain_input(drive);
    m.step();
  } catch (...) {  // OCD's parameter layer or its allocation failed: end the run as non-finite
    s.status |= kStatusNonFinite;
    s.time += h;
    return;
  }

  // 4. OCD's output into scw's state fields.
  const tam::ocd::types::VehicleModelOutput o = m.get_vehicle_model_output();
  const auto& vd = o.vehicle_dynamics_output;
  StateVector x = s.x;
  x[kX] = vd.position_m.x;
  x[kY] = vd.position_m.y;
  x[kPsi] = vd.orientation_rad.z;
  x[kVx] = vd.velocity_mps.x;
  x[kVy] = vd.velocity_mps.y;
  x[kYawRate] = vd.angular_velocity_radps.z;
  const PerWheel<double> omega = Wheels(o.wheel_speeds_radps);
  const PerWheel<double> kappa = Wheels(vd.tire_longitudinal_slip_per_wheel);
  const PerWheel<double> alpha = Wheels(vd.tire_slip_angle_per_wheel_rad);
  for (std::size_t i = 0; i < 4; ++i) {
    x[kOmegaFL + i] = omega[i];
    x[kKappaFL + i] = kappa[i];
    x[kAlphaFL + i] = alpha[i];
  }
  x[kAxLoadTransfer] = vd.acceleration_mps2.x;
  x[kAyLoadTransfer] = vd.acceleration_mps2.y;
  x[kAxLoadTransferRate] = 0.0;
  x[kAyLoadTransferRate] = 0.0;
  const PerWheel<double> fz = Wheels(vd.vertical_tire_force_per_wheel_N);
  const PerWheel<double> fx = Wheels(vd.longitudinal_tire_force_tire_frame_per_wheel_N);
  const PerWheel<double> fy = Wheels(vd.lateral_tire_force_tire_frame_per_wheel_N);
  bool finite = x.allFinite();
  for (std::size_t i = 0; i < 4; ++i)
    finite = finite && std::isfinite(fz[i]) && std::isfinite(fx[i]) && std::isfinite(fy[i]);
  if (!finite) {
    s.status |= kStatusNonFinite;
    s.time += h;
    return;
  }
  s.x = x;
  StepOutputs& out = s.out;
  out.a_x = vd.acceleration_mps2.x;
  out.a_y = vd.acceleration_mps2.y;
  out.fz = fz;
  out.fx = fx;
  out.fy = fy;
  out.kappa = kappa;
  out.alpha = alpha;
  out.brake_torque = brake_torque;
  out.engine_torque = engine_torque;
  out.axle_torque = axle_torque;
  out.engine_speed = std::max(KinematicEngineSpeed(s.x, s.gearbox.engaged), clutch_slip_speed_);
  s.time += h;
}

Measurement OcdVehicle::Measure(const State& s, SensorNoiseState* noise) const noexcept {
  return MeasureState(s, p_.sensors, noise);
}

double OcdVehicle::OcdValue(const OcdState& s, const std::string& name) const {
  if (!s.model) throw std::out_of_range("no OCD instance in this state");
  try {
    return ValueOf(s.model->params->get_value(name));
  } catch (const std::exception& e) {
    throw std::out_of_range("OCD has no parameter " + name + " (" + e.what() + ")");
  }
}

std::vector<std::string> OcdVehicle::OcdNames(const OcdState& s) const {
  std::vector<std::string> out;
  if (!s.model) return out;
  for (const std::string& n : s.model->params->list_parameters()) out.push_back(n);
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace scw::plant::ocd
