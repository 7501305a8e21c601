// Write failures while exporting or logging: the target folder does not exist or is read-only,
// the target path is a folder, the disk fills up (RLIMIT_FSIZE makes write(2) fail with EFBIG
// once the file reaches the limit, the same code path as ENOSPC; /dev/full where a file is opened
// in place). After every failure: an exception whose message names the path, the previous content
// of the target unchanged, and no temporary or partial file left in the folder.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "controller/stability/stability_controller.h"
#include "params/io/atomic_file.h"
#include "params/io/csv.h"
#include "params/io/write.h"
#include "params/io/yaml_doc.h"
#include "tuning/optim/tuner.h"
#include "tuning/replay/controller_log.h"

namespace scw::tuning {
namespace {

namespace fs = std::filesystem;

class WriteFailureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("scw_write_failure_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::permissions(dir_, fs::perms::owner_all, ec);
    fs::remove_all(dir_, ec);
  }

  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  std::set<std::string> Listing() const {
    std::set<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.insert(e.path().filename().string());
    return out;
  }

  static std::string Read(const std::string& path) { return params::ReadTextFile(path); }

  static void WriteOld(const std::string& path) { std::ofstream(path) << "old content\n"; }

  // Runs f and returns the message of the std::exception it must throw.
  static std::string Message(const std::function<void()>& f) {
    try {
      f();
    } catch (const std::exception& e) {
      return e.what();
    }
    ADD_FAILURE() << "no exception";
    return "";
  }

  fs::path dir_;
};

// File-size limit for the calling process (a full disk), restored on destruction.
class DiskFull {
 public:
  explicit DiskFull(rlim_t bytes) {
    previous_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    ::getrlimit(RLIMIT_FSIZE, &previous_);
    rlimit l = previous_;
    l.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &l);
  }
  ~DiskFull() {
    ::setrlimit(RLIMIT_FSIZE, &previous_);
    std::signal(SIGXFSZ, previous_handler_);
  }

 private:
  rlimit previous_{};
  void (*previous_handler_)(int) = nullptr;
};

std::string Big(std::size_t bytes) {
  std::string s;
  while (s.size() < bytes) s += "key: 1.0  # some text to fill the file\n";
  return s;
}

// ------------------------------------------------------------------------------------------------
// WriteFileAtomic (params export, tuned params, comparison, manifest)

