#include "tuning/sim/sweep/sweep_processes.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <stdexcept>
#include <utility>

#include "params/schema/field.h"

namespace scw::tuning::detail {
namespace {

std::string Multiline(std::string s) {
  for (char& c : s)
    if (c == '\x1f') c = '\n';
  return s;
}

bool WriteAll(int fd, const std::string& s) {
  std::size_t done = 0;
  while (done < s.size()) {
    const ssize_t n = write(fd, s.data() + done, s.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

std::string StatusText(int status) {
  if (WIFSIGNALED(status))
    return "was killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
           strsignal(WTERMSIG(status)) + ")";
  if (WIFEXITED(status)) {
    if (WEXITSTATUS(status) == 127) return "could not be started (exit code 127)";
    return "exited with code " + std::to_string(WEXITSTATUS(status));
  }
  return "ended abnormally";
}

[[noreturn]] void Fail(const std::string& what) { throw std::runtime_error(what); }

}  // namespace

std::string OneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = '\x1f';
  return s;
}

SweepProcessPool::SweepProcessPool(std::vector<std::string> argv, int n,
                                   std::function<std::string(int)> label)
    : label_(std::move(label)) {
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGPIPE, &ignore, &old_sigpipe_);  // a dead worker's pipe: EPIPE, not death
  argv.push_back("--worker-fd=3");
  std::vector<char*> cargv;
  for (auto& a : argv) cargv.push_back(a.data());
  cargv.push_back(nullptr);
  for (int w = 0; w < n; ++w) {
    int to[2], from[2];
    if (pipe2(to, O_CLOEXEC) != 0) Fail("cannot create a pipe");
    if (pipe2(from, O_CLOEXEC) != 0) {
      close(to[0]);
      close(to[1]);
      Fail("cannot create a pipe");
    }
    const pid_t pid = fork();
    if (pid == 0) {  // child: async-signal-safe calls only
      if (dup2(to[0], 0) < 0 || dup2(from[1], 3) < 0 || dup2(2, 1) < 0) _exit(127);
      execv(cargv[0], cargv.data());
      _exit(127);
    }
    close(to[0]);
    close(from[1]);
    if (pid < 0) {
      close(to[1]);
      close(from[0]);
      Fail("cannot start a worker process");
    }
    workers_.push_back({pid, to[1], from[0], {}, -1});
  }
}

SweepProcessPool::~SweepProcessPool() {
  for (auto& w : workers_) {
    if (w.to >= 0) close(w.to);
    if (w.from >= 0) close(w.from);
    if (w.pid > 0) {
      kill(w.pid, SIGTERM);
      waitpid(w.pid, nullptr, 0);
    }
  }
  sigaction(SIGPIPE, &old_sigpipe_, nullptr);
}

void SweepProcessPool::Run(const std::vector<int>& jobs,
                           const std::function<void(int, const char*)>& on_result) {
  std::size_t next = 0, pending = 0;
  std::map<int, std::pair<bool, std::string>> errors;  // run → (config error, message)
  const auto assign = [&](Worker& w) {
    if (next >= jobs.size()) return;
    w.job = jobs[next++];
    const std::string line = "run " + std::to_string(w.job) + "\n";
    if (!WriteAll(w.to, line)) Died(w);
    ++pending;
  };
  for (auto& w : workers_) assign(w);
  std::vector<pollfd> fds(workers_.size());
  while (pending > 0) {
    for (std::size_t k = 0; k < workers_.size(); ++k)
      fds[k] = {workers_[k].job >= 0 ? workers_[k].from : -1, POLLIN, 0};
    if (poll(fds.data(), fds.size(), -1) < 0) {
      if (errno == EINTR) continue;
      Fail("poll failed");
    }
    for (std::size_t k = 0; k < workers_.size(); ++k) {
      if (fds[k].revents == 0) continue;
      Worker& w = workers_[k];
      char buf[4096];
      const ssize_t got = read(w.from, buf, sizeof buf);
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) Died(w);
      w.buf.append(buf, static_cast<std::size_t>(got));
      std::size_t eol;
      while ((eol = w.buf.find('\n')) != std::string::npos) {
        const std::string line = w.buf.substr(0, eol);
        w.buf.erase(0, eol + 1);
        int job = -1, used = 0;
        if (line.rfind("ok ", 0) == 0 && std::sscanf(line.c_str(), "ok %d%n", &job, &used) == 1 &&
            job == w.job) {
          on_result(job, line.c_str() + used);
        } else if (line.rfind("error ", 0) == 0 &&
                   std::sscanf(line.c_str(), "error %d%n", &job, &used) == 1 && job == w.job &&
                   line.size() > static_cast<std::size_t>(used) + 2) {
          const bool config = line[static_cast<std::size_t>(used) + 1] == 'C';
          errors[job] = {config, Multiline(line.substr(static_cast<std::size_t>(used) + 3))};
        } else {
          Fail("sweep worker process " + std::to_string(w.pid) + " sent an unreadable line for " +
               label_(w.job) + ": '" + line.substr(0, 200) + "'");
        }
        w.job = -1;
        --pending;
        assign(w);
      }
    }
  }
  if (!errors.empty()) {
    const auto& [job, e] = *errors.begin();
    if (e.first) throw ConfigError("scw sweep", "", label_(job) + ": " + e.second);
    throw std::runtime_error(label_(job) + ": " + e.second);
  }
}

void SweepProcessPool::Finish() {
  for (auto& w : workers_) {
    close(w.to);
    w.to = -1;
  }
  for (auto& w : workers_) {
    int status = 0;
    const pid_t pid = w.pid;
    waitpid(pid, &status, 0);
    w.pid = -1;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
      Fail("sweep worker process " + std::to_string(pid) + " " + StatusText(status) +
           " at the end of the sweep");
  }
}

void SweepProcessPool::Died(Worker& w) {
  int status = 0;
  const pid_t pid = w.pid;
  if (w.from >= 0) close(w.from);
  w.from = -1;
  kill(pid, SIGTERM);
  waitpid(pid, &status, 0);
  w.pid = -1;
  Fail("sweep worker process " + std::to_string(pid) + " " + StatusText(status) +
       " while computing " + label_(w.job) + "; no table written");
}

}  // namespace scw::tuning::detail
