// The trace schema: one table for the header and the rows, on synthetic ticks.
#include "tuning/sim/trace_schema.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "params/io/csv.h"
#include "params/io/yaml_doc.h"
#include "test/tuning/sim/tick_signals.h"
#include "tuning/sim/closed_loop.h"

namespace scw::tuning {
namespace {

using synthetic::TickSignals;

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("scw_trace_schema_" + name + ".csv")).string();
}

// Writes rows with the recorder and returns the file's records (header first).
std::vector<std::vector<std::string>> Write(const std::vector<TickSignals>& ticks, long every,
                                            const std::string& name) {
  const std::string path = TempPath(name);
  {
    io::CsvWriter w(path, TraceHeader());
    TraceRecorder trace(&w, every);
    for (std::size_t k = 0; k < ticks.size(); ++k)
      trace.Record(static_cast<long>(k), ticks[k].Record());
    w.Commit();
  }
  auto records = io::ParseCsv(params::ReadTextFile(path));
  std::filesystem::remove(path);
  return records;
}

TEST(TraceSchemaTest, HeaderKeepsItsNamesAndOrder) {
  // Traces are read by name by scripts and tests: the names and their order are the format.
  std::vector<std::string> expected = {"t_s",
                                       "lap",
                                       "s_m",
                                       "x_m",
                                       "y_m",
                                       "psi_rad",
                                       "vx_mps",
                                       "vy_mps",
                                       "yaw_rate_radps",
                                       "ax_mps2",
                                       "ay_mps2",
                                       "beta_deg",
                                       "lateral_error_m",
                                       "heading_error_deg",
                                       "v_target_mps",
                                       "steer_req_rad",
                                       "steer_out_rad",
                                       "steer_meas_rad",
                                       "throttle_req",
                                       "throttle_out",
                                       "long_fx_N",
                                       "gear",
                                       "engine_speed_radps",
                                       "esc_active",
                                       "cs_active",
                                       "abs_active",
                                       "tc_active",
                                       "yaw_moment_Nm"};
  const std::pair<const char*, const char*> per_wheel[] = {
      {"p_req_", "_bar"}, {"p_out_", "_bar"}, {"slip_", "_pct"}, {"alpha_", "_rad"}, {"fz_", "_N"}};
  for (const auto& [prefix, unit] : per_wheel)
    for (const char* w : kWheelNames) expected.push_back(prefix + std::string(w) + unit);
  expected.push_back("events");
  expected.push_back(
      "yaw_rate_ref_radps");  // issue 27: appended, so older columns keep their place
  // Issue 48 (decisive test 6): the tyres' longitudinal forces, appended likewise.
  for (const char* w : kWheelNames) expected.push_back("fx_" + std::string(w) + "_N");
  EXPECT_EQ(TraceHeader(), expected);
}

TEST(TraceSchemaTest, NamesAreUniqueAndEveryColumnIsDescribed) {
  std::set<std::string> names;
  for (const TraceColumn& c : kTraceColumns) {
    EXPECT_TRUE(names.insert(std::string(c.name)).second) << "twice: " << c.name;
    EXPECT_NE(c.real == nullptr, c.integer == nullptr) << c.name << ": exactly one accessor";
    EXPECT_FALSE(c.unit.empty()) << c.name;
    EXPECT_FALSE(c.doc.empty()) << c.name;
  }
  EXPECT_EQ(TraceHeader().size(), kTraceColumns.size());
}

TEST(TraceSchemaTest, PerWheelColumnsReadTheWheelTheirNameSays) {
  for (const TraceColumn& c : kTraceColumns) {
    const std::string name(c.name);
    const std::string wheel = "_" + std::string(kWheelNames[c.wheel]) + "_";
    if (c.wheel != 0 || name.find("_fl_") != std::string::npos) {
      EXPECT_NE(name.find(wheel), std::string::npos) << name << " reads wheel " << c.wheel;
    }
  }
}