TEST_F(WriteFailureTest, WriteFileAtomicIntoAMissingFolderNamesThePath) {
  const std::string path = Path("missing/sub/stability.yaml");
  const std::string msg = Message([&] { io::WriteFileAtomic(path, "a: 1.0\n"); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_TRUE(Listing().empty());
}

TEST_F(WriteFailureTest, WriteFileAtomicOntoAFolderLeavesItAndNoTemporary) {
  const std::string path = Path("a_folder");
  fs::create_directory(path);
  const std::string msg = Message([&] { io::WriteFileAtomic(path, "a: 1.0\n"); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_TRUE(fs::is_directory(path));
  EXPECT_EQ(Listing(), std::set<std::string>{"a_folder"});
}

TEST_F(WriteFailureTest, WriteFileAtomicOntoAFolderWithASlashNamesTheCause) {
  fs::create_directory(Path("out"));
  std::string msg = Message([&] { io::WriteFileAtomic(Path("out/"), "a: 1.0\n"); });
  EXPECT_NE(
      msg.find(Path("out/") + ": it is a folder; give a file name (e.g. " + Path("out/") + "NAME)"),
      std::string::npos)
      << msg;
  EXPECT_EQ(msg.find("rename"), std::string::npos) << msg;
  msg = Message([&] { io::WriteFileAtomic(Path("missing/"), "a: 1.0\n"); });
  EXPECT_NE(msg.find("a file name cannot end in '/'"), std::string::npos) << msg;
  EXPECT_EQ(Listing(), std::set<std::string>{"out"});
  EXPECT_TRUE(fs::is_empty(Path("out")));
}

// Item 3 of issue 27: the rename needs write permission on the folder only, so a write-protected
// file would be replaced although `cp` and the shell refuse. Root too is refused for a file
// without any write bit (the kernel would let root write it, so this cannot pass by EACCES).
TEST_F(WriteFailureTest, WriteFileAtomicRefusesAWriteProtectedFile) {
  const std::string path = Path("stability.yaml");
  WriteOld(path);
  fs::permissions(path, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  const std::string msg = Message([&] { io::WriteFileAtomic(path, "a: 1.0\n"); });
  EXPECT_NE(msg.find(path + ": is write-protected (mode 0444); the file was not changed"),
            std::string::npos)
      << msg;
  EXPECT_EQ(Read(path), "old content\n");
  EXPECT_EQ(fs::status(path).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  EXPECT_EQ(Listing(), std::set<std::string>{"stability.yaml"});
  // Through a symlink: the target is named.
  fs::create_symlink(path, Path("link.yaml"));
  const std::string via = Message([&] { io::WriteFileAtomic(Path("link.yaml"), "a: 1.0\n"); });
  EXPECT_NE(via.find("its target " + path + " is write-protected"), std::string::npos) << via;
  // Writable again: written.
  fs::permissions(path, fs::perms::owner_write, fs::perm_options::add);
  io::WriteFileAtomic(path, "a: 2.0\n");
  EXPECT_EQ(Read(path), "a: 2.0\n");
}

TEST_F(WriteFailureTest, WriteFileAtomicIntoAReadOnlyFolder) {
  if (::geteuid() == 0) GTEST_SKIP() << "running as root: permissions do not stop writes";
  const std::string path = Path("stability.yaml");
  WriteOld(path);
  fs::permissions(dir_, fs::perms::owner_read | fs::perms::owner_exec);
  const std::string msg = Message([&] { io::WriteFileAtomic(path, "a: 1.0\n"); });
  fs::permissions(dir_, fs::perms::owner_all);
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_EQ(Read(path), "old content\n");
  EXPECT_EQ(Listing(), std::set<std::string>{"stability.yaml"});
}

TEST_F(WriteFailureTest, WriteFileAtomicOnAFullDiskKeepsThePreviousFile) {
  const std::string path = Path("stability.yaml");
  WriteOld(path);
  std::string msg;
  {
    DiskFull full(4096);
    msg = Message([&] { io::WriteFileAtomic(path, Big(64 * 1024)); });
  }
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_EQ(Read(path), "old content\n");
  EXPECT_EQ(Listing(), std::set<std::string>{"stability.yaml"});
}

// ------------------------------------------------------------------------------------------------
// io::CsvWriter (trace, comparison, sweep tables)

TEST_F(WriteFailureTest, CsvWriterIntoAMissingFolderNamesThePath) {
  const std::string path = Path("missing/trace.csv");
  const std::string msg = Message([&] { io::CsvWriter w(path, {"a", "b"}); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_TRUE(Listing().empty());
}

TEST_F(WriteFailureTest, CsvWriterOntoAFolderIsRefusedAtOnce) {
  const std::string path = Path("a_folder");
  fs::create_directory(path);
  const std::string msg = Message([&] { io::CsvWriter w(path, {"a", "b"}); });
  EXPECT_NE(msg.find(path + ": it is a folder; give a file name (e.g. " + path + "/NAME)"),
            std::string::npos)
      << msg;
  EXPECT_TRUE(fs::is_directory(path));
  EXPECT_EQ(Listing(), std::set<std::string>{"a_folder"});
}

// ------------------------------------------------------------------------------------------------
// ControllerLogWriter (scw simulate --controller-log)

controller::StabilityInput Row(int k) {
  controller::StabilityInput in;
  in.t = 0.01 * k;
  in.v_x = 30.0;
  in.wheel_speed = {100.0, 100.0, 99.0, 99.0};
  return in;
}

TEST_F(WriteFailureTest, ControllerLogIntoAMissingFolderNamesThePath) {
  const std::string path = Path("missing/log.csv");
  const std::string msg = Message([&] { replay::ControllerLogWriter w(path); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_TRUE(Listing().empty());
}

TEST_F(WriteFailureTest, ControllerLogOntoAFolderIsRefusedAtOnce) {
  const std::string path = Path("a_folder");
  fs::create_directory(path);
  const std::string msg = Message([&] { replay::ControllerLogWriter w(path); });
  EXPECT_NE(msg.find(path + ": it is a folder"), std::string::npos) << msg;
  EXPECT_EQ(Listing(), std::set<std::string>{"a_folder"});
}

TEST_F(WriteFailureTest, ControllerLogOnAFullDiskKeepsThePreviousFile) {
  const std::string path = Path("log.csv");
  WriteOld(path);
  std::string msg;
  {
    DiskFull full(16384);
    msg = Message([&] {
      replay::ControllerLogWriter w(path);
      for (int k = 0; k < 20000; ++k) w.Write(Row(k));
      w.Commit();
    });
  }
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_EQ(Read(path), "old content\n");
  EXPECT_EQ(Listing(), std::set<std::string>{"log.csv"});
}

// ------------------------------------------------------------------------------------------------
// The tuner's evaluation log (scw tune: evaluations.csv). It is appended row by row on purpose (an
// interrupted run keeps its log for --resume), so the guarantee is: only whole rows, never a
// half-written one, and the error names the log.

Evaluation Bowl(const std::vector<double>& u) {
  double c = 0;
  for (double x : u) c += (x - 0.3) * (x - 0.3);
  return {c, "ok", {"extra"}};
}

TunerOptions LogOptions(const std::string& log) {
  TunerOptions o;
  o.algorithm = "sbplx";
  o.max_evals = 400;
  o.log_path = log;
  o.log_extra_header = {"note"};
  return o;
}

void ExpectWholeRows(const std::string& path, std::size_t min_rows) {
  const std::string text = params::ReadTextFile(path);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n') << "the log ends in a partial row";
  std::istringstream in(text);
  std::string line;
  std::size_t cells = 0, rows = 0;
  while (std::getline(in, line)) {
    const std::size_t n = static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) + 1;
    if (rows++ == 0) cells = n;
    EXPECT_EQ(n, cells) << "row " << rows << ": " << line;
  }
  EXPECT_GE(rows, min_rows + 1);
}

TEST_F(WriteFailureTest, TunerLogIntoAMissingFolderNamesThePath) {
  const std::string path = Path("missing/evaluations.csv");
  const std::string msg = Message([&] { Tune({0.5, 0.5}, Bowl, LogOptions(path)); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_TRUE(Listing().empty());
}

TEST_F(WriteFailureTest, TunerLogOnDevFullNamesThePath) {
  const std::string msg = Message([&] { Tune({0.5, 0.5}, Bowl, LogOptions("/dev/full")); });
  EXPECT_NE(msg.find("/dev/full"), std::string::npos) << msg;
}

TEST_F(WriteFailureTest, TunerLogOnAFullDiskKeepsWholeRowsAndNamesThePath) {
  const std::string path = Path("evaluations.csv");
  std::string msg;
  {
    DiskFull full(6000);  // room for the header and a few dozen rows
    msg = Message([&] { Tune({0.5, 0.5}, Bowl, LogOptions(path)); });
  }
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  ExpectWholeRows(path, 10);
  EXPECT_EQ(Listing(), std::set<std::string>{"evaluations.csv"});
}

}  // namespace
}  // namespace scw::tuning
