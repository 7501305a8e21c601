// Vehicle parameter set of the plant (scw::plant::Vehicle): chassis, aero, wheels, tyres (MF5.2,
// one set per axle), grip scaling, powertrain, brakes, steering, sensors and the integrator step.
// Plain nested YAML files of this struct live in params/vehicles/ (eav24.yaml = these in-class
// defaults, av21.yaml = the public AV-21 set).
//
// In-class defaults: an EAV24/25-class car (A2RL, Dallara SF23 based). No validated public set
// exists (spec ../shared/spec/plant-and-track.md §0.3); the numbers are the public estimates of
// spec §4.4-§4.6 and §7, each field's doc names its source or says "assumption". Calibrated
// against public data before any study was run (issue 14): the tyre friction scalings
// (tires.*.lmux/lmuy/lkx) so that mu_x/mu_y at nominal load stays in 1.0-1.25 and the plant's
// steady-state limits lie within 10 % of the public EAV g-g-v fit (`scw vehicle gg`); the front
// cornering-stiffness scaling (tires.front.lky) for a positive understeer gradient (`scw vehicle
// balance`); the brake delay for a 150 ms total brake response; an LSD as on the SF23-based car.
// The paper's 29.2 / 29.5 m/s^2 real-car maxima lie inside the resulting envelope.
//
// Conventions: SI units, ISO 8855 vehicle axes (x forward, y left, z up), wheel order FL, FR, RL,
// RR.
#pragma once

#include <cmath>
#include <numbers>
#include <string>

#include "params/schema/field.h"
#include "params/schema/tire_params.h"
#include "params/schema/vehicle_actuator_params.h"
#include "params/schema/vehicle_powertrain_params.h"

