#include "tuning/cli/python_script.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

extern char** environ;

namespace scw::cli {
namespace {

struct Outcome {
  int spawn_error = 0;  ///< errno of posix_spawnp (ENOENT: no such interpreter)
  int exit_code = -1;   ///< -1: ended by a signal (`signal`)
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

// Python reads the whole script before it runs any of it, so writing it all first cannot block
// on the child's output.
Outcome Run(const std::string& python, std::string_view script,
            const std::vector<std::string>& args) {
  Outcome out;
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
  std::vector<std::string> all = {python, "-"};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
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
    const ssize_t n = ::read(out_parent.get(), buf, sizeof buf);
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

/// The script's reason: its last line that starts with `prefix` (without it), else the last
/// non-empty line of its output.
std::string Reason(const std::string& output, const std::string& prefix) {
  std::string last, tagged;
  std::size_t pos = 0;
  while (pos < output.size()) {
    std::size_t end = output.find('\n', pos);
    if (end == std::string::npos) end = output.size();
    std::string line = output.substr(pos, end - pos);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (!line.empty()) last = line;
    if (!prefix.empty() && line.rfind(prefix, 0) == 0) tagged = line.substr(prefix.size());
    pos = end + 1;
  }
  return tagged.empty() ? last : tagged;
}

bool Fail(std::string* message, const std::string& text) {
  if (message) *message = text;
  return false;
}

}  // namespace

bool RunPythonScript(std::string_view script, const std::vector<std::string>& args,
                     std::string* message, const PythonScriptOptions& options) {
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
      const Outcome r = Run(python, script, args);
      if (r.spawn_error == ENOENT || r.spawn_error == EACCES || r.spawn_error == ENOTDIR) {
        not_found += (not_found.empty() ? "" : ", ") + python;
        continue;
      }
      if (r.spawn_error != 0)
        return Fail(message, "cannot start " + python + ": " + std::strerror(r.spawn_error));
      if (r.exit_code == kScriptNoMatplotlib) {
        without_matplotlib += (without_matplotlib.empty() ? "" : ", ") + python;
        continue;
      }
      if (r.exit_code == 0) {
        if (message) message->clear();
        return true;
      }
      const std::string reason = Reason(r.output, options.reason_prefix);
      if (r.exit_code == -1)
        return Fail(message, "the plot script (" + python + ") was stopped by signal " +
                                 std::to_string(r.signal));
      if (r.exit_code == kScriptBadInput) return Fail(message, reason);
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
    return Fail(message, std::string("cannot run the plot script: ") + e.what());
  } catch (...) {
    return Fail(message, "cannot run the plot script");
  }
}

}  // namespace scw::cli
