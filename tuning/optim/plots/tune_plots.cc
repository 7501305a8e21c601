#include "tuning/optim/plots/tune_plots.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "tuning/optim/plots/tune_plots_script.h"  // generated: generated::kTunePlotScript

extern char** environ;

namespace scw::tuning {
namespace {

constexpr int kExitBadInput = 2;  // the script's exit codes (tune_plots.py)
constexpr int kExitNoMatplotlib = 3;
constexpr const char* kPrefix = "tune_plots: ";

struct ScriptRun {
  int spawn_error = 0;  ///< errno of posix_spawnp (ENOENT: no such interpreter)
  int exit_code = -1;   ///< -1: killed by a signal (`signal`)
  int signal = 0;
  std::string output;  ///< stdout and stderr
};

class Fd {
 public:
  explicit Fd(int fd = -1) : fd_(fd) {}
  ~Fd() { Close(); }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }
  void Close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
};

// Runs `python - run_dir` with the script on stdin (a socket, so that a child that dies early
// gives EPIPE, not SIGPIPE: send() with MSG_NOSIGNAL) and its stdout/stderr collected. Python
// reads the whole script before it runs any of it, so writing it all first cannot deadlock.
ScriptRun Run(const std::string& python, const std::string& run_dir) {
  ScriptRun out;
  int sv[2], pipe_fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) {
    out.spawn_error = errno;
    return out;
  }
  Fd in_parent(sv[0]), in_child(sv[1]);
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) {
    out.spawn_error = errno;
    return out;
  }
  Fd out_parent(pipe_fds[0]), out_child(pipe_fds[1]);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in_child.get(), 0);
  posix_spawn_file_actions_adddup2(&actions, out_child.get(), 1);
  posix_spawn_file_actions_adddup2(&actions, out_child.get(), 2);
  std::vector<std::string> args = {python, "-", run_dir};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int rc = ::posix_spawnp(&pid, python.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  in_child.Close();
  out_child.Close();
  if (rc != 0) {
    out.spawn_error = rc;
    return out;
  }

  const std::string_view script = TunePlotScript();
  std::size_t sent = 0;
  while (sent < script.size()) {
    const ssize_t n =
        ::send(in_parent.get(), script.data() + sent, script.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // the child closed its stdin (died): its exit code tells why
    sent += static_cast<std::size_t>(n);
  }
  in_parent.Close();
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(out_parent.get(), buf, sizeof(buf));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    if (out.output.size() < (1u << 20)) out.output.append(buf, static_cast<std::size_t>(n));
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return out;
  if (WIFEXITED(status))
    out.exit_code = WEXITSTATUS(status);
  else if (WIFSIGNALED(status))
    out.signal = WTERMSIG(status);
  return out;
}

/// The script's reason: its last line that starts with the prefix (without it), else the last
/// non-empty line of its output.
std::string Reason(const std::string& output) {
  std::string last, tagged;
  std::size_t pos = 0;
  while (pos < output.size()) {
    std::size_t end = output.find('\n', pos);
    if (end == std::string::npos) end = output.size();
    std::string line = output.substr(pos, end - pos);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty()) last = line;
    if (line.rfind(kPrefix, 0) == 0) tagged = line.substr(std::strlen(kPrefix));
    pos = end + 1;
  }
  return tagged.empty() ? last : tagged;
}

bool Fail(std::string* message, const std::string& text) {
  if (message) *message = text;
  return false;
}

}  // namespace

std::string_view TunePlotScript() { return generated::kTunePlotScript; }

std::string TunePlotsMarkdown() {
  return std::string("### Plots\n\n") + "![Convergence: training cost of every evaluation and " +
         "the best cost so far, optimiser phases marked](" + kConvergencePlotFile + ")\n\n" +
         "![Baseline vs tuned per scenario: how the run ended, mean lap time, max sideslip, " +
         "interventions](" + kComparisonPlotFile + ")\n\n";
}

bool WriteTunePlots(const std::filesystem::path& run_dir, std::string* message,
                    const TunePlotOptions& options) {
  try {
    std::vector<std::string> candidates;
    if (!options.python.empty()) {
      candidates.push_back(options.python);
    } else if (const char* env = std::getenv("SCW_PYTHON"); env && *env) {
      candidates.push_back(env);
    } else {
      candidates = {"python3", "/usr/bin/python3"};
    }
    std::string without_matplotlib, not_found;
    for (const auto& python : candidates) {
      const ScriptRun r = Run(python, run_dir.string());
      if (r.spawn_error == ENOENT || r.spawn_error == EACCES || r.spawn_error == ENOTDIR) {
        not_found += (not_found.empty() ? "" : ", ") + python;
        continue;
      }
      if (r.spawn_error != 0)
        return Fail(message, "cannot start " + python + ": " + std::strerror(r.spawn_error));
      if (r.exit_code == kExitNoMatplotlib) {
        without_matplotlib += (without_matplotlib.empty() ? "" : ", ") + python;
        continue;
      }
      if (r.exit_code == 0) {
        for (const char* f : {kConvergencePlotFile, kComparisonPlotFile}) {
          std::error_code ec;
          if (std::filesystem::file_size(run_dir / f, ec) == 0 || ec)
            return Fail(message, "the plot script did not write " + (run_dir / f).string());
        }
        if (message) message->clear();
        return true;
      }
      const std::string reason = Reason(r.output);
      if (r.exit_code == -1)
        return Fail(message, "the plot script (" + python + ") was stopped by signal " +
                                 std::to_string(r.signal));
      if (r.exit_code == kExitBadInput) return Fail(message, reason);
      return Fail(message, "the plot script (" + python + ") failed" +
                               (reason.empty() ? " with exit code " + std::to_string(r.exit_code)
                                               : ": " + reason));
    }
    if (!without_matplotlib.empty())
      return Fail(message, "matplotlib is not installed for " + without_matplotlib +
                               " (Debian: apt-get install python3-matplotlib)");
    return Fail(message, "no Python interpreter found (tried " + not_found +
                             "; Debian: apt-get install python3 python3-matplotlib, or set "
                             "SCW_PYTHON)");
  } catch (const std::exception& e) {
    return Fail(message, std::string("cannot draw the plots: ") + e.what());
  } catch (...) {
    return Fail(message, "cannot draw the plots");
  }
}

}  // namespace scw::tuning