namespace scw::params {

/// Rigid body, geometry and load transfer.
struct ChassisParams {
  double mass = 720.0;
  double yaw_inertia = 1000.0;
  double wheelbase = 3.115;
  double cg_to_front_axle = 1.786;
  double track_front = 1.6;
  double track_rear = 1.6;
  double cg_height = 0.342;
  double roll_stiffness_share_front = 0.5;
  double load_transfer_time_constant = 0.04;
  double load_transfer_frequency = 0.0;
  double load_transfer_damping_ratio = 0.4;
  double gravity = 9.81;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.mass, {.key = "mass",
                     .unit = "kg",
                     .lo = 100.0,
                     .hi = 5000.0,
                     .doc = "Total mass incl. wheels, fuel and autonomy kit. EAV24: 720 kg "
                            "(assumption between the A2RL team models 692-750 kg; SF23 minimum "
                            "650 kg without driver, spec §4.6)."});
    v.Field(s.yaw_inertia, {.key = "yaw_inertia",
                            .unit = "kg*m^2",
                            .lo = 10.0,
                            .hi = 10000.0,
                            .doc = "Yaw moment of inertia I_z about the CoG. EAV24: 1000 "
                                   "(assumption; unknown, AV-21 800-1000, spec §4.6)."});
    v.Field(s.wheelbase, {.key = "wheelbase",
                          .unit = "m",
                          .lo = 0.5,
                          .hi = 6.0,
                          .doc = "Wheelbase l. EAV24: 3.115 m (EAV25 set, spec §4.4)."});
    v.Field(s.cg_to_front_axle,
            {.key = "cg_to_front_axle",
             .unit = "m",
             .lo = 0.1,
             .hi = 5.0,
             .doc = "Distance l_f from the CoG to the front axle (l_r = l - l_f). EAV24: 1.786 m "
                    "(EAV25 set, spec §4.4), i.e. 42.7 % static front load."});
    v.Field(s.track_front, {.key = "track_front",
                            .unit = "m",
                            .lo = 0.5,
                            .hi = 3.0,
                            .doc = "Front track width b_f. EAV24: 1.6 m (EAV25 set)."});
    v.Field(s.track_rear,
            {.key = "track_rear",
             .unit = "m",
             .lo = 0.5,
             .hi = 3.0,
             .doc = "Rear track width b_r. EAV24: 1.6 m (EAV25 set gives one track)."});
    v.Field(s.cg_height, {.key = "cg_height",
                          .unit = "m",
                          .lo = 0.0,
                          .hi = 2.0,
                          .doc = "CoG height h above ground, lever of the load transfer. EAV24: "
                                 "0.342 m (EAV25 set)."});
    v.Field(s.roll_stiffness_share_front,
            {.key = "roll_stiffness_share_front",
             .lo = 0.0,
             .hi = 1.0,
             .doc = "Share of the lateral load transfer m a_y h taken by the front axle (roll "
                    "stiffness distribution incl. roll-centre effects, lumped). 0.5 as in the "
                    "public gg sets of both cars (epsilon, spec §4.2/4.4). Higher = more "
                    "understeer."});
    v.Field(s.load_transfer_time_constant,
            {.key = "load_transfer_time_constant",
             .unit = "s",
             .lo = 0.001,
             .hi = 1.0,
             .doc = "First-order lag of the accelerations that drive the quasi-static load "
                    "transfer; stands in for the roll/pitch modes when they are not modelled "
                    "(stiff race-car suspension, 3-4 Hz, well damped: 0.04 s, assumption) and "
                    "breaks the algebraic loop load -> tyre force -> acceleration -> load. Used "
                    "when load_transfer_frequency is 0."});
    v.Field(s.load_transfer_frequency,
            {.key = "load_transfer_frequency",
             .unit = "Hz",
             .lo = 0.0,
             .hi = 50.0,
             .doc = "Natural frequency of the body's roll and pitch modes. Above 0 the "
                    "accelerations that drive the load transfer follow a second-order mode "
                    "(this frequency, load_transfer_damping_ratio) instead of the first-order "
                    "lag, so the load transfer can overshoot as a sprung body does. 0 = the "
                    "first-order lag (default). AV-21 suspension data (TUM sim_vehicle_dynamics, "
                    "springs and tyres in series, dampers, front anti-roll bar): roll 7.4 Hz, "
                    "pitch 6.5 Hz; EAV24 unknown. At most 0.1 / (2 pi simulation.time_step): "
                    "15.9 Hz at the 1 ms step.",
             .optional = true});
    v.Field(s.load_transfer_damping_ratio,
            {.key = "load_transfer_damping_ratio",
             .lo = 0.05,
             .hi = 2.0,
             .doc = "Damping ratio of the roll and pitch modes (with load_transfer_frequency > "
                    "0). AV-21 suspension data: 0.39 roll, 0.40 pitch; 0.4 (assumption for the "
                    "EAV24).",
             .optional = true});
    v.Field(s.gravity, {.key = "gravity",
                        .unit = "m/s^2",
                        .lo = 1.0,
                        .hi = 20.0,
                        .doc = "Gravitational acceleration."});
  }
  static void CrossCheck(const ChassisParams& p, Problems& pr) {
    if (!(p.cg_to_front_axle < p.wheelbase))
      pr.Add("cg_to_front_axle", "must be shorter than the wheelbase");
  }
};

