#include "tuning/exec/processes.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <utility>

namespace scw::tuning::exec {
namespace {

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

[[noreturn]] void Fail(const std::string& what) { throw WorkerError(what); }

std::string Hex(std::string_view bytes) {
  static const char kDigits[] = "0123456789abcdef";
  std::string s;
  s.reserve(2 * bytes.size());
  for (const char c : bytes) {
    const auto u = static_cast<unsigned char>(c);
    s += kDigits[u >> 4];
    s += kDigits[u & 15];
  }
  return s;
}

int Nibble(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

// Decodes `hex` into *bytes; false for an odd length or a non-digit.
bool Unhex(std::string_view hex, std::string* bytes) {
  if (hex.size() % 2 != 0) return false;
  bytes->resize(hex.size() / 2);
  for (std::size_t k = 0; k < bytes->size(); ++k) {
    const int hi = Nibble(hex[2 * k]), lo = Nibble(hex[2 * k + 1]);
    if (hi < 0 || lo < 0) return false;
    (*bytes)[k] = static_cast<char>(hi * 16 + lo);
  }
  return true;
}

// "<word> <i> <hex>" → i and the decoded bytes.
bool ParseAnswer(const std::string& line, const char* word, int* job, std::string* bytes) {
  const std::string head = std::string(word) + " ";
  if (line.rfind(head, 0) != 0) return false;
  int used = 0;
  if (std::sscanf(line.c_str() + head.size(), "%d %n", job, &used) != 1 || used == 0) return false;
  return Unhex(std::string_view(line).substr(head.size() + static_cast<std::size_t>(used)), bytes);
}

}  // namespace

ProcessPool::ProcessPool(std::vector<std::string> argv, int n, const std::string& kind,
                         const std::string& setup) {
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
  const std::string line = "setup " + kind + " " + Hex(setup) + "\n";
  for (auto& w : workers_)
    if (!WriteAll(w.to, line)) Died(w, "before its first job");
}

ProcessPool::~ProcessPool() {
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

void ProcessPool::Run(const std::string& payload, int jobs, const std::vector<int>& order,
                      const std::function<void(int, std::string_view)>& on_result,
                      const std::function<std::string(int)>& label) {
  if (jobs <= 0) return;
  if (!order.empty() && order.size() != static_cast<std::size_t>(jobs))
    throw std::logic_error("job order of the wrong length");
  const std::string batch = "batch " + Hex(payload) + "\n";
  for (auto& w : workers_)
    if (!WriteAll(w.to, batch)) Died(w, "before " + label(order.empty() ? 0 : order[0]));
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(jobs));
  int next = 0, pending = 0;
  const auto assign = [&](Worker& w) {
    if (next >= jobs) return;
    w.job = order.empty() ? next : order[static_cast<std::size_t>(next)];
    ++next;
    if (!WriteAll(w.to, "job " + std::to_string(w.job) + "\n"))
      Died(w, "while computing " + label(w.job));
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
      if (got <= 0) Died(w, "while computing " + label(w.job));
      w.buf.append(buf, static_cast<std::size_t>(got));
      std::size_t eol;
      while ((eol = w.buf.find('\n')) != std::string::npos) {
        const std::string line = w.buf.substr(0, eol);
        w.buf.erase(0, eol + 1);
        int job = -1;
        std::string bytes;
        if (w.job >= 0 && ParseAnswer(line, "ok", &job, &bytes) && job == w.job) {
          try {
            on_result(job, bytes);
          } catch (...) {
            errors[static_cast<std::size_t>(job)] = std::current_exception();
          }
        } else if (w.job >= 0 && ParseAnswer(line, "error", &job, &bytes) && job == w.job) {
          errors[static_cast<std::size_t>(job)] =
              std::make_exception_ptr(std::runtime_error(bytes));
        } else {
          Fail("worker process " + std::to_string(w.pid) + " sent an unreadable line" +
               (w.job >= 0 ? " for " + label(w.job) : std::string()) + ": '" + line.substr(0, 200) +
               "'");
        }
        w.job = -1;
        --pending;
        assign(w);
      }
    }
  }
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

void ProcessPool::Finish() {
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
      Fail("worker process " + std::to_string(pid) + " " + StatusText(status) +
           " after its last job");
  }
}

void ProcessPool::Died(Worker& w, const std::string& doing) {
  int status = 0;
  const pid_t pid = w.pid;
  if (w.from >= 0) close(w.from);
  w.from = -1;
  kill(pid, SIGTERM);
  waitpid(pid, &status, 0);
  w.pid = -1;
  Fail("worker process " + std::to_string(pid) + " " + StatusText(status) + " " + doing);
}

int ServeWorkerProcess(const TaskKinds& kinds, int in_fd, int out_fd) {
  FILE* in = fdopen(in_fd, "r");
  FILE* out = fdopen(out_fd, "w");
  if (in == nullptr || out == nullptr) return 1;
  std::unique_ptr<WorkerTask> task;
  // The task could not be prepared, or the batch not started: every job (of the batch) says so.
  std::string setup_error, batch_error;
  char* raw = nullptr;
  std::size_t capacity = 0;
  ssize_t got = 0;
  int code = 0;
  while ((got = getline(&raw, &capacity, in)) > 0) {
    std::string_view line(raw, static_cast<std::size_t>(got));
    if (line.back() == '\n') line.remove_suffix(1);
    std::string bytes, answer;
    int job = -1;
    if (line.rfind("setup ", 0) == 0) {
      const std::size_t space = line.find(' ', 6);
      const std::string kind(line.substr(6, space == std::string_view::npos ? 0 : space - 6));
      const auto it = kinds.find(kind);
      if (space == std::string_view::npos || !Unhex(line.substr(space + 1), &bytes)) {
        code = 1;
        break;
      }
      if (it == kinds.end()) {
        setup_error = "no task kind '" + kind + "' in this worker";
        continue;
      }
      try {
        task = it->second(bytes, 1);
      } catch (const std::exception& e) {
        setup_error = e.what();
      }
    } else if (line.rfind("batch ", 0) == 0) {
      if (!Unhex(line.substr(6), &bytes)) {
        code = 1;
        break;
      }
      batch_error.clear();
      if (!task) continue;
      try {
        task->StartBatch(bytes);
      } catch (const std::exception& e) {
        batch_error = e.what();
      }
    } else if (std::sscanf(std::string(line).c_str(), "job %d", &job) == 1) {
      const std::string& error = setup_error.empty() ? batch_error : setup_error;
      if (!error.empty() || !task) {
        answer = "error " + std::to_string(job) + " " +
                 Hex(error.empty() ? "the task was not set up in this worker" : error);
      } else {
        try {
          answer = "ok " + std::to_string(job) + " " + Hex(task->Run(job));
        } catch (const std::exception& e) {
          answer = "error " + std::to_string(job) + " " + Hex(e.what());
        }
      }
      if (std::fputs((answer + "\n").c_str(), out) < 0 || std::fflush(out) != 0) {
        code = 1;
        break;
      }
    } else {
      code = 1;
      break;
    }
  }
  std::free(raw);
  return code;
}

}  // namespace scw::tuning::exec
