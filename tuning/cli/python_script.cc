#include "tuning/cli/python_script.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

extern char** environ;

namespace scw::cli {
namespace {

struct Outcome {
  int spawn_error = 0;
  int exit_code = -1;  ///< -1: ended by a signal
  std::string output;  ///< stdout and stderr
};

// The script goes to the child's stdin through a socket (a child that dies early gives EPIPE, not
// SIGPIPE, with MSG_NOSIGNAL); Python reads it whole before it runs, so writing first cannot block
// on the child's output.
Outcome Run(const std::string& python, std::string_view script,
            const std::vector<std::string>& args) {
  Outcome o;
  int sv[2], fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) {
    o.spawn_error = errno;
    return o;
  }
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    o.spawn_error = errno;
    ::close(sv[0]);
    ::close(sv[1]);
    return o;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, sv[1], 0);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 2);
  std::vector<std::string> all = {python, "-"};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int rc = ::posix_spawnp(&pid, python.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(sv[1]);
  ::close(fds[1]);
  if (rc != 0) {
    o.spawn_error = rc;
    ::close(sv[0]);
    ::close(fds[0]);
    return o;
  }
  std::size_t sent = 0;
  while (sent < script.size()) {
    const ssize_t n = ::send(sv[0], script.data() + sent, script.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    sent += static_cast<std::size_t>(n);
  }
  ::close(sv[0]);
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    if (o.output.size() < (1u << 20)) o.output.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return o;
  if (WIFEXITED(status)) o.exit_code = WEXITSTATUS(status);
  return o;
}

std::string LastLine(const std::string& text) {
  std::string last;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(pos, end - pos);
    if (!line.empty()) last = line;
    pos = end + 1;
  }
  return last;
}

}  // namespace

bool RunPythonScript(std::string_view script, const std::vector<std::string>& args,
                     std::string* message) {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("SCW_PYTHON"); env && *env)
    candidates.push_back(env);
  else
    candidates = {"python3", "/usr/bin/python3"};
  std::string tried;
  for (const auto& python : candidates) {
    const Outcome o = Run(python, script, args);
    if (o.spawn_error != 0 || o.exit_code == kScriptNoMatplotlib) {
      tried += (tried.empty() ? "" : ", ") + python;
      continue;
    }
    if (o.exit_code == 0) {
      message->clear();
      return true;
    }
    *message = "the plot script (" + python + ") failed: " + LastLine(o.output);
    return false;
  }
  *message = "no Python with matplotlib found (tried " + tried +
             "; Debian: apt-get install python3-matplotlib, or set SCW_PYTHON)";
  return false;
}

}  // namespace scw::cli