/// Aerodynamic drag, downforce and (in wind only) side force, from the car's velocity relative to
/// the air (plant/vehicle/vehicle.h). No ride-height or pitch dependence.
struct AeroParams {
  double air_density = 1.225;
  double drag_area = 1.27;
  double downforce_area_front = 1.681;
  double downforce_area_rear = 2.379;
  double side_force_area = 1.2;
  double side_force_arm = -0.3;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.air_density, {.key = "air_density",
                            .unit = "kg/m^3",
                            .lo = 0.5,
                            .hi = 2.0,
                            .doc = "Air density rho (ISA 1.225; the public fits use it)."});
    v.Field(s.drag_area, {.key = "drag_area",
                          .unit = "m^2",
                          .lo = 0.0,
                          .hi = 10.0,
                          .doc = "c_D A: drag F = 1/2 rho c_D A u_x |u_x| along the body x-axis at "
                                 "the CoG; u_x = v_x - w_x is the longitudinal air speed (w_x: "
                                 "the wind's body-frame component, 0 in still air). EAV24: 1.27 "
                                 "m^2 (EAV25 set, spec §4.4)."});
    v.Field(s.downforce_area_front,
            {.key = "downforce_area_front",
             .unit = "m^2",
             .lo = 0.0,
             .hi = 20.0,
             .doc = "-c_Lf A: downforce on the front axle 1/2 rho (-c_Lf A) u_x^2 (u_x as for "
                    "drag), split equally over both wheels. EAV24: 1.681 m^2 (EAV25 set)."});
    v.Field(s.downforce_area_rear,
            {.key = "downforce_area_rear",
             .unit = "m^2",
             .lo = 0.0,
             .hi = 20.0,
             .doc = "-c_Lr A: downforce on the rear axle. EAV24: 2.379 m^2 (EAV25 set; total "
                    "4.06 m^2, 41 % front)."});
    v.Field(
        s.side_force_area,
        {.key = "side_force_area",
         .unit = "m^2",
         .lo = 0.0,
         .hi = 10.0,
         .doc = "c_Y A: aerodynamic side force from wind, F_y = 1/2 rho c_Y A w_y |u_r| at "
                "the centre of pressure (w_y: the wind's body-frame lateral component, u_r: "
                "the car's velocity relative to the air). Zero without wind: the still-air "
                "side force of the car's own side slip (~0.1 kN at 50 m/s and 3 deg) is left "
                "out, as in the still-air model. EAV24: 1.2 m^2, assumption (no public data): "
                "side area of an open-wheel single-seater ~1.3 m^2 (length ~5 m x ~0.4 m mean "
                "side height incl. wheels, cockpit and engine cover) times c_Y ~0.8-1.0. Scale: "
                "a 15 m/s crosswind at 50 m/s gives 0.58 kN (0.08 g).",
         .optional = true});
    v.Field(s.side_force_arm,
            {.key = "side_force_arm",
             .unit = "m",
             .lo = -3.0,
             .hi = 3.0,
             .doc = "Distance of the side force's centre of pressure ahead of the CoG (negative: "
                    "behind); yaw moment M_z = F_y * arm. EAV24: -0.3 m, assumption (no public "
                    "data): slightly behind the CoG because of the engine cover and fin. It lies "
                    "behind the plant's neutral steer point, so a crosswind first pushes the car "
                    "downwind, then turns its nose into the wind (at 0 m it turns away).",
             .optional = true});
  }
};

/// Wheel inertia, effective rolling radius, rolling resistance.
struct WheelParams {
  double radius_front = 0.307;
  double radius_rear = 0.307;
  double inertia_front = 1.2;
  double inertia_rear = 1.5;
  double rolling_resistance = 0.015;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.radius_front, {.key = "radius_front",
                             .unit = "m",
                             .lo = 0.1,
                             .hi = 1.0,
                             .doc = "Effective rolling radius r_e of a front wheel (slip and "
                                    "torque lever). EAV24: 0.307 m (A2RL team, spec §4.5)."});
    v.Field(s.radius_rear, {.key = "radius_rear",
                            .unit = "m",
                            .lo = 0.1,
                            .hi = 1.0,
                            .doc = "Effective rolling radius of a rear wheel. EAV24: 0.307 m (both "
                                   "tyres are 620 mm diameter)."});
    v.Field(s.inertia_front, {.key = "inertia_front",
                              .unit = "kg*m^2",
                              .lo = 0.05,
                              .hi = 20.0,
                              .doc = "Spin inertia of a front wheel incl. tyre, disc, hub. EAV24: "
                                     "1.2 (assumption; AV-21 1.35)."});
    v.Field(s.inertia_rear, {.key = "inertia_rear",
                             .unit = "kg*m^2",
                             .lo = 0.05,
                             .hi = 20.0,
                             .doc = "Spin inertia of a rear wheel incl. half shaft. EAV24: 1.5 "
                                    "(assumption; wider 360 mm tyre)."});
    v.Field(s.rolling_resistance,
            {.key = "rolling_resistance",
             .lo = 0.0,
             .hi = 0.1,
             .doc = "Rolling-resistance coefficient c_rr: a friction torque c_rr F_z r_e on each "
                    "wheel (never reverses it). 0.015 = QSY1 of the AV-21 tyre (spec §4.1)."});
  }
};

