// A scenario's variation of the simulated car (scenario key `plant`): which plant model simulates
// it (scw's reduced double track or Open-Car-Dynamics, the paper's simulator), which actuator
// model the plant runs (the real car's, from the vehicle file, or the paper's simulator's), and the
// plant quantities that the paper's claims and a robust scenario set vary: the split of the brake's
// response into dead time and lag, the steering dead time, the rear tyre's force beyond its peak,
// the yaw inertia, and how the scenario's grip factors act on the tyres.
//
// Only the simulated car changes: the planner, the motion controllers and the vehicle constants
// the stability node receives keep the vehicle file's values (the car's software does not know
// the plant it meets). Every field at its default leaves the run bit for bit as without the
// section, and a scenario file or printed scenario lists only the keys that differ from it.
// Applied by tuning/sim/plant_variation.h (ApplyPlantVariation); docs/plant-calibration.md,
// "Two actuator models", gives the sources and how to score a run against each.
#pragma once

#include <string>

#include "params/schema/field.h"

namespace scw::params {

struct PlantVariationParams {
  std::string model = "scw";
  std::string actuators = "vehicle";
  double brake_dead_time = -1.0;
  double steering_delay = -1.0;
  double rear_tire_falloff = 1.0;
  double yaw_inertia_scale = 1.0;
  std::string grip_scaling = "vehicle";

  template <class Self, class V>
  static void Visit(Self& s, V& v) {
    v.Field(s.model,
            {.key = "model",
             .doc = "Plant model of the simulated car: scw = scw's reduced double track "
                    "(plant/vehicle); ocd = Open-Car-Dynamics, the paper's simulator (sprung body "
                    "on springs, MF5.2 tyres, RWD with LSD), driven by scw's engine, gearbox, "
                    "brake and steering actuators and read by scw's sensors, with the vehicle "
                    "file mapped onto its parameters (docs/ocd-plant.md). ocd needs a build with "
                    "Open-Car-Dynamics (CMake option SCW_WITH_OCD); a vehicle value it cannot "
                    "represent (a tyre fall-off other than 1, other slip kinematics) is an error.",
             .optional = true,
             .choices = "scw|ocd",
             .omit_default = true});
    v.Field(
        s.actuators,
        {.key = "actuators",
         .doc = "Actuator model of the simulated car: vehicle = the vehicle file's brakes and "
                "steering (the real car: brake dead time + lag + rate limit, about 150 ms to "
                "63 %); paper_sim = the paper's simulator, Open Car Dynamics (no brake-pressure "
                "dynamics: the requested pressure acts at once; steering 60 ms dead time, PT1 "
                "60 ms, 0.5 rad/s: the simulator's shipped defaults); paper_sim_v1 = the same "
                "simulator as its IV-2024 code had it (longitudinal request 10 ms dead time + "
                "PT1 30 ms; steering 50 ms, PT1 50 ms, 1.0 rad/s), values and sources in "
                "tuning/sim/plant_variation.h and docs/plant-calibration.md.",
         .optional = true,
         .choices = "vehicle|paper_sim|paper_sim_v1",
         .omit_default = true});
    v.Field(s.brake_dead_time,
            {.key = "brake_dead_time",
             .unit = "s",
             .lo = -1.0,
             .hi = 1.0,
             .doc = "Brake pure delay at a fixed total response: the lag (brakes.time_constant) is "
                    "recomputed so that delay + lag + rate limit still reach 63 % of an 80 bar "
                    "step at the total response time of the selected actuators (`scw vehicle "
                    "balance`; 150 ms for the EAV24). Feasible from 0 to that time minus what the "
                    "rate limit alone needs (about 29 ms for the EAV24: 0-121 ms); outside is an "
                    "error naming the range. The actuators' own dead time (or a negative value) "
                    "keeps their own split bit for bit.",
             .optional = true,
             .omit_default = true});
    v.Field(s.steering_delay,
            {.key = "steering_delay",
             .unit = "s",
             .lo = -1.0,
             .hi = 1.0,
             .doc = "Steering pure delay (lag and rate limit unchanged), rounded to whole plant "
                    "steps. Negative = the selected actuators' own (vehicle: 0.03 s, the paper's "
                    "real car; paper_sim: 0.06 s; paper_sim_v1: 0.05 s).",
             .optional = true,
             .omit_default = true});
    v.Field(s.rear_tire_falloff,
            {.key = "rear_tire_falloff",
             .unit = "-",
             .lo = 0.0,
             .hi = 3.0,
             .doc = "Scale of the rear tyre's force loss beyond its peak, lateral and "
                    "longitudinal (pure slip), on the vehicle file's (tires.rear.falloff): "
                    "beyond the slip of the peak the force is D - s (D - F_MF), F_MF the Magic "
                    "Formula's, so the curve up to the peak, the peak D and the slip stiffness "
                    "stay exactly. 0 = no loss (the force holds its peak), 1 = the vehicle file, "
                    "2 = twice the loss (EAV24: sliding force 59 % of the peak laterally at 1, "
                    "18 % at 2). Values at which the sliding force would reach zero are an error "
                    "naming the limit.",
             .optional = true,
             .omit_default = true});
    v.Field(s.yaw_inertia_scale,
            {.key = "yaw_inertia_scale",
             .unit = "-",
             .lo = 0.5,
             .hi = 1.5,
             .doc = "Multiplies the plant's yaw inertia (chassis.yaw_inertia); plausible range "
                    "0.8-1.2 (no EAV24 value is public; the estimate is 1000 kg*m^2).",
             .optional = true,
             .omit_default = true});
    v.Field(s.grip_scaling,
            {.key = "grip_scaling",
             .doc = "How the scenario's grip factors act on the simulated car's tyres "
                    "(tires.grip_scaling): vehicle = as the vehicle file says (peak for the "
                    "EAV24); peak = on the friction coefficients only, the slip stiffness stays "
                    "(grip.rear_mu_y 0.8: the rear's peak side force -20 %, reached at a smaller "
                    "slip angle); curve = on the whole force curve (the rear's side force -20 % at "
                    "every slip angle, its cornering stiffness too), as the paper's simulator's "
                    "per-wheel friction scaling multiplies the tyre force. Which one the paper's "
                    "'rear lateral grip reduced by 20 %' used is not published.",
             .optional = true,
             .choices = "vehicle|peak|curve",
             .omit_default = true});
  }
};

}  // namespace scw::params
