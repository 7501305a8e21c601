// Output files never damage anything (issue 15), end to end with the built program:
//  * Ctrl-C (SIGINT) or SIGTERM during `scw simulate --trace … --controller-log …`, raised at a
//    fixed controller step while the run is writing (SCW_TEST_FAULT): the program dies by that
//    signal, leaves no `*.tmp.<pid>.<n>` file, and the previous trace is unchanged;
//  * `scw params init -o -` writes to standard output and creates no file named `-`;
//  * `scw params init -o LINK` with LINK → /proc/self/fd/1 (what /dev/stdout is; made in the test
//    folder so that a regression cannot replace the machine's /dev/stdout) writes through it and
//    leaves the link in place.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "test/common/cli_run.h"

namespace {

namespace fs = std::filesystem;
using scw::test::Slurp;
class OutputTargetsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("scw_output_targets_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  std::set<std::string> Listing() const {
    std::set<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.insert(e.path().filename().string());
    return out;
  }

  // Starts `SCW_BIN args...` in the test folder, stdout and stderr into files; returns the pid.
  pid_t Start(const std::vector<std::string>& args, const std::string& out,
              const std::string& err) const {
    std::vector<std::string> argv_s = {SCW_BIN};
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    const std::string cwd = dir_.string();
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (o < 0 || e < 0 || ::dup2(o, 1) < 0 || ::dup2(e, 2) < 0 || ::chdir(cwd.c_str()) != 0)
        ::_exit(127);
      std::vector<char*> argv;
      for (auto& a : argv_s) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    return pid;
  }

  // Waits for the process (no timer: ctest's TIMEOUT bounds a hang); returns its wait status, or
  // -1 when waiting failed.
  static int Wait(pid_t pid) {
    int status = 0;
    return ::waitpid(pid, &status, 0) == pid ? status : -1;
  }

  // Names in the test folder that look like temporary files of an unfinished write.
  std::vector<std::string> Temporaries() const {
    std::vector<std::string> out;
    for (const auto& name : Listing())
      if (name.find(".tmp.") != std::string::npos) out.push_back(name);
    return out;
  }

  // Runs `scw simulate` with a trace, a controller log and a summary; the run raises `sig` in
  // itself at its 1500th controller step (15 s simulated, of 2 laps; a test-only fault point,
  // SCW_TEST_FAULT, docs/robustness.md), when both temporary files hold data; then checks that
  // nothing is left behind.
  void InterruptSimulate(int sig) {
    const std::string trace = Path("trace.csv"), log = Path("log.csv");
    std::ofstream(trace) << "previous trace\n";
    ::setenv("SCW_TEST_FAULT", sig == SIGINT ? "simulate-step:1500:INT" : "simulate-step:1500:TERM",
             1);
    const pid_t pid = Start({"simulate", "--trace", trace, "--controller-log", log, "--summary",
                             Path("summary.yaml"), "--set", "laps=2"},
                            Path("run.out"), Path("run.err"));
    ::unsetenv("SCW_TEST_FAULT");
    ASSERT_GT(pid, 0);
    const int status = Wait(pid);
    ASSERT_NE(status, -1) << "scw simulate did not end after the signal";
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit code " << WEXITSTATUS(status) << "\n"
                                     << Slurp(Path("run.err"));
    EXPECT_EQ(WTERMSIG(status), sig);
    EXPECT_EQ(Temporaries(), std::vector<std::string>{});
    EXPECT_EQ(Slurp(trace), "previous trace\n");
    EXPECT_FALSE(fs::exists(log));
    EXPECT_EQ(Listing(), (std::set<std::string>{"run.err", "run.out", "trace.csv"}));
  }

  fs::path dir_;
};

TEST_F(OutputTargetsTest, CtrlCDuringSimulateLeavesNoTemporaryFile) { InterruptSimulate(SIGINT); }

TEST_F(OutputTargetsTest, SigtermDuringSimulateLeavesNoTemporaryFile) {
  InterruptSimulate(SIGTERM);
}

TEST_F(OutputTargetsTest, ParamsInitDashWritesStandardOutputAndNoFile) {
  const pid_t pid = Start({"params", "init", "-o", "-"}, Path("out.txt"), Path("err.txt"));
  const int status = Wait(pid);
  ASSERT_TRUE(status != -1 && WIFEXITED(status)) << Slurp(Path("err.txt"));
  EXPECT_EQ(WEXITSTATUS(status), 0) << Slurp(Path("err.txt"));
  EXPECT_NE(Slurp(Path("out.txt")).find("ros__parameters:"), std::string::npos);
  EXPECT_EQ(Listing(), (std::set<std::string>{"err.txt", "out.txt"}));
}

TEST_F(OutputTargetsTest, ParamsInitThroughAStdoutLinkKeepsTheLink) {
  fs::create_symlink("/proc/self/fd/1", Path("stdout"));
  const pid_t pid =
      Start({"params", "init", "-o", Path("stdout")}, Path("out.txt"), Path("err.txt"));
  const int status = Wait(pid);
  ASSERT_TRUE(status != -1 && WIFEXITED(status)) << Slurp(Path("err.txt"));
  EXPECT_EQ(WEXITSTATUS(status), 0) << Slurp(Path("err.txt"));
  EXPECT_TRUE(fs::is_symlink(Path("stdout")));
  EXPECT_EQ(fs::read_symlink(Path("stdout")), fs::path("/proc/self/fd/1"));
  EXPECT_NE(Slurp(Path("out.txt")).find("ros__parameters:"), std::string::npos);
  EXPECT_EQ(Listing(), (std::set<std::string>{"err.txt", "out.txt", "stdout"}));
}

}  // namespace
