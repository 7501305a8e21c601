// Ctrl-C during `scw tune`, end to end with the built program: SIGINT right after the second
// evaluation is logged (SCW_TEST_FAULT) → the process exits by itself (130, after writing its
// outputs), the log is a valid CSV of whole rows, the best-so-far params files exist and pass `scw
// params check`; then
// `--resume DIR/evaluations.csv` with the same options completes in a fresh folder and its log
// starts with exactly the interrupted run's rows.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test/common/cli_run.h"

namespace {

namespace fs = std::filesystem;
using scw::test::CliResult;
using scw::test::RunCli;
using scw::test::Slurp;
// Starts `SCW_BIN args...` with stdout/stderr into `capture`; returns the pid.
pid_t Start(const std::vector<std::string>& args, const std::string& capture) {
  std::vector<std::string> argv_s = {SCW_BIN};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(capture.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, 1);
      ::dup2(fd, 2);
    }
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
int Wait(pid_t pid) {
  int status = 0;
  return ::waitpid(pid, &status, 0) == pid ? status : -1;
}

std::vector<std::string> Lines(const std::string& path) {
  std::vector<std::string> out;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) out.push_back(line);
  return out;
}

std::size_t Cells(const std::string& line) {
  return static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) + 1;
}

/// A fresh folder `name`_<pid> under the temporary directory holding set.yaml, a one-lap scenario
/// set; returns the folder.
fs::path TinySetFolder(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "set.yaml")
      << "name: tiny\n"
         "training:\n"
         "  - {name: one_lap, weight: 1.0, set: [laps=1, gg_scale=1.1]}\n";
  return dir;
}

TEST(TuneInterruptTest, CtrlCKeepsLogAndBestAndResumeContinues) {
  const fs::path dir = TinySetFolder("scw_tune_interrupt");
  const std::string set = (dir / "set.yaml").string();
  const std::vector<std::string> common = {
      "tune",  "--scenarios", set, "--max-evals", "40", "--threads",       "1", "--progress",
      "never", "--seed",      "3", "--max-time",  "0",  "--no-sensitivity"};
  const fs::path run1 = dir / "run1", run2 = dir / "run2";
  const std::string log1 = (run1 / "evaluations.csv").string();
  const std::string log2 = (run2 / "evaluations.csv").string();

  auto args1 = common;
  args1.insert(args1.end(), {"--out", run1.string()});
  // SIGINT right after the second evaluation is logged: a test-only fault point
  // (SCW_TEST_FAULT, docs/robustness.md), so the signal arrives at the same place on any machine.
  ::setenv("SCW_TEST_FAULT", "tune-eval:2:INT", 1);
  const pid_t pid = Start(args1, (dir / "run1.out").string());
  ::unsetenv("SCW_TEST_FAULT");
  ASSERT_GT(pid, 0);
  const int status = Wait(pid);
  ASSERT_NE(status, -1) << "scw tune did not exit after SIGINT";
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 130) << Slurp((dir / "run1.out").string());

  // The log: header + whole rows, fewer than the budget.
  const std::string text1 = Slurp(log1);
  ASSERT_FALSE(text1.empty());
  EXPECT_EQ(text1.back(), '\n');
  const auto rows1 = Lines(log1);
  // One thread, one point at a time: the run stops before a third evaluation.
  ASSERT_EQ(rows1.size(), 3u) << text1;
  for (std::size_t i = 1; i < rows1.size(); ++i) {
    EXPECT_EQ(Cells(rows1[i]), Cells(rows1[0])) << "row " << i << ": " << rows1[i];
    EXPECT_EQ(rows1[i].rfind(std::to_string(i - 1) + ",", 0), 0u) << rows1[i];
  }
  EXPECT_NE(Slurp((run1 / "manifest.yaml").string()).find("stop_reason: interrupted"),
            std::string::npos);

  // The best-so-far params files pass the ROS 2 check.
  const std::string full = (run1 / "stability_tuned.yaml").string();
  const std::string over = (run1 / "stability_overrides.yaml").string();
  ASSERT_TRUE(fs::exists(full));
  ASSERT_TRUE(fs::exists(over));
  for (const std::string& args : {full, over + " --overrides"}) {
    const CliResult check = RunCli(SCW_BIN, "params check " + args, dir);
    EXPECT_EQ(check.code, 0) << check.all();
  }

  // Resume with the same options into a fresh folder: completes, starts with the same rows.
  std::string args2;
  for (const auto& a : common) args2 += a + " ";
  const CliResult resumed =
      RunCli(SCW_BIN, args2 + "--out " + run2.string() + " --resume " + log1, dir);
  ASSERT_EQ(resumed.code, 0) << resumed.all();
  const auto rows2 = Lines(log2);
  ASSERT_GT(rows2.size(), rows1.size());
  for (std::size_t i = 0; i < rows1.size(); ++i) EXPECT_EQ(rows2[i], rows1[i]) << "row " << i;
  const std::string manifest2 = Slurp((run2 / "manifest.yaml").string());
  EXPECT_NE(manifest2.find("replayed_evaluations: " + std::to_string(rows1.size() - 1)),
            std::string::npos)
      << manifest2;
  EXPECT_EQ(manifest2.find("stop_reason: interrupted"), std::string::npos) << manifest2;

  fs::remove_all(dir);
}

// Issue 50 finding 14: Ctrl-C during the screen (before the search) ended the program with 130,
// no message and an empty run folder left behind.
TEST(TuneInterruptTest, CtrlCBeforeTheSearchSaysSoAndLeavesNoEmptyFolder) {
  const fs::path dir = TinySetFolder("scw_tune_interrupt_screen");
  const std::string set = (dir / "set.yaml").string();
  const fs::path run = dir / "run";
  ::setenv("SCW_TEST_FAULT", "tune-screen:1:INT", 1);
  const pid_t pid = Start({"tune", "--scenarios", set, "--threads", "1", "--progress", "never",
                           "--out-dir", run.string()},
                          (dir / "out.txt").string());
  ::unsetenv("SCW_TEST_FAULT");
  ASSERT_GT(pid, 0);
  const int status = Wait(pid);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const std::string out = Slurp((dir / "out.txt").string());
  EXPECT_NE(out.find("interrupted during the screen: nothing was written (the empty folder"),
            std::string::npos)
      << out;
  EXPECT_FALSE(fs::exists(run)) << out;
  fs::remove_all(dir);
}

}  // namespace
