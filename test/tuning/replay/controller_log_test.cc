// The controller-log format (tuning/replay/controller_log.h): exact round trip, atomic writing,
// and refusal of bad logs with the line and the column named.
#include "tuning/replay/controller_log.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "test/tuning/replay/log_stories.h"

namespace scw::tuning::replay {
namespace {

using controller::StabilityInput;
using testing::ReadFile;
using testing::SameBits;
using testing::TempDir;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

double Get(const StabilityInput& in, const LogColumn& c) {
  if (c.integer != nullptr) return in.*c.integer;
  if (c.wheel != nullptr) return (in.*c.wheel)[c.wheel_index];
  return in.*c.real;
}

void ExpectSameRow(const StabilityInput& a, const StabilityInput& b, std::size_t row) {
  for (const auto& c : kInputColumns)
    EXPECT_TRUE(SameBits(Get(a, c), Get(b, c)))
        << "row " << row << ", column " << c.name << ": " << Get(a, c) << " vs " << Get(b, c);
}

std::size_t CountFiles(const std::filesystem::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
  return n;
}

TEST(ControllerLogColumns, NamesAreUniqueAndEachColumnHasOneTarget) {
  for (std::size_t i = 0; i < kInputColumns.size(); ++i) {
    const auto& c = kInputColumns[i];
    EXPECT_EQ((c.real != nullptr) + (c.wheel != nullptr) + (c.integer != nullptr), 1) << c.name;
    for (std::size_t j = 0; j < i; ++j) EXPECT_NE(c.name, kInputColumns[j].name);
  }
}

TEST(ControllerLog, RoundTripIsBitIdenticalIncludingUnavailableSignals) {
  const TempDir dir("scw_log_roundtrip");
  const params::StabilityParams p;
  std::vector<StabilityInput> rows;
  for (int k = 0; k < 200; ++k) rows.push_back(testing::SyntheticRow(p, 2950 + k));
  // Awkward values: shortest round-trip text must reproduce every bit.
  rows[3].v_y = -0.0;
  rows[4].a_y = 0.1 + 0.2;
  rows[5].yaw_rate = 5e-324;  // smallest subnormal
  rows[6].long_fx = -1.7976931348623157e308;
  rows[7].steering_measured = kInf;  // implausible but representable
  rows[8].brake_request_bar[kRR] = kNan;
  rows[9].gear = -1;
  rows[10].t = rows[9].t;  // equal time stamps are allowed
  rows[11].wheel_speed = {kNan, kNan, kNan, kNan};
  rows[12].beta_request = 1.0 / 3.0;
  rows[13].engine_speed = -kNan;

  const std::string path = dir.File("log.csv");
  testing::WriteLog(path, rows);
  EXPECT_EQ(CountFiles(dir.path()), 1u) << "no temporary file left behind";

  ControllerLogReader reader(path);
  EXPECT_EQ(reader.header().size(), kInputColumns.size());
  StabilityInput in;
  std::size_t n = 0;
  while (reader.Next(&in)) {
    ASSERT_LT(n, rows.size());
    ExpectSameRow(rows[n], in, n);
    EXPECT_EQ(reader.line(), static_cast<std::int64_t>(n) + 2);
    ++n;
  }
  EXPECT_EQ(n, rows.size());

  // Writing the rows read back gives the same bytes.
  const std::string copy = dir.File("copy.csv");
  {
    ControllerLogWriter w(copy);
    ControllerLogReader r(path);
    while (r.Next(&in)) w.Write(in);
    w.Commit();
    EXPECT_EQ(w.rows(), static_cast<std::int64_t>(rows.size()));
  }
  EXPECT_EQ(ReadFile(copy), ReadFile(path));
}

TEST(ControllerLog, OptionalColumnsMayBeLeftOutAndCellsMayBeEmptyOrNan) {
  const TempDir dir("scw_log_optional");
  std::string header, cells;
  for (const auto& c : kInputColumns) {
    if (!c.required) continue;
    header += (header.empty() ? "" : ",") + std::string(c.name);
    std::string v = c.name == "t_s" ? "0.5" : c.integer ? "3" : c.name == "vx_mps" ? " 12.5 " : "";
    if (c.name == "ax_mps2") v = "NaN";
    if (c.name == "ay_mps2") v = "-nan";
    cells += (cells.empty() ? "" : ",") + v;
  }
  const std::string path = dir.File("log.csv");
  std::ofstream(path) << header << "\r\n" << cells << "\r\n";
  ControllerLogReader reader(path);
  StabilityInput in;
  ASSERT_TRUE(reader.Next(&in));
  EXPECT_EQ(in.t, 0.5);
  EXPECT_EQ(in.v_x, 12.5);
  EXPECT_EQ(in.gear, 3);
  EXPECT_TRUE(std::isnan(in.v_y));
  EXPECT_TRUE(std::isnan(in.a_x));
  EXPECT_TRUE(std::isnan(in.a_y));
  EXPECT_TRUE(std::isnan(in.long_fx));
  EXPECT_TRUE(std::isnan(in.steering_measured));  // optional column absent
  for (std::size_t i = 0; i < 4; ++i) EXPECT_TRUE(std::isnan(in.fz_external[i]));
  EXPECT_FALSE(reader.Next(&in));
}

TEST(ControllerLogColumns, NamesCarryTheirUnitLikeTheTrace) {
  // The trace of `scw simulate --trace` names t_s, vx_mps, p_req_fl_bar, long_fx_N, fz_fl_N ...
  auto ends_with = [](std::string_view s, std::string_view suffix) {
    return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
  };
  const std::vector<std::pair<std::string_view, std::string_view>> suffixes = {
      {"s", "_s"},     {"m/s", "_mps"}, {"m/s^2", "_mps2"}, {"rad/s", "_radps"},
      {"rad", "_rad"}, {"bar", "_bar"}, {"N", "_N"},        {"degC", "_degC"}};
  for (const auto& c : kInputColumns) {
    for (const auto& [unit, end] : suffixes) {
      if (c.unit == unit) {
        EXPECT_TRUE(ends_with(c.name, end)) << c.name;
      }
    }
    // Every renamed column keeps its old name readable, and no old name is a current name.
    if (c.name != "throttle_req" && c.integer == nullptr) {
      EXPECT_FALSE(c.alias.empty()) << c.name;
    }
    for (const auto& other : kInputColumns) EXPECT_NE(c.alias, other.name);
  }
}

TEST(ControllerLog, OldColumnNamesAreReadBitForBit) {
  // A log of the first format version (names without units, as the fuzz corpus and the car's
  // first recordings have them) reads exactly like the same log with the current names.
  const TempDir dir("scw_log_old_names");
  const params::StabilityParams p;
  std::vector<StabilityInput> rows;
  for (int k = 0; k < 50; ++k) rows.push_back(testing::SyntheticRow(p, 3000 + k));
  testing::WriteLog(dir.File("new.csv"), rows);
  std::string text = ReadFile(dir.File("new.csv"));
  const std::size_t eol = text.find('\n');
  std::string old_header;
  for (const auto& c : kInputColumns)
    old_header += (old_header.empty() ? "" : ",") + std::string(c.alias.empty() ? c.name : c.alias);
  EXPECT_EQ(old_header.substr(0, 21), "t,vx,vy,yaw_rate,ax,a");
  std::ofstream(dir.File("old.csv")) << old_header << text.substr(eol);
  ControllerLogReader reader(dir.File("old.csv"));
  StabilityInput in;
  std::size_t n = 0;
  while (reader.Next(&in)) {
    ASSERT_LT(n, rows.size());
    ExpectSameRow(rows[n], in, n);
    ++n;
  }
  EXPECT_EQ(n, rows.size());

  // The fuzz corpus's full log (old names) is still a valid log.
  ControllerLogReader corpus(std::string(SCW_SOURCE_DIR) + "/test/fuzz/corpus/replay_log/full.csv");
  EXPECT_TRUE(corpus.Next(&in));
  EXPECT_EQ(in.wheel_speed[kFL], 140.0);
}

TEST(ControllerLogWriter, WithTheOutputWritesTheLoadsTheControllerUsed) {
  const TempDir dir("scw_log_loads");
  const params::StabilityParams p;
  const controller::StabilityController c(p);
  controller::StabilityController::State s;
  StabilityInput in = testing::SyntheticRow(p, 10);
  in.fz_external = {kNan, kNan, kNan, kNan};
  const controller::StabilityOutput out = c.Step(in, &s);
  ASSERT_TRUE(out.valid);
  StabilityInput invalid = in;
  invalid.t += 0.01;
  invalid.yaw_rate = kNan;  // pass-through: no loads used
  const controller::StabilityOutput out_invalid = c.Step(invalid, &s);
  ASSERT_FALSE(out_invalid.valid);
  {
    ControllerLogWriter w(dir.File("log.csv"));
    w.Write(in, out);
    w.Write(invalid, out_invalid);
    w.Commit();
    EXPECT_EQ(w.bytes(), static_cast<std::int64_t>(ReadFile(dir.File("log.csv")).size()));
    EXPECT_TRUE(w.is_file());
  }
  ControllerLogReader r(dir.File("log.csv"));
  StabilityInput back;
  ASSERT_TRUE(r.Next(&back));
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_GT(back.fz_external[i], 0.0);
    EXPECT_TRUE(SameBits(back.fz_external[i], out.fz[i]));
  }
  ASSERT_TRUE(r.Next(&back));
  for (std::size_t i = 0; i < 4; ++i) EXPECT_TRUE(std::isnan(back.fz_external[i]));
}

TEST(ControllerLog, TrailingBlankLinesAreIgnored) {
  const TempDir dir("scw_log_trailing");
  const params::StabilityParams p;
  testing::WriteLog(dir.File("log.csv"),
                    {testing::SyntheticRow(p, 0), testing::SyntheticRow(p, 1)});
  std::ofstream(dir.File("log.csv"), std::ios::app) << "\n  \r\n\n";
  ControllerLogReader reader(dir.File("log.csv"));
  StabilityInput in;
  EXPECT_TRUE(reader.Next(&in));
  EXPECT_TRUE(reader.Next(&in));
  EXPECT_FALSE(reader.Next(&in));
  EXPECT_EQ(reader.rows(), 2);
}

TEST(ControllerLogWriter, WithoutCommitNothingIsWritten) {
  const TempDir dir("scw_log_nocommit");
  const std::string path = dir.File("log.csv");
  std::ofstream(path) << "previous content\n";
  {
    ControllerLogWriter w(path);
    w.Write(testing::SyntheticRow(params::StabilityParams{}, 0));
    EXPECT_EQ(CountFiles(dir.path()), 2u);  // the target and the temporary file
  }
  EXPECT_EQ(CountFiles(dir.path()), 1u);
  EXPECT_EQ(ReadFile(path), "previous content\n");
}

TEST(ControllerLogWriter, RefusesRowsTheReaderWouldRefuse) {
  const TempDir dir("scw_log_refuse");
  ControllerLogWriter w(dir.File("log.csv"));
  StabilityInput in;
  in.t = 1.0;
  w.Write(in);
  in.t = 0.99;
  EXPECT_THROW(w.Write(in), std::invalid_argument);
  in.t = kNan;
  EXPECT_THROW(w.Write(in), std::invalid_argument);
  EXPECT_EQ(w.rows(), 1);
}

TEST(ControllerLogWriter, UnwritableFolderIsReported) {
  EXPECT_THROW(ControllerLogWriter w("/nonexistent-folder/log.csv"), std::runtime_error);
}

// ---------------------------------------------------------------------------------------------
// Bad logs: each is refused with the line (1 = header) and the column named.

using Cells = std::vector<std::vector<std::string>>;  // header row first

Cells GoodLog() {
  const TempDir dir("scw_log_good");
  const params::StabilityParams p;
  std::vector<StabilityInput> rows;
  for (int k = 0; k < 4; ++k) rows.push_back(testing::SyntheticRow(p, k));
  testing::WriteLog(dir.File("log.csv"), rows);
  Cells cells;
  std::ifstream f(dir.File("log.csv"));
  std::string line;
  while (std::getline(f, line)) {
    std::vector<std::string> row;
    std::size_t pos = 0;
    while (true) {
      const std::size_t comma = line.find(',', pos);
      row.push_back(line.substr(pos, comma == std::string::npos ? comma : comma - pos));
      if (comma == std::string::npos) break;
      pos = comma + 1;
    }
    cells.push_back(row);
  }
  return cells;
}

std::size_t IndexOf(const Cells& c, const std::string& column) {
  return static_cast<std::size_t>(std::find(c[0].begin(), c[0].end(), column) - c[0].begin());
}

std::string Join(const Cells& c) {
  std::string s;
  for (const auto& row : c) {
    for (std::size_t i = 0; i < row.size(); ++i) s += (i ? "," : "") + row[i];
    s += '\n';
  }
  return s;
}

struct BadLog {
  std::string name;
  std::string text;
  std::int64_t line;
  std::string column;  // empty: the problem concerns the whole row or file
  std::string message_part;
};

std::vector<BadLog> BadLogs() {
  std::vector<BadLog> v;
  {
    Cells c = GoodLog();
    const std::size_t i = IndexOf(c, "vy_mps");
    for (auto& row : c) row.erase(row.begin() + static_cast<long>(i));
    v.push_back({"missing_required_column", Join(c), 1, "vy_mps", "required column is missing"});
  }
  {
    Cells c = GoodLog();
    c[0][IndexOf(c, "omega_rl_radps")] = "omega_rrl_radps";
    v.push_back({"unknown_column", Join(c), 1, "omega_rrl_radps", "did you mean omega_rl_radps"});
  }
  {
    Cells c = GoodLog();
    c[0][IndexOf(c, "fz_fl_N")] = "vx_mps";
    v.push_back({"duplicate_column", Join(c), 1, "vx_mps", "given twice"});
  }
  {
    Cells c = GoodLog();
    c[0][IndexOf(c, "fz_fl_N")] = "vx";  // the old name of vx_mps
    v.push_back({"old_and_new_name", Join(c), 1, "vx", "vx being the old name of vx_mps"});
  }
  {
    Cells c = GoodLog();
    c[0][IndexOf(c, "omega_rl_radps")] = "omega_rrl";
    v.push_back({"misspelt_old_name", Join(c), 1, "omega_rrl", "did you mean omega_rl_radps"});
  }
  {
    Cells c = GoodLog();
    c[0][IndexOf(c, "yaw_rate_radps")] = "yaw_rate";
    c[3][IndexOf(c, "yaw_rate")] = "0.1x";
    v.push_back({"old_name_named_in_messages", Join(c), 4, "yaw_rate", "not a number: '0.1x'"});
  }
  {
    Cells c = GoodLog();
    c[0][IndexOf(c, "t_s")] = "t";
    c[3][IndexOf(c, "t")] = "0.005";
    v.push_back({"old_time_column_going_backwards", Join(c), 4, "t", "time goes backwards"});
  }
  {
    Cells c = GoodLog();
    c[3][IndexOf(c, "yaw_rate_radps")] = "0.1x";
    v.push_back({"non_numeric_cell", Join(c), 4, "yaw_rate_radps", "not a number: '0.1x'"});
  }
  {
    Cells c = GoodLog();
    c[2][IndexOf(c, "gear")] = "4.5";
    v.push_back({"non_integer_gear", Join(c), 3, "gear", "expected an integer"});
  }
  {
    Cells c = GoodLog();
    c[2][IndexOf(c, "gear_req")] = "nan";
    v.push_back({"missing_gear", Join(c), 3, "gear_req", "integer in every row"});
  }
  {
    Cells c = GoodLog();
    c[3][IndexOf(c, "t_s")] = "0.005";
    v.push_back({"time_going_backwards", Join(c), 4, "t_s", "time goes backwards"});
  }
  {
    Cells c = GoodLog();
    c[2][IndexOf(c, "t_s")] = "";
    v.push_back({"time_missing", Join(c), 3, "t_s", "finite number"});
  }
  {
    Cells c = GoodLog();
    c[3].pop_back();
    v.push_back({"short_row", Join(c), 4, c[0].back(), "header has 36 columns"});
  }
  {
    Cells c = GoodLog();
    c[2].push_back("1.0");
    v.push_back({"long_row", Join(c), 3, c[0].back(), "extra cells after column"});
  }
  {
    Cells c = GoodLog();
    v.push_back({"empty_line", Join({c[0], c[1], {""}, c[2]}), 3, "", "empty line"});
  }
  {
    // Issue 50 finding 21: several required columns missing are one problem naming how many.
    Cells c = GoodLog();
    for (const char* name : {"vy_mps", "ax_mps2", "omega_rr_radps"}) {
      const std::size_t i = IndexOf(c, name);
      for (auto& row : c) row.erase(row.begin() + static_cast<long>(i));
    }
    v.push_back({"missing_required_columns", Join(c), 1, "",
                 "3 of the 24 required columns are missing from the header: vy_mps, ax_mps2, "
                 "omega_rr_radps (write nan"});
  }
  {
    Cells c = GoodLog();
    const std::size_t first = IndexOf(c, "fz_fl_N");
    for (std::size_t k = 0; k < 5; ++k) c[0][first + k] += "x";
    v.push_back({"many_unknown_columns", Join(c), 1, "",
                 "5 unknown columns: fz_fl_Nx, fz_fr_Nx, fz_rl_Nx, fz_rr_Nx, brake_temp_fl_degCx "
                 "(scw replay --columns"});
  }
  v.push_back({"other_csv", "a,b,c\n1,2,3\n", 1, "",
               "not a controller log header: none of its 3 column(s) (a, b, c) is a log column"});
  // Issue 50 finding 11: a binary file says so, and never echoes its bytes.
  v.push_back({"binary_nul", std::string("t_s,\x01\x02") + '\0' + "\x9B[2J,vx\n", 1, "",
               "a NUL byte: this is a binary file"});
  v.push_back({"binary_control", "t_s,\x1B]0;title\x07,vx\n", 1, "",
               "a control character (\\x1B): this is a binary file"});
  v.push_back({"unknown_column_raw_bytes", Join({{"t_s", "v\xC3\xA9x\xFF"}}), 1, "v\xC3\xA9x\\xFF",
               "unknown column 'v\xC3\xA9x\\xFF'"});
  v.push_back({"empty_file", "", 1, "", "empty file"});
  v.push_back(
      {"blank_lines_only_after_header", Join({GoodLog()[0]}) + "\n\n", 2, "", "no data rows"});
  v.push_back({"header_only", Join({GoodLog()[0]}), 2, "", "no data rows"});
  return v;
}

class BadLogTest : public ::testing::TestWithParam<BadLog> {};

TEST_P(BadLogTest, IsRefusedNamingLineAndColumn) {
  const BadLog& b = GetParam();
  const TempDir dir("scw_badlog_" + b.name);
  const std::string path = dir.File(b.name + ".csv");
  std::ofstream(path) << b.text;
  try {
    ControllerLogReader reader(path);
    StabilityInput in;
    while (reader.Next(&in)) {
    }
    FAIL() << b.name << " was accepted";
  } catch (const LogFormatError& e) {
    EXPECT_EQ(e.line(), b.line) << e.what();
    EXPECT_EQ(e.column(), b.column) << e.what();
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find("line " + std::to_string(b.line)), std::string::npos) << what;
    if (!b.column.empty()) {
      EXPECT_NE(what.find("column " + b.column), std::string::npos) << what;
    }
    EXPECT_NE(what.find(b.message_part), std::string::npos) << what;
    EXPECT_NE(dynamic_cast<const ConfigError*>(&e), nullptr);  // `scw` exits with 2
  }
}

INSTANTIATE_TEST_SUITE_P(ControllerLogReader, BadLogTest, ::testing::ValuesIn(BadLogs()),
                         [](const auto& test_info) { return test_info.param.name; });

TEST(ControllerLogReader, MissingFileIsABadInput) {
  EXPECT_THROW(ControllerLogReader r("/nonexistent-folder/log.csv"), LogFormatError);
}

}  // namespace
}  // namespace scw::tuning::replay