/// Both axles' tyre coefficients plus the shared slip kinematics.
struct TireSetParams {
  Mf52Params front;
  Mf52Params rear = Eav24RearTire();
  TireKinematicsParams kinematics;
  std::string grip_scaling = "peak";  ///< peak | curve

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Nested("front", s.front);
    v.Nested("rear", s.rear);
    v.Nested("kinematics", s.kinematics);
    v.Field(s.grip_scaling,
            {.key = "grip_scaling",
             .doc = "How a friction scaling (grip.*, a road's friction) acts on a tyre: peak = on "
                    "the friction coefficients (LMUX/LMUY: the peak and the sliding force scale, "
                    "the slip stiffness stays, so the peak moves to a smaller slip); curve = on "
                    "the whole force curve (the slip stiffness scales too: the force at every "
                    "slip is the nominal one times the factor, as Open Car Dynamics' per-wheel "
                    "friction scaling multiplies the tyre's output force).",
             .optional = true,
             .choices = "peak|curve",
             .omit_default = true});
  }
};

/// Fixed-step integrator.
struct SimulationParams {
  double time_step = 0.001;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.time_step,
            {.key = "time_step",
             .unit = "s",
             .lo = 1e-5,
             .hi = 0.005,
             .doc = "Fixed plant step h. 1 ms by default; the step-convergence test shows that "
                    "halving it changes lap-relevant quantities by far less than 0.5 %. Delays "
                    "are rounded to whole steps. Use a divisor of the controller period."});
  }
};

struct VehicleParams {
  std::string name = "eav24";
  ChassisParams chassis;
  AeroParams aero;
  WheelParams wheels;
  TireSetParams tires;
  GripParams grip;
  EngineParams engine;
  GearboxParams gearbox;
  DifferentialParams differential;
  BrakeParams brakes;
  SteeringParams steering;
  SensorParams sensors;
  SimulationParams simulation;

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.name, {.key = "name", .doc = "Short name of the parameter set (logs, reports)."});
    v.Nested("chassis", s.chassis);
    v.Nested("aero", s.aero);
    v.Nested("wheels", s.wheels);
    v.Nested("tires", s.tires);
    v.Nested("grip", s.grip);
    v.Nested("engine", s.engine);
    v.Nested("gearbox", s.gearbox);
    v.Nested("differential", s.differential);
    v.Nested("brakes", s.brakes);
    v.Nested("steering", s.steering);
    v.Nested("sensors", s.sensors);
    v.Nested("simulation", s.simulation);
  }
  static void CrossCheck(const VehicleParams& p, Problems& pr) {
    // Shifts must be possible without the limiter cutting in first.
    for (double up : p.gearbox.upshift_rpm)
      if (up > p.engine.rev_limit_rpm + p.engine.rev_limiter_band_rpm) {
        pr.Add("gearbox.upshift_rpm", "an upshift speed lies above the rev limiter band");
        break;
      }
    // Delays are held in ring buffers of whole steps; keep them a manageable size.
    const double h = p.simulation.time_step;
    if (h > 0 && (p.brakes.delay / h > 100000.0 || p.steering.delay / h > 100000.0))
      pr.Add("simulation.time_step", "delay / time_step exceeds 100000 steps");
    // The roll/pitch modes are stepped explicitly (symplectic Euler: stable for omega_n h < 2);
    // keep ten steps per radian of the mode so that its overshoot and period stay right.
    if (h > 0 && 2.0 * std::numbers::pi * p.chassis.load_transfer_frequency * h > 0.1)
      pr.Add("chassis.load_transfer_frequency",
             "2 pi * frequency * simulation.time_step must be at most 0.1 (the roll/pitch modes "
             "need at least ten plant steps per radian)");
  }
};

}  // namespace scw::params
