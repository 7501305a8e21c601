// CSV text fields per RFC 4180 (issue 15): a name with a comma, a quote or a line break stays one
// cell. Written with CsvWriter, parsed back with ParseCsv, every field round-trips; plain fields
// are written exactly as before.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "params/io/csv.h"
#include "params/io/yaml_doc.h"

namespace scw::tuning {
namespace {

namespace fs = std::filesystem;

class CsvQuotingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("scw_csv_quoting_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path dir_;
};

TEST_F(CsvQuotingTest, CommaQuoteAndLineBreaksRoundTripThroughTheWriter) {
  const std::string path = (dir_ / "comparison.csv").string();
  const std::vector<std::string> names = {
      "Yas North, wet",    // comma: shifted every later column before
      "the \"fast\" set",  // quotes
      "\"quoted\"",        // quotes at both ends
      "two\nlines",        // LF
      "cr\r\nlf",          // CRLF inside a field
      "plain",             // untouched
      "",                  // empty
      " spaces kept ",     // blanks are data
      ",",                 // only a separator
  };
  {
    io::CsvWriter w(path, {"scenario", "mean lap, s", "count"});
    for (std::size_t i = 0; i < names.size(); ++i) {
      w.Add(names[i]);
      w.Add(0.5 + static_cast<double>(i));
      w.Add(static_cast<int>(i));
      w.EndRow();
    }
    w.Commit();
  }
  const auto records = io::ParseCsv(params::ReadTextFile(path));
  ASSERT_EQ(records.size(), names.size() + 1);
  EXPECT_EQ(records[0], (std::vector<std::string>{"scenario", "mean lap, s", "count"}));
  for (std::size_t i = 0; i < names.size(); ++i) {
    ASSERT_EQ(records[i + 1].size(), 3u) << "row " << i << ": " << names[i];
    EXPECT_EQ(records[i + 1][0], names[i]);
    EXPECT_EQ(std::stod(records[i + 1][1]), 0.5 + static_cast<double>(i));
    EXPECT_EQ(records[i + 1][2], std::to_string(i));
  }
}

TEST_F(CsvQuotingTest, QuotingFollowsRfc4180AndLeavesPlainFieldsAlone) {
  EXPECT_EQ(io::CsvField("plain"), "plain");
  EXPECT_EQ(io::CsvField("1.25e-05"), "1.25e-05");
  EXPECT_EQ(io::CsvField("a,b"), "\"a,b\"");
  EXPECT_EQ(io::CsvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(io::CsvField("a\nb"), "\"a\nb\"");
  EXPECT_EQ(io::CsvField("a\rb"), "\"a\rb\"");
  EXPECT_EQ(io::CsvRecord({"x", "y,z", ""}), "x,\"y,z\",");

  const std::string path = (dir_ / "plain.csv").string();
  {
    io::CsvWriter w(path, {"t", "status"});
    w.Add(0.25);
    w.Add(std::string("ok"));
    w.EndRow();
    w.Commit();
  }
  EXPECT_EQ(params::ReadTextFile(path), "t,status\n0.25,ok\n");
}

TEST_F(CsvQuotingTest, ParserAcceptsCrLfAndRefusesBrokenQuoting) {
  EXPECT_EQ(io::ParseCsv("a,b\r\n1,\"x\"\"y\"\r\n"),
            (std::vector<std::vector<std::string>>{{"a", "b"}, {"1", "x\"y"}}));
  EXPECT_EQ(io::ParseCsv("a,\n"), (std::vector<std::vector<std::string>>{{"a", ""}}));
  EXPECT_THROW(io::ParseCsv("a,\"open\n"), std::invalid_argument);
  EXPECT_THROW(io::ParseCsv("\"closed\"tail,b\n"), std::invalid_argument);
}

// The append-only log (a tune's evaluation log) and its row reader: rows are quoted like every
// other CSV, appending keeps the rows already there byte for byte, the reader gives the header as
// written, whole rows, a malformed row as such, and says whether the file ends inside a row.
TEST_F(CsvQuotingTest, AnAppendedLogReadsBackRowByRow) {
  const std::string path = (dir_ / "log.csv").string();
  {
    io::CsvLog log(path, io::CsvLog::Open::kCreate, {"eval", "status"}, "the test log");
    ASSERT_TRUE(log.Write({"0", "ok"}));
    EXPECT_THROW(log.Write({"1"}), std::logic_error);
  }
  {
    io::CsvLog log(path, io::CsvLog::Open::kAppend, {"eval", "status"}, "the test log");
    ASSERT_TRUE(log.Write({"1", "late, 2 s"}));
  }
  EXPECT_EQ(params::ReadTextFile(path), "eval,status\n0,ok\n1,\"late, 2 s\"\n");
  io::CsvRowReader in(path);
  ASSERT_TRUE(in.is_open());
  EXPECT_EQ(in.header_line(), "eval,status");
  EXPECT_TRUE(in.ends_with_line_break());
  std::vector<std::string> cells;
  ASSERT_EQ(in.Next(&cells), io::CsvRowReader::Row::kCells);
  EXPECT_EQ(cells, (std::vector<std::string>{"0", "ok"}));
  ASSERT_EQ(in.Next(&cells), io::CsvRowReader::Row::kCells);
  EXPECT_EQ(cells, (std::vector<std::string>{"1", "late, 2 s"}));
  EXPECT_EQ(in.Next(&cells), io::CsvRowReader::Row::kEnd);

  io::WriteFileAtomic(path, "a,b\n\"open,1\n2,");
  io::CsvRowReader cut(path);
  EXPECT_FALSE(cut.ends_with_line_break());
  EXPECT_EQ(cut.Next(&cells), io::CsvRowReader::Row::kMalformed);
  EXPECT_FALSE(io::CsvRowReader((dir_ / "missing.csv").string()).is_open());
  const std::string missing = (dir_ / "no" / "log.csv").string();
  try {
    io::CsvLog log(missing, io::CsvLog::Open::kCreate, {"a"}, "the test log");
    ADD_FAILURE() << "no error for " << missing;
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "cannot write the test log " + missing);
  }
}

}  // namespace
}  // namespace scw::tuning