TEST(TraceSchemaTest, ARowHasOneCellPerHeaderColumn) {
  const auto records = Write({TickSignals{}}, 1, "width");
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0], TraceHeader());
  EXPECT_EQ(records[1].size(), records[0].size());
}

TEST(TraceSchemaTest, CellsCarryTheirSignalsInTheirUnits) {
  TickSignals x;
  x.t = 1.25;
  x.lap = 2;
  x.s = 17.5;
  x.beta = 0.1;
  x.motion.heading_error = -0.05;
  x.meas.gear = 4;
  x.meas.v_x = 61.5;
  x.input.throttle_request = 0.75;
  x.input.long_fx = -1500.0;
  x.output.esc_active = true;
  x.output.tc_state[kRR] = controller::SlipPhase::kReduce;
  x.input.brake_request_bar = {1.0, 2.0, 3.0, 4.0};
  x.output.brake_bar = {5.0, 6.0, 7.0, 8.0};
  x.plant.kappa[kFR] = -0.125;
  x.plant.fz[kRL] = 2500.0;
  x.event_mask = 5;
  const auto records = Write({x}, 1, "cells");
  ASSERT_EQ(records.size(), 2u);
  const auto cell = [&](const std::string& name) {
    for (std::size_t i = 0; i < records[0].size(); ++i)
      if (records[0][i] == name) return records[1][i];
    ADD_FAILURE() << "no column " << name;
    return std::string();
  };
  EXPECT_EQ(cell("t_s"), "1.25");
  EXPECT_EQ(cell("lap"), "2");
  EXPECT_EQ(cell("s_m"), "17.5");
  EXPECT_EQ(std::stod(cell("beta_deg")), 0.1 * kRadToDeg);
  EXPECT_EQ(std::stod(cell("heading_error_deg")), -0.05 * kRadToDeg);
  EXPECT_EQ(cell("gear"), "4");
  EXPECT_EQ(cell("vx_mps"), "61.5");
  EXPECT_EQ(cell("throttle_req"), "0.75");
  EXPECT_EQ(cell("long_fx_N"), "-1500");
  EXPECT_EQ(cell("esc_active"), "1");
  EXPECT_EQ(cell("cs_active"), "0");
  EXPECT_EQ(cell("abs_active"), "0");
  EXPECT_EQ(cell("tc_active"), "1");
  EXPECT_EQ(cell("p_req_rl_bar"), "3");
  EXPECT_EQ(cell("p_out_fr_bar"), "6");
  EXPECT_EQ(cell("slip_fr_pct"), "-12.5");
  EXPECT_EQ(cell("fz_rl_N"), "2500");
  EXPECT_EQ(cell("events"), "5");
}

TEST(TraceRecorderTest, WritesEveryNthTickStartingWithTheFirst) {
  std::vector<TickSignals> ticks(7);
  for (std::size_t k = 0; k < ticks.size(); ++k) ticks[k].t = 0.5 * static_cast<double>(k);
  const auto records = Write(ticks, 3, "every");
  ASSERT_EQ(records.size(), 4u);  // header + ticks 0, 3, 6
  EXPECT_EQ(records[1][0], "0");
  EXPECT_EQ(records[2][0], "1.5");
  EXPECT_EQ(records[3][0], "3");
}

TEST(TraceRecorderTest, WithoutAWriterRecordsNothing) {
  TraceRecorder trace(nullptr, 1);
  EXPECT_NO_THROW(trace.Record(0, TickSignals{}.Record()));
}

TEST(TraceRecorderTest, AWriterWithAnotherHeaderIsRefused) {
  const std::string path = TempPath("other");
  io::CsvWriter w(path, {"t_s", "lap"});
  TraceRecorder trace(&w, 1);
  const TickSignals x;
  EXPECT_THROW(trace.Record(0, x.Record()), std::logic_error);
}

}  // namespace
}  // namespace scw::tuning
