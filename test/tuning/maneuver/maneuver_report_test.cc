// What `scw maneuver` prints and writes (tuning/maneuver/maneuver_report.h) on hand-made results
// (issue 50 findings 17 and 10): the conditions, the standard's pass limits with the runs they
// apply to, what each column is, no "-0.000", and the notes on what a run did not test.
#include "tuning/maneuver/maneuver_report.h"

#include <gtest/gtest.h>

#include <string>
#include <utility>

namespace scw::tuning {
namespace {

/// A sine with dwell of three amplitudes in which CS acted once and ESC never.
ManeuverResult Swd() {
  ManeuverResult r;
  r.name = "sine_with_dwell";
  r.standard = "FMVSS 126 / UN R140 sine with dwell";
  r.series = "amplitude factor [A]";
  r.setup = {{"speed_mps", 80.0 / 3.6, "test speed"}};
  for (const auto& [f, label] : {std::pair{4.5, "4.50 A"}, {5.0, "5.00 A"}, {5.5, "5.50 A"}}) {
    ManeuverRun run;
    run.label = label;
    run.level = f;
    run.values = {{"ratio_1_00_pct", -0.0004, "yaw rate 1.00 s after COS / peak"},
                  {"lateral_displacement_m", 3.0, "at BOS + 1.07 s, towards the first steer"}};
    run.criteria = {{"ratio_1_00_pct", -0.0004, 35.0, true, "FMVSS 126 S5.2.1"}};
    if (f >= 5.0)
      run.criteria.push_back({"lateral_displacement_m", 3.0, 1.83, false, "FMVSS 126 S5.2.3"});
    run.metrics.cs_count = f == 5.0 ? 1 : 0;
    run.metrics.max_esc_margin = 0.1 * f;
    r.runs.push_back(run);
  }
  return r;
}

TEST(ManeuverReport, LimitsConditionsColumnsAndNoNegativeZero) {
  ManeuverConditions c;
  c.stability = "/cars/set.yaml";
  const std::string text = FormatManeuver(Swd(), c);
  EXPECT_NE(text.find("vehicle: built-in; stability: /cars/set.yaml; subsystems: ESC CS ABS TC "
                      "(stability control on)\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("pass limits:\n  ratio_1_00_pct <= 35.0  (FMVSS 126 S5.2.1; every run)\n"
                      "  lateral_displacement_m >= 1.83  (FMVSS 126 S5.2.3; runs 5.00 A to "
                      "5.50 A)\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("  lateral_displacement_m: at BOS + 1.07 s, towards the first steer\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("-0.000"), std::string::npos) << text;
  EXPECT_NE(text.find("| 4.50 A | 0.000 | 3.00 |"), std::string::npos) << text;
  // CS acted, ESC (what the test is about) never: said, with the closest approach.
  EXPECT_NE(text.find("note: ESC ran but did not act in any run: at these conditions this test "
                      "does not exercise ESC (its activation condition came to 0.55 of holding"),
            std::string::npos)
      << text;
}

TEST(ManeuverReport, NotesFollowTheSubsystemsThatRan) {
  ManeuverResult r = Swd();
  ManeuverConditions c;
  // No subsystem acted at all: the result is the car's own.
  for (auto& run : r.runs) run.metrics.cs_count = 0;
  auto notes = ManeuverNotes(r, c);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("no stability subsystem that ran (ESC CS ABS TC) acted"),
            std::string::npos);
  // Stability control off: nothing to say.
  c.subsystems = {false, false, false, false, false};
  EXPECT_TRUE(ManeuverNotes(r, c).empty());
  EXPECT_NE(FormatManeuver(r, c).find("subsystems: none (stability control off)"),
            std::string::npos);
  // ESC acted: no note.
  c.subsystems = {};
  r.runs[1].metrics.esc_count = 2;
  EXPECT_TRUE(ManeuverNotes(r, c).empty());
}

// Finding 10: in the acceleration tests a braking slip of a rear wheel with TC acting is named
// as the published TC's, with its value and time; without TC acting, or without braking slip,
// there is no such note.
TEST(ManeuverReport, BrakingSlipUnderFullThrottleIsExplained) {
  ManeuverResult r;
  r.name = "mu_jump_acceleration";
  r.standard = "mu jump under full throttle (high to low mu)";
  ManeuverRun run;
  run.label = "mu jump";
  run.signals.t = {-0.01, 0.0, 1.0, 2.29, 3.0};
  run.signals.max_slip_rear = {-80.0, 20.0, 24.0, -73.7, 23.0};  // t < 0 does not count
  run.metrics.tc_count = 1;
  r.runs.push_back(run);
  const ManeuverConditions on;
  const auto notes = ManeuverNotes(r, on);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("mu jump: a rear wheel ran at -73.7 % slip (braking) at t = 2.29 s "
                          "although this test requests no brake. This is the published TC"),
            std::string::npos)
      << notes[0];
  const std::string json = ManeuverJson(r, 1, on);
  EXPECT_NE(json.find("\"notes\": [\"mu jump: a rear wheel ran at -73.7 %"), std::string::npos);
  // The figure's rear-slip panel: signed.
  EXPECT_NE(json.find("\"slip_rear_pct\": [-80.0,20.0,24.0,-73.7,23.0]"), std::string::npos)
      << json;
  ManeuverConditions off;
  off.subsystems = {false, false, false, false, false};
  EXPECT_TRUE(ManeuverNotes(r, off).empty());
  r.runs[0].signals.max_slip_rear[3] = -5.0;  // a little braking slip: nothing to explain
  EXPECT_TRUE(ManeuverNotes(r, on).empty());
}

TEST(ManeuverReport, JsonHasConditionsLimitsAndNotes) {
  ManeuverConditions c;
  c.vehicle = "v\"1.yaml";
  c.subsystems.tc = false;
  const std::string json = ManeuverJson(Swd(), 2, c);
  EXPECT_NE(json.find("\"conditions\": {\"vehicle\": \"v\\\"1.yaml\", \"stability\": "
                      "\"built-in\", \"subsystems\": \"ESC CS ABS\", \"stability_control\": "
                      "\"partial\"}"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find("{\"key\": \"lateral_displacement_m\", \"limit\": 1.83, \"bound\": "
                      "\"min\", \"source\": \"FMVSS 126 S5.2.3\", \"runs\": \"runs 5.00 A to "
                      "5.50 A\"}"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find("\"notes\": [\"ESC ran but did not act"), std::string::npos) << json;
}

}  // namespace
}  // namespace scw::tuning
