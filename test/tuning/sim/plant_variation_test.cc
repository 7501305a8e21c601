// The scenario's plant section (tuning/sim/plant_variation.h): identity at the defaults, the
// brake dead time at a fixed total response, the paper's simulator's actuators, the rear tyre's
// fall-off, the yaw inertia, and the section as scenario keys (files, --set, Monte-Carlo draws,
// resolution: only the simulated car changes).
#include "tuning/sim/plant_variation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <string>

#include "params/io/write.h"
#include "plant/actuator/actuators.h"
#include "plant/tire/magic_formula.h"
#include "plant/vehicle/vehicle.h"
#include "tuning/sim/scenario.h"
#include "tuning/sim/scenario_set.h"

namespace scw::tuning {
namespace {

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "<no error>";
}

bool Contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(PlantVariationTest, DefaultsAreTheVehicleBitForBit) {
  const params::VehicleParams v;
  const params::VehicleParams out = ApplyPlantVariation(v, params::PlantVariationParams{});
  EXPECT_EQ(params::ToPlainYaml(out), params::ToPlainYaml(v));  // shortest round-trip text
  // Explicit values that mean "as the vehicle file" are the identity too.
  params::PlantVariationParams same;
  same.actuators = "vehicle";
  same.brake_dead_time = -0.5;
  same.steering_delay = -1.0;
  EXPECT_EQ(params::ToPlainYaml(ApplyPlantVariation(v, same)), params::ToPlainYaml(v));
}

TEST(PlantVariationTest, DeadTimeKeepsTheTotalResponseWithinOneStep) {
  const params::VehicleParams v;
  const double h = v.simulation.time_step;
  const double total = plant::BrakeStepResponseTime(v.brakes, h);
  EXPECT_NEAR(total, 0.150, 1e-9);  // the EAV24's 150 ms (paper: "about 150 ms")
  const DeadTimeRange range = FeasibleBrakeDeadTimes(v.brakes, h);
  EXPECT_NEAR(range.max, 0.121, 1e-9);  // 150 ms - 29 steps of 1.8 bar to reach 50.6 bar
  double last_lag = 2.0;
  for (double d : {0.0, 0.03, 0.06, 0.09, 0.116, 0.121}) {
    params::PlantVariationParams p;
    p.brake_dead_time = d;
    const params::VehicleParams out = ApplyPlantVariation(v, p);
    EXPECT_EQ(out.brakes.delay, d);
    EXPECT_NEAR(plant::BrakeStepResponseTime(out.brakes, h), total, 0.5 * h) << d;
    EXPECT_LT(out.brakes.time_constant, last_lag) << "a longer dead time leaves a shorter lag";
    last_lag = out.brakes.time_constant;
    // Everything else is the vehicle's.
    params::VehicleParams back = out;
    back.brakes.delay = v.brakes.delay;
    back.brakes.time_constant = v.brakes.time_constant;
    EXPECT_EQ(params::ToPlainYaml(back), params::ToPlainYaml(v));
  }
  // The vehicle's own dead time is the vehicle file bit for bit (a sweep over dead times that
  // includes it reproduces the baseline run).
  params::PlantVariationParams own;
  own.brake_dead_time = v.brakes.delay;
  EXPECT_EQ(params::ToPlainYaml(ApplyPlantVariation(v, own)), params::ToPlainYaml(v));
  // A 30 ms dead time needs about a 120 ms lag (the measured alternative split).
  own.brake_dead_time = 0.03;
  EXPECT_NEAR(ApplyPlantVariation(v, own).brakes.time_constant, 0.12, 0.005);
}

TEST(PlantVariationTest, InfeasibleDeadTimeNamesTheKeyAndTheRange) {
  params::PlantVariationParams p;
  p.brake_dead_time = 0.13;
  const std::string e = ErrorOf([&] { ApplyPlantVariation(params::VehicleParams{}, p); });
  EXPECT_TRUE(Contains(e, "plant.brake_dead_time: 0.13 s is outside the feasible range 0-0.121 s"))
      << e;
  EXPECT_TRUE(Contains(e, "total response (63 % of an 80 bar step) is 0.15 s")) << e;
  // The paper's simulator's brakes respond within two steps: no dead time fits.
  p.actuators = "paper_sim";
  p.brake_dead_time = 0.01;
  EXPECT_TRUE(Contains(ErrorOf([&] { ApplyPlantVariation(params::VehicleParams{}, p); }),
                       "plant.brake_dead_time: 0.01 s is outside the feasible range 0-0 s"));
}

TEST(PlantVariationTest, EveryProblemOfTheSectionIsListedBeforeAnythingIsApplied) {
  params::PlantVariationParams p;
  p.brake_dead_time = 0.13;
  p.rear_tire_falloff = 40.0;
  const std::string e = ErrorOf([&] { ApplyPlantVariation(params::VehicleParams{}, p); });
  EXPECT_TRUE(Contains(e, "plant.brake_dead_time: 0.13 s is outside")) << e;
  EXPECT_TRUE(Contains(e, "plant.rear_tire_falloff: 40 is outside the feasible range")) << e;
  EXPECT_LT(e.find("plant.brake_dead_time"), e.find("plant.rear_tire_falloff")) << e;
  // An unknown actuator model is named; the dead time is not judged against a model it lacks.
  p.actuators = "ocd";
  const std::string u = ErrorOf([&] { ApplyPlantVariation(params::VehicleParams{}, p); });
  EXPECT_TRUE(Contains(u, "plant.actuators: 'ocd' is not one of vehicle|paper_sim|paper_sim_v1"))
      << u;
  EXPECT_FALSE(Contains(u, "plant.brake_dead_time")) << u;
  EXPECT_TRUE(Contains(u, "plant.rear_tire_falloff")) << u;
}

TEST(PlantVariationTest, PaperSimAppliesTheDocumentedValues) {
  const params::VehicleParams v;
  params::PlantVariationParams p;
  p.actuators = "paper_sim";
  const params::VehicleParams out = ApplyPlantVariation(v, p);
  EXPECT_EQ(out.brakes.delay, 0.0);
  EXPECT_EQ(out.brakes.time_constant, 0.0);
  EXPECT_EQ(out.brakes.rate_limit, 100000.0);
  EXPECT_EQ(out.brakes.torque_gain_front, v.brakes.torque_gain_front);
  EXPECT_EQ(out.brakes.max_pressure, v.brakes.max_pressure);
  EXPECT_EQ(out.steering.delay, 0.06);
  EXPECT_EQ(out.steering.time_constant, 0.06);
  EXPECT_EQ(out.steering.rate_limit, 0.5);
  EXPECT_EQ(out.steering.max_angle, v.steering.max_angle);
  // No brake-pressure dynamics: an 80 bar step is there within the 100 bar-per-step rate.
  EXPECT_LE(plant::BrakeStepResponseTime(out.brakes, v.simulation.time_step),
            v.simulation.time_step + 1e-12);
  EXPECT_TRUE(params::Validate(out).empty());
  // The steering delay overrides either model's.
  p.steering_delay = 0.03;
  EXPECT_EQ(ApplyPlantVariation(v, p).steering.delay, 0.03);
  p.actuators = "vehicle";
  p.steering_delay = 0.0;
  EXPECT_EQ(ApplyPlantVariation(v, p).steering.delay, 0.0);
}

TEST(PlantVariationTest, PaperSimV1AppliesTheIv2024Values) {
  const params::VehicleParams v;
  params::PlantVariationParams p;
  p.actuators = "paper_sim_v1";
  const params::VehicleParams out = ApplyPlantVariation(v, p);
  EXPECT_EQ(out.brakes.delay, 0.01);
  EXPECT_EQ(out.brakes.time_constant, 0.03);
  EXPECT_EQ(out.brakes.rate_limit, 100000.0);
  EXPECT_EQ(out.brakes.torque_gain_rear, v.brakes.torque_gain_rear);
  EXPECT_EQ(out.steering.delay, 0.05);
  EXPECT_EQ(out.steering.time_constant, 0.05);
  EXPECT_EQ(out.steering.rate_limit, 1.0);
  EXPECT_EQ(out.steering.max_angle, v.steering.max_angle);
  EXPECT_TRUE(params::Validate(out).empty());
  // 10 ms dead time + 30 ms PT1: 63 % of an 80 bar step after 40 ms, between the paper's
  // current simulator (one step) and the real car (150 ms).
  EXPECT_NEAR(plant::BrakeStepResponseTime(out.brakes, v.simulation.time_step), 0.04,
              2 * v.simulation.time_step);
  // Its own split is a feasible dead time; the 150 ms of the real car is not.
  p.brake_dead_time = 0.01;
  EXPECT_EQ(ApplyPlantVariation(v, p).brakes.time_constant, 0.03);
  p.brake_dead_time = 0.05;
  EXPECT_TRUE(Contains(ErrorOf([&] { ApplyPlantVariation(v, p); }),
                       "plant.brake_dead_time: 0.05 s is outside the feasible range"));
}

TEST(PlantVariationTest, YawInertiaScales) {
  params::PlantVariationParams p;
  p.yaw_inertia_scale = 1.2;
  const params::VehicleParams v;
  EXPECT_EQ(ApplyPlantVariation(v, p).chassis.yaw_inertia, v.chassis.yaw_inertia * 1.2);
  p.yaw_inertia_scale = 0.8;
  EXPECT_EQ(ApplyPlantVariation(v, p).chassis.yaw_inertia, v.chassis.yaw_inertia * 0.8);
}

// plant.grip_scaling: "vehicle" keeps the vehicle file's; peak/curve set it. With "curve" the
// simulated car's rear wheels (rear_mu_y 0.8) get the factor on the cornering stiffness too, the
// front ones nothing; the planner's and the stability node's vehicle keep the file's reading.
TEST(PlantVariationTest, GripScalingChoosesHowTheGripFactorsAct) {
  const params::VehicleParams v;
  ASSERT_EQ(v.tires.grip_scaling, "peak");
  params::PlantVariationParams p;
  EXPECT_EQ(ApplyPlantVariation(v, p).tires.grip_scaling, "peak");
  p.grip_scaling = "curve";
  EXPECT_EQ(ApplyPlantVariation(v, p).tires.grip_scaling, "curve");
  params::VehicleParams file = v;
  file.tires.grip_scaling = "curve";
  p.grip_scaling = "vehicle";
  EXPECT_EQ(ApplyPlantVariation(file, p).tires.grip_scaling, "curve");

  const ResolvedScenario peak = Resolve(DefaultScenario({"grip.rear_mu_y=0.8"}));
  const ResolvedScenario curve =
      Resolve(DefaultScenario({"grip.rear_mu_y=0.8", "plant.grip_scaling=curve"}));
  EXPECT_EQ(curve.plant_vehicle.tires.grip_scaling, "curve");
  EXPECT_EQ(curve.vehicle.tires.grip_scaling, "peak");  // the car's software: the vehicle file
  const plant::Vehicle a(peak.plant_vehicle), b(curve.plant_vehicle);
  const double fz = v.tires.rear.fnomin, alpha = 0.002;
  for (std::size_t i = 0; i < 4; ++i) {
    const bool rear = i >= 2;
    const plant::TireInput ia = a.WheelTireInput(i, fz, 0.0, alpha);
    const plant::TireInput ib = b.WheelTireInput(i, fz, 0.0, alpha);
    EXPECT_EQ(ia.stiffness_y, 1.0);
    EXPECT_EQ(ib.stiffness_y, rear ? 0.8 : 1.0) << i;
    EXPECT_EQ(ib.lambda_mu_y, ia.lambda_mu_y);
    const auto& t = rear ? v.tires.rear : v.tires.front;
    const double fa = plant::TireForces(ia, t).fy, fb = plant::TireForces(ib, t).fy;
    EXPECT_NEAR(fb / fa, rear ? 0.8 : 1.0, rear ? 0.01 : 1e-12) << i;
  }
  EXPECT_TRUE(Contains(ErrorOf([] { (void)DefaultScenario({"plant.grip_scaling=both"}); }),
                       "plant.grip_scaling"));
}

// Lateral force of the rear tyre at nominal load and slip angle a [rad].
double RearFy(const params::Mf52Params& t, double a) {
  return plant::TireForces({t.fnomin, 0.0, a, 1.0, 1.0}, t).fy;
}

double PeakFy(const params::Mf52Params& t) {
  double peak = 0.0;
  for (int i = 1; i <= 600; ++i) peak = std::max(peak, RearFy(t, 0.001 * i));
  return peak;
}

TEST(PlantVariationTest, RearTyreFalloffScalesTheLossBeyondThePeak) {
  const params::Mf52Params rear = params::VehicleParams{}.tires.rear;
  EXPECT_EQ(params::ToPlainYaml(WithFalloff(rear, 1.0)), params::ToPlainYaml(rear));
  // The slip angle of the lateral peak (scanned at 1 mrad).
  double peak = 0.0, a_peak = 0.0;
  for (int i = 1; i <= 600; ++i)
    if (RearFy(rear, 0.001 * i) > peak) peak = RearFy(rear, 0.001 * i), a_peak = 0.001 * i;
  ASSERT_GT(a_peak, 0.02);
  ASSERT_LT(a_peak, 0.3);
  for (double s : {0.0, 0.5, 1.5, 2.0}) {
    const params::Mf52Params t = WithFalloff(rear, s);
    EXPECT_EQ(t.falloff, s);
    EXPECT_EQ(t.pcy1, rear.pcy1);  // the fit's coefficients stay
    EXPECT_EQ(t.pcx1, rear.pcx1);
    // Up to the peak the curve is the fit's, bit for bit; beyond it the loss is scaled by s.
    for (int i = 1; i <= 600; ++i) {
      const double a = 0.001 * i;
      if (a < a_peak - 0.002) {
        EXPECT_EQ(RearFy(t, a), RearFy(rear, a)) << s << " " << a;
      } else if (a > a_peak + 0.002) {
        EXPECT_NEAR(RearFy(t, a), peak - s * (peak - RearFy(rear, a)), 1e-5 * peak)
            << s << " " << a;
      }
    }
    EXPECT_NEAR(PeakFy(t) / peak, 1.0, 1e-5) << s;  // both scanned at 1 mrad
    // The longitudinal curve too: at 50 % slip the force has lost s times the fit's loss.
    const auto fx = [](const params::Mf52Params& tt, double k) {
      return plant::TireForces({tt.fnomin, k, 0.0, 1.0, 1.0}, tt).fx;
    };
    const double dx = plant::PeakFriction(rear.fnomin, 1, 1, rear).mu_x * rear.fnomin;
    EXPECT_NEAR(fx(t, 0.5), dx - s * (dx - fx(rear, 0.5)), 1e-6 * dx) << s;
    EXPECT_EQ(fx(t, 0.01), fx(rear, 0.01)) << s;
  }
  // At large slip the force falls with the fall-off.
  double last = 1e9;
  for (double s : {0.0, 0.5, 1.0, 1.5, 2.0}) {
    const double fy = RearFy(WithFalloff(rear, s), 0.35);  // 20 deg
    EXPECT_LT(fy, last) << s;
    last = fy;
  }
  // The vehicle file's own fall-off is checked when the file is read (tires.<axle>.falloff).
  params::Mf52Params bad = rear;
  bad.falloff = 2.5;
  const auto items = params::Validate(bad, "tires.rear").items();
  ASSERT_EQ(items.size(), 1u);
  EXPECT_EQ(items[0].path, "tires.rear.falloff");
  EXPECT_TRUE(Contains(items[0].message, "(PCX1 1.6144: falloff < 2.32)")) << items[0].message;
  bad.falloff = 2.3;
  EXPECT_TRUE(params::Validate(bad, "tires.rear").empty());
  // The vehicle file's own fall-off is scaled, not replaced.
  params::Mf52Params half = rear;
  half.falloff = 0.5;
  EXPECT_EQ(WithFalloff(half, 2.0).falloff, 1.0);
  EXPECT_TRUE(Contains(ErrorOf([&] { WithFalloff(half, 4.7); }), "0 <= falloff < 4.6")) << "";
  // Beyond 1 / (1 - sin(C pi/2)) = 2.43 the sliding force would be negative.
  const std::string e = ErrorOf([&] { WithFalloff(rear, 2.5); });
  EXPECT_TRUE(Contains(e,
                       "plant.rear_tire_falloff: 2.5 is outside the feasible range "
                       "0 <= falloff < 2.32"))
      << e;  // PCX1 1.6144 is the tighter one
  params::Mf52Params no_peak = rear;
  no_peak.pcy1 = 0.9;
  EXPECT_TRUE(Contains(ErrorOf([&] { WithFalloff(no_peak, 0.5); }), "only 1 is accepted"));
  EXPECT_NO_THROW(WithFalloff(no_peak, 1.0));
}

TEST(PlantVariationTest, SectionIsAScenarioKeyPrintedOnlyWhenSet) {
  const params::ScenarioParams def = DefaultScenario();
  EXPECT_FALSE(Contains(params::ToPlainYaml(def), "plant:"));
  const params::ScenarioParams set = DefaultScenario(
      {"plant.actuators=paper_sim", "plant.brake_dead_time=0.06", "plant.yaw_inertia_scale=1.1"});
  EXPECT_EQ(set.plant.actuators, "paper_sim");
  EXPECT_EQ(set.plant.brake_dead_time, 0.06);
  const std::string text = params::ToPlainYaml(set);
  EXPECT_TRUE(Contains(text,
                       "plant:\n  actuators: \"paper_sim\"\n  brake_dead_time: 0.06\n"
                       "  yaw_inertia_scale: 1.1\n"))
      << text;
  EXPECT_TRUE(Contains(ErrorOf([] { DefaultScenario({"plant.actuators=ocd"}); }),
                       "plant.actuators: 'ocd' is not one of vehicle|paper_sim"));
  EXPECT_TRUE(Contains(ErrorOf([] { DefaultScenario({"plant.yaw_inertia_scale=2"}); }),
                       "plant.yaw_inertia_scale: 2 is above the upper bound 1.5"));
}

TEST(PlantVariationTest, MonteCarloBlocksDrawThePlantKeys) {
  const ScenarioSet s = ScenarioSet::FromYamlText(
      "training:\n"
      "  - monte_carlo:\n"
      "      name: robust\n"
      "      count: 8\n"
      "      seed: 3\n"
      "      vary:\n"
      "        plant.brake_dead_time: {uniform: [0.03, 0.116], step: 0.001}\n"
      "        plant.steering_delay: {uniform: [0.02, 0.06], step: 0.005}\n"
      "        plant.rear_tire_falloff: {uniform: [0.5, 1.5]}\n"
      "        plant.yaw_inertia_scale: {uniform: [0.8, 1.2]}\n"
      "      grid:\n"
      "        plant.actuators: [vehicle, paper_sim]\n"
      "held_out:\n  - {name: clean, set: [laps=1]}\n",
      "robust.yaml");
  ASSERT_EQ(s.training.size(), 16u);
  std::set<std::string> actuators;
  std::set<double> dead_times;
  for (const auto& e : s.training) {
    const params::ScenarioParams spec = LoadEntry(e, "");
    actuators.insert(spec.plant.actuators);
    dead_times.insert(spec.plant.brake_dead_time);
    EXPECT_GE(spec.plant.brake_dead_time, 0.03);
    EXPECT_LE(spec.plant.brake_dead_time, 0.116);
    EXPECT_GE(spec.plant.steering_delay, 0.02);
    EXPECT_LE(spec.plant.steering_delay, 0.06);
    EXPECT_GE(spec.plant.rear_tire_falloff, 0.5);
    EXPECT_LE(spec.plant.rear_tire_falloff, 1.5);
    EXPECT_GE(spec.plant.yaw_inertia_scale, 0.8);
    EXPECT_LE(spec.plant.yaw_inertia_scale, 1.2);
  }
  EXPECT_EQ(actuators, (std::set<std::string>{"vehicle", "paper_sim"}));
  EXPECT_GT(dead_times.size(), 4u);
}

TEST(PlantVariationTest, ResolveChangesOnlyTheSimulatedCar) {
  const ResolvedScenario base = Resolve(DefaultScenario({"laps=1"}));
  EXPECT_EQ(params::ToPlainYaml(base.plant_vehicle), params::ToPlainYaml(base.vehicle));
  const ResolvedScenario sc = Resolve(DefaultScenario(
      {"laps=1", "plant.yaw_inertia_scale=1.2", "plant.brake_dead_time=0.03", "plant_step=0.002"}));
  // The car's software knows the vehicle file: planner, vehicle constants, controller models.
  EXPECT_EQ(sc.vehicle.chassis.yaw_inertia, base.vehicle.chassis.yaw_inertia);
  EXPECT_EQ(sc.stability.vehicle.inertia.yaw, base.stability.vehicle.inertia.yaw);
  EXPECT_EQ(sc.ideal_lap_time, base.ideal_lap_time);
  // The plant is the varied car, at the scenario's plant step, with the lag found at the
  // vehicle's own step.
  EXPECT_EQ(sc.plant_vehicle.chassis.yaw_inertia, 1.2 * base.vehicle.chassis.yaw_inertia);
  EXPECT_EQ(sc.plant_vehicle.simulation.time_step, 0.002);
  EXPECT_EQ(sc.plant_vehicle.brakes.delay, 0.03);
  params::PlantVariationParams p;
  p.brake_dead_time = 0.03;
  EXPECT_EQ(sc.plant_vehicle.brakes.time_constant,
            ApplyPlantVariation(base.vehicle, p).brakes.time_constant);
  // A bad value names the scenario and the key.
  const std::string e = ErrorOf([] { Resolve(DefaultScenario({"plant.brake_dead_time=0.2"})); });
  EXPECT_TRUE(Contains(e, "scenario default: plant.brake_dead_time: 0.2 s is outside")) << e;
}

}  // namespace
}  // namespace scw::tuning
