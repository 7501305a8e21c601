#include "plant/ocd/ocd_parameters.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <sstream>

namespace scw::plant::ocd {
namespace {

constexpr const char* kVd = "vehicle_dynamics_double_track.";
constexpr const char* kAero = "vehicle_dynamics_double_track.aerodynamics.";

// Public sources of the OCD-only values (the AV-21 "il" set of TUMFTM/sim_vehicle_dynamics @
// df2ae95d, extracted to ../shared/data/vehicles/sim_vehicle_dynamics_AV21/).
constexpr const char* kAv21 = "AV-21 'il' set (sim_vehicle_dynamics, data/vehicles README)";

// AV-21 'il' values (av21_il_vehicleparameters_vehdynsim.json).
constexpr double kAv21WheelMass = 15.0;             // tire*__INERTIAL__m_Wheel_kg
constexpr double kAv21RollInertia = 70.0;           // I_K_Vehicle_kgm2 [0]
constexpr double kAv21PitchInertia = 470.0;         // I_K_Vehicle_kgm2 [4]
constexpr double kAv21SpringFront = 191903.0;       // SUS__Compliance__cz_SpringRateFrRe_Npm
constexpr double kAv21SpringRear = 111694.0;        //
constexpr double kAv21DamperFront = 2152.7777;      // SUS__Compliance__Cz_DamperRateFrRe_Nspm
constexpr double kAv21DamperRear = 1377.777777;     //
constexpr double kAv21ArbTorsionFront = 6042.9752;  // SUS__Antisway__c_AntiSwayTSpringFrRe_Nmprad
constexpr double kAv21ArbArmFront = 0.482;          // SUS__Antisway__r_AntiSwayArmRadiusFrRe_m
constexpr double kAv21TireVertical = 240000.0;      // tire*__VERTICAL__VERTICAL_STIFFNESS

// The AV-21 suspension's roll stiffness per axle expressed as OCD's springs at half the track:
// spring c plus anti-roll bar; a bar of torsional stiffness k with arms of radius r pushes each
// wheel with k (z_L - z_R) / r^2, which is OCD's 0.5 c_ar (z_L - z_R) for c_ar = 2 k / r^2.
constexpr double kAv21ArbFront = 2.0 * kAv21ArbTorsionFront / (kAv21ArbArmFront * kAv21ArbArmFront);

std::string Upper(std::string_view key) {
  std::string s(key);
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// MF5.2 coefficients OCD declares that scw's fit leaves out, with the value the adapter gives
// them: camber terms 0 (the reduced plant's tyres have no camber, so they would not act anyway),
// the scaling factors 1 (the fit as it is).
struct Neutral {
  const char* name;
  double value;
  const char* why;
};
constexpr const char* kCamberWhy =
    "camber coefficient: scw's fit has none and OCD's camber is 0 here; 0 states it";
constexpr const char* kScaleWhy = "scaling factor scw's fit does not have: 1 keeps the fit";
constexpr const char* kUnusedWhy =
    "declared by OCD but not in its equations (its relaxation is the fixed 0.3/0.2 m lag, no "
    "inflation pressure); 0";
constexpr Neutral kNeutralTyre[] = {
    {"PDX3", 0.0, kCamberWhy}, {"RBX3", 0.0, kCamberWhy}, {"PDY3", 0.0, kCamberWhy},
    {"PEY4", 0.0, kCamberWhy}, {"PEY5", 0.0, kCamberWhy}, {"PKY3", 0.0, kCamberWhy},
    {"PKY5", 0.0, kCamberWhy}, {"PKY6", 0.0, kCamberWhy}, {"PKY7", 0.0, kCamberWhy},
    {"PHY3", 0.0, kCamberWhy}, {"PVY3", 0.0, kCamberWhy}, {"PVY4", 0.0, kCamberWhy},
    {"RBY4", 0.0, kCamberWhy}, {"RVY3", 0.0, kCamberWhy}, {"PTX1", 0.0, kUnusedWhy},
    {"PTX2", 0.0, kUnusedWhy}, {"PTX3", 0.0, kUnusedWhy}, {"PTY1", 0.0, kUnusedWhy},
    {"PTY2", 0.0, kUnusedWhy}, {"PPY1", 0.0, kUnusedWhy}, {"PPY2", 0.0, kUnusedWhy},
    {"PPY3", 0.0, kUnusedWhy}, {"PPY4", 0.0, kUnusedWhy}, {"PPY5", 0.0, kUnusedWhy},
    {"LFZO", 1.0, kScaleWhy},  {"LCX", 1.0, kScaleWhy},   {"LEX", 1.0, kScaleWhy},
    {"LHX", 1.0, kScaleWhy},   {"LVX", 1.0, kScaleWhy},   {"LGAX", 1.0, kScaleWhy},
    {"LCY", 1.0, kScaleWhy},   {"LEY", 1.0, kScaleWhy},   {"LKYG", 1.0, kScaleWhy},
    {"LHY", 1.0, kScaleWhy},   {"LVY", 1.0, kScaleWhy},   {"LGAY", 1.0, kScaleWhy},
    {"LTR", 1.0, kScaleWhy},   {"LRES", 1.0, kScaleWhy},  {"LGAZ", 1.0, kScaleWhy},
    {"LXAL", 1.0, kScaleWhy},  {"LYKA", 1.0, kScaleWhy},  {"LVYKA", 1.0, kScaleWhy},
    {"LS", 1.0, kScaleWhy},    {"LSGKP", 1.0, kScaleWhy}, {"LSGAL", 1.0, kScaleWhy},
    {"LGYR", 1.0, kScaleWhy},  {"LMX", 1.0, kScaleWhy},   {"LVMX", 1.0, kScaleWhy},
    {"LMY", 1.0, kScaleWhy}};

class Builder {
 public:
  void Scw(std::string name, double v, std::string source) {
    out_.push_back({std::move(name), {v}, std::move(source), false, ""});
  }
  void Scw(std::string name, std::vector<double> v, std::string source) {
    out_.push_back({std::move(name), std::move(v), std::move(source), false, ""});
  }
  void Own(std::string name, double v, std::string source, std::string why) {
    out_.push_back({std::move(name), {v}, std::move(source), true, std::move(why)});
  }
  void Own(std::string name, std::vector<double> v, std::string source, std::string why) {
    out_.push_back({std::move(name), std::move(v), std::move(source), true, std::move(why)});
  }
  std::vector<OcdParameter> Take() { return std::move(out_); }

 private:
  std::vector<OcdParameter> out_;
};

// Anti-roll bar stiffnesses [N/m] (OCD's virtual springs at half the track): the smallest
// non-negative pair that, added to the AV-21 springs, gives the vehicle file's front share of the
// roll stiffness, K_axle = (c + c_ar) b^2 / 2.
std::pair<double, double> AntiRollBars(const params::ChassisParams& c) {
  const double e = c.roll_stiffness_share_front;
  const double bf2 = 0.5 * c.track_front * c.track_front;
  const double br2 = 0.5 * c.track_rear * c.track_rear;
  const double kf = kAv21SpringFront * bf2, kr = kAv21SpringRear * br2;
  if (kf / (kf + kr) >= e) {
    const double kr_needed = kf * (1.0 - e) / e;
    return {0.0, (kr_needed - kr) / br2};
  }
  const double kf_needed = kr * e / (1.0 - e);
  return {(kf_needed - kf) / bf2, 0.0};
}

std::string Fmt(double x) {
  // Four significant digits for the table, the exact value stays in MapVehicle.
  std::ostringstream s;
  s.precision(6);
  s << x;
  return s.str();
}

}  // namespace

std::vector<OcdParameter> MapVehicle(const params::VehicleParams& p) {
  Builder b;
  const auto& c = p.chassis;
  const auto& d = p.differential;
  const bool spool = d.type == "spool";
  // Drivetrain (ocd_drivetrain_rwd_lsd_cpp).
  b.Scw("drivetrain.I_wheel_front_kgm2", p.wheels.inertia_front, "wheels.inertia_front");
  b.Scw("drivetrain.I_wheel_rear_kgm2", p.wheels.inertia_rear, "wheels.inertia_rear");
  b.Scw("drivetrain.transmission_ratio", p.gearbox.final_drive_ratio,
        "gearbox.final_drive_ratio (declared by OCD, not in its equations: the transmission "
        "torque comes from scw's engine and gearbox)");
  if (spool) {
    b.Scw("drivetrain.LSD_preload", kOcdSpoolPreload,
          "differential.type spool: a stiff preload stands in for the locked axle");
    b.Scw("drivetrain.LSD_lock_drive", 1.0, "differential.type spool");
    b.Scw("drivetrain.LSD_lock_coast", 1.0, "differential.type spool");
  } else {
    b.Scw("drivetrain.LSD_preload", d.lsd_preload, "differential.lsd_preload");
    b.Scw("drivetrain.LSD_lock_drive", d.lsd_lock_drive, "differential.lsd_lock_drive");
    b.Scw("drivetrain.LSD_lock_coast", d.lsd_lock_coast, "differential.lsd_lock_coast");
  }
  // The vehicle model's integration step (one DoPri45 step per scw plant step).
  b.Scw("integration_step_size_s", p.simulation.time_step, "simulation.time_step");

  // Vehicle dynamics (ocd_vehicle_dynamics_double_track_cpp).
  const std::string vd = kVd;
  b.Scw(vd + "mass_vehicle_kg", c.mass, "chassis.mass");
  b.Own(vd + "mass_wheel_kg.front", kAv21WheelMass, kAv21,
        "unsprung mass per corner; no EAV24 value is public (OCD's default is the same)");
  b.Own(vd + "mass_wheel_kg.rear", kAv21WheelMass, kAv21, "as front");
  b.Scw(vd + "moment_of_inertia_kgpm2.z", c.yaw_inertia, "chassis.yaw_inertia");
  b.Own(vd + "moment_of_inertia_kgpm2.y", kAv21PitchInertia, kAv21,
        "pitch inertia; scw's load transfer is quasi-static and has none");
  b.Own(vd + "moment_of_inertia_kgpm2.x", kAv21RollInertia, kAv21, "roll inertia, likewise");
  b.Scw(vd + "wheelbase_m", c.wheelbase, "chassis.wheelbase");
  b.Scw(vd + "track_width_m.front", c.track_front, "chassis.track_front");
  b.Scw(vd + "track_width_m.rear", c.track_rear, "chassis.track_rear");
  b.Scw(vd + "cog.distance_from_front_axle_m", c.cg_to_front_axle, "chassis.cg_to_front_axle");
  b.Scw(vd + "cog.height_m", c.cg_height, "chassis.cg_height");
  const char* centres_why =
      "0: all load transfer elastic through springs and bars, as scw's vehicle file describes it "
      "(CoG height and roll-stiffness split); a roll centre would route part of it through each "
      "axle's own side force. No public value";
  b.Own(vd + "suspension.pitch_center_height_m.accel", 0.0, "(none)", centres_why);
  b.Own(vd + "suspension.pitch_center_height_m.decel", 0.0, "(none)", centres_why);
  b.Own(vd + "suspension.roll_center_height_m", 0.0, "(none)", centres_why);
  b.Own(vd + "suspension.vehicle_spring_stiffness_Npm.front", kAv21SpringFront, kAv21,
        "wheel rate; no EAV24 value is public");
  b.Own(vd + "suspension.vehicle_spring_stiffness_Npm.rear", kAv21SpringRear, kAv21, "wheel rate");
  b.Own(vd + "suspension.vehicle_damper_coefficient_Nspm.front", kAv21DamperFront, kAv21,
        "damper rate");
  b.Own(vd + "suspension.vehicle_damper_coefficient_Nspm.rear", kAv21DamperRear, kAv21,
        "damper rate");
  const auto [arb_f, arb_r] = AntiRollBars(c);
  const std::string arb_source = "chassis.roll_stiffness_share_front with the AV-21 springs (" +
                                 Fmt(kAv21ArbFront) + " N/m front bar in the AV-21)";
  const char* arb_why =
      "the smallest non-negative bars that give the vehicle file's front share of the roll "
      "stiffness (c + c_ar) b^2/2 with the AV-21 springs";
  b.Own(vd + "suspension.antirollbar_virtual_spring_stiffness_Npm.front", arb_f, arb_source,
        arb_why);
  b.Own(vd + "suspension.antirollbar_virtual_spring_stiffness_Npm.rear", arb_r, arb_source,
        arb_why);
  const char* toe_why = "scw's plant has no toe or camber; 0 keeps the tyres at their fit";
  for (const char* w : kOcdWheelNames) {
    b.Own(vd + "suspension.toe_out_rad." + w, 0.0, "(none)", toe_why);
    b.Own(vd + "suspension.camber_out_rad." + w, 0.0, "(none)", toe_why);
  }
  b.Scw(vd + "tire.rolling_radius_m.front", p.wheels.radius_front, "wheels.radius_front");
  b.Scw(vd + "tire.rolling_radius_m.rear", p.wheels.radius_rear, "wheels.radius_rear");
  b.Own(vd + "tire.spring_stiffness_Npm.front", kAv21TireVertical, kAv21,
        "tyre vertical stiffness; no EAV24 value is public");
  b.Own(vd + "tire.spring_stiffness_Npm.rear", kAv21TireVertical, kAv21, "as front");
  b.Scw(vd + "tire.rolling_resistance_coefficient", p.wheels.rolling_resistance,
        "wheels.rolling_resistance");
  b.Own(vd + "tire.rolling_radius_m.velocity_scaling.velocity_points_mps", {0.0, 100.0}, "(none)",
        "scw's rolling radius does not grow with speed: factors 1");
  b.Own(vd + "tire.rolling_radius_m.velocity_scaling.factors", {1.0, 1.0}, "(none)",
        "scw's rolling radius does not grow with speed: factors 1");

  // Aerodynamics (ocd_aerodynamics_models_cpp, default model): coefficients times A = 1 m^2.
  const std::string ae = kAero;
  const auto& a = p.aero;
  b.Scw(ae + "air_density_kgpm3", a.air_density, "aero.air_density");
  b.Own(ae + "A_m2", 1.0, "(none)", "1 m^2, so that c_d and c_l are scw's areas c*A");
  b.Scw(ae + "c_d", a.drag_area, "aero.drag_area");
  b.Scw(ae + "c_l", -(a.downforce_area_front + a.downforce_area_rear),
        "-(aero.downforce_area_front + aero.downforce_area_rear)");
  const double share_f = a.downforce_area_front / (a.downforce_area_front + a.downforce_area_rear);
  const double lr = c.wheelbase - c.cg_to_front_axle;
  b.Scw(ae + "d_aero_center_cog_m", share_f * c.wheelbase - lr,
        "downforce front share x chassis.wheelbase - l_r: the front axle's share of the "
        "downforce as the vehicle file splits it");
  b.Own(ae + "c_l_velocity_scaling.vel_mps", {0.0, 100.0}, "(none)",
        "scw's downforce coefficient does not change with speed: delta 0");
  b.Own(ae + "c_l_velocity_scaling.delta_c_l", {0.0, 0.0}, "(none)",
        "scw's downforce coefficient does not change with speed: delta 0");
  b.Own(ae + "pitch_aero_center_translation.pitch_rad", {-M_PI, M_PI}, "(none)",
        "no aero-balance shift with pitch in scw: translation 0");
  b.Own(ae + "pitch_aero_center_translation.aero_center_translation_m", {0.0, 0.0}, "(none)",
        "no aero-balance shift with pitch in scw: translation 0");

  // The four tyre models (ocd_tire_models_cpp MF52), from the axle's MF5.2 set: every coefficient
  // of scw's schema under its .tir name, the friction scalings with the grip factors of the wheel.
  const auto& g = p.grip;
  const bool curve = p.tires.grip_scaling == "curve";
  for (std::size_t i = 0; i < 4; ++i) {
    const bool front = i < 2;
    const params::Mf52Params& t = front ? p.tires.front : p.tires.rear;
    const std::string axle = front ? "tires.front." : "tires.rear.";
    const std::string pre = vd + "z.tire_model." + kOcdWheelNames[i] + ".";
    const double gx = g.mu * (front ? g.front_mu_x : g.rear_mu_x) * g.wheel_mu_x[i];
    const double gy = g.mu * (front ? g.front_mu_y : g.rear_mu_y) * g.wheel_mu_y[i];
    params::ForEachField(t, [&](const std::string& key, const auto& value, const params::Meta&) {
      if constexpr (std::is_same_v<std::remove_cvref_t<decltype(value)>, double>) {
        if (key == "falloff") return;  // CheckRepresentable
        double v = value;
        std::string source = axle + key;
        const std::string grip = "grip.mu x grip." + std::string(front ? "front" : "rear");
        const std::string how = curve ? "" : " (tires.grip_scaling peak)";
        if (key == "lmux") {
          v *= gx;
          source += " x " + grip + "_mu_x x grip.wheel_mu_x[" + std::to_string(i) + "]" + how;
        } else if (key == "lmuy") {
          v *= gy;
          source += " x " + grip + "_mu_y x grip.wheel_mu_y[" + std::to_string(i) + "]" + how;
        } else if (key == "lkx" && curve) {
          v *= gx;
          source += " x the wheel's mu_x factors (tires.grip_scaling curve)";
        } else if (key == "lky" && curve) {
          v *= gy;
          source += " x the wheel's mu_y factors (tires.grip_scaling curve)";
        }
        b.Scw(pre + Upper(key), v, source);
      }
    });
    for (const Neutral& n : kNeutralTyre) b.Own(pre + n.name, n.value, "(none)", n.why);
  }
  return b.Take();
}

std::vector<Problem> CheckRepresentable(const params::VehicleParams& p) {
  std::vector<Problem> out;
  const auto not_ocd = [&](std::string path, double value, double ocd, const std::string& what) {
    if (value != ocd)
      out.push_back({std::move(path), "is " + params::FormatNumber(value) + "; " + what +
                                          " is fixed at " + params::FormatNumber(ocd) +
                                          " in Open-Car-Dynamics (plant.model=ocd): set it to " +
                                          params::FormatNumber(ocd) + " or run plant.model=scw"});
  };
  if (p.tires.front.falloff != 1.0 || p.tires.rear.falloff != 1.0) {
    for (const char* axle : {"front", "rear"}) {
      const double f = std::string(axle) == "front" ? p.tires.front.falloff : p.tires.rear.falloff;
      if (f != 1.0)
        out.push_back({std::string("tires.") + axle + ".falloff",
                       "is " + params::FormatNumber(f) +
                           " (with the scenario's plant.rear_tire_falloff); Open-Car-Dynamics' "
                           "MF5.2 has no fall-off scale (plant.model=ocd needs 1): run "
                           "plant.model=scw"});
    }
  }
  const auto& k = p.tires.kinematics;
  const std::string kin = "tires.kinematics.";
  not_ocd(kin + "relaxation_length_long", k.relaxation_length_long, kOcdRelaxationLengthLong,
          "the longitudinal relaxation length");
  not_ocd(kin + "relaxation_length_lat", k.relaxation_length_lat, kOcdRelaxationLengthLat,
          "the lateral relaxation length");
  not_ocd(kin + "relaxation_speed_min", k.relaxation_speed_min, kOcdRelaxationSpeedMin,
          "the relaxation speed floor");
  not_ocd(kin + "slip_speed_min_long", k.slip_speed_min_long, kOcdSlipSpeedMinLong,
          "the slip denominator floor");
  not_ocd(kin + "slip_speed_min_lat", k.slip_speed_min_lat, kOcdSlipSpeedMinLat,
          "the slip-angle denominator floor");
  not_ocd(kin + "slip_limit", k.slip_limit, kOcdSlipLimit, "the slip clamp");
  not_ocd("chassis.gravity", p.chassis.gravity, kOcdGravity, "gravity");
  if (p.differential.type != "spool")
    not_ocd("differential.lsd_speed_scale", p.differential.lsd_speed_scale, kOcdLsdSpeedScale,
            "the LSD's speed scale");
  return out;
}

std::vector<std::string> Replaced(const params::VehicleParams& p) {
  std::vector<std::string> out;
  out.push_back(
      "chassis.load_transfer_time_constant, chassis.load_transfer_frequency, "
      "chassis.load_transfer_damping_ratio: not used; OCD's sprung body on springs, dampers and "
      "anti-roll bars (AV-21 values, docs/ocd-plant.md) transfers the load");
  out.push_back(
      "aero.side_force_area, aero.side_force_arm: not used; OCD's side force is its lateral drag "
      "(c_d A of the lateral air speed, at the CoG)");
  if (p.differential.type == "spool")
    out.push_back("differential.type spool (differential.lsd_* not used): OCD's LSD with a " +
                  params::FormatNumber(kOcdSpoolPreload) + " N*m preload stands in for it");
  return out;
}

std::string MappingTableMarkdown(const params::VehicleParams& p) {
  const std::vector<OcdParameter> all = MapVehicle(p);
  std::ostringstream md;
  md << "| OCD parameter | value | from scw | or: public source, why |\n"
     << "| --- | --- | --- | --- |\n";
  const auto value_text = [](const OcdParameter& q) {
    std::string s;
    for (std::size_t j = 0; j < q.value.size(); ++j) s += (j ? ", " : "") + Fmt(q.value[j]);
    return q.value.size() > 1 ? "[" + s + "]" : s;
  };
  const std::string tyre_prefix = std::string(kVd) + "z.tire_model.";
  // Tyre coefficients are listed once per axle (the left wheel's name stands for both; the
  // friction scalings are per wheel, so they differ only with per-wheel grip factors).
  std::map<std::string, bool> seen;
  for (const OcdParameter& q : all) {
    std::string name = q.name;
    if (name.rfind(tyre_prefix, 0) == 0) {
      const std::string rest = name.substr(tyre_prefix.size());
      const std::string wheel = rest.substr(0, rest.find('.'));
      const std::string coeff = rest.substr(rest.find('.') + 1);
      if (wheel == "front_right" || wheel == "rear_right") continue;
      const bool neutral = q.ocd_only;
      const std::string group = wheel == "front_left" ? "front_*" : "rear_*";
      if (neutral) {
        // The neutral coefficients, one row per group and value.
        const std::string key = "neutral " + q.why + Fmt(q.value[0]);
        if (seen[key]) continue;
        seen[key] = true;
        std::string names;
        for (const OcdParameter& r : all)
          if (r.name.rfind(tyre_prefix + "front_left.", 0) == 0 && r.ocd_only && r.why == q.why &&
              r.value == q.value)
            names += (names.empty() ? "" : ", ") + r.name.substr(r.name.rfind('.') + 1);
        md << "| `z.tire_model.*.{" << names << "}` | " << Fmt(q.value[0]) << " | | " << q.why
           << " |\n";
        continue;
      }
      name = "z.tire_model." + group + "." + coeff;
      std::string source = q.source;
      const auto pos = source.find(" x grip.wheel");
      if (pos != std::string::npos)
        source = source.substr(0, pos) + " x grip.wheel_mu_*[wheel]" +
                 source.substr(source.find(']', pos) + 1);
      md << "| `" << name << "` | " << value_text(q) << " | `" << source << "` | |\n";
      continue;
    }
    if (name.rfind(kVd, 0) == 0) name = name.substr(std::string(kVd).size());
    md << "| `" << name << "` | " << value_text(q) << " | "
       << (q.ocd_only ? "" : "`" + q.source + "`") << " | "
       << (q.ocd_only ? (q.source == "(none)" ? q.why : q.source + ": " + q.why) : "") << " |\n";
  }
  return md.str();
}

}  // namespace scw::plant::ocd
