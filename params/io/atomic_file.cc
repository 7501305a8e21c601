#include "params/io/atomic_file.h"

#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace scw::io {

namespace {

// ---------------------------------------------------------------------------------------------
// Registry of temporary files, readable from a signal handler: fixed storage, lock-free atomics.
// A slot is free (0), being filled (1) or holds a live temporary file name (2). The owning pid
// guards against a forked child (between fork and exec) removing its parent's files.

constexpr int kSlots = 64;
constexpr int kFree = 0, kFilling = 1, kLive = 2;

struct Slot {
  std::atomic<int> state{kFree};
  std::atomic<pid_t> owner{0};
  char path[PATH_MAX];
};

Slot g_slots[kSlots];
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<pid_t>::is_always_lock_free,
              "the signal handler needs lock-free atomics");

int Register(const std::string& path) noexcept {
  if (path.size() >= PATH_MAX) return -1;  // still removed by the destructor
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (!g_slots[i].state.compare_exchange_strong(expected, kFilling, std::memory_order_acquire))
      continue;
    std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
    g_slots[i].owner.store(::getpid(), std::memory_order_relaxed);
    g_slots[i].state.store(kLive, std::memory_order_release);
    return i;
  }
  return -1;  // more than kSlots writers at once: these are removed by their destructors only
}

void Unregister(int slot) noexcept {
  if (slot >= 0) g_slots[slot].state.store(kFree, std::memory_order_release);
}

// ---------------------------------------------------------------------------------------------
// Signal handling

constexpr int kCleanupSignals[] = {SIGINT, SIGTERM, SIGHUP};

void RemoveTemporaryFilesAndDie(int sig) {
  const int saved_errno = errno;
  RemoveTemporaryFiles();
  // Die by the same signal (default action) so that the parent sees "killed by SIGINT". The
  // signal is blocked while this handler runs and is delivered when it returns.
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  ::sigaction(sig, &dfl, nullptr);
  ::raise(sig);
  errno = saved_errno;
}

// ---------------------------------------------------------------------------------------------
// Target classification

std::string Reason(int error) { return std::strerror(error); }

/// Where a symlink chain passes through /proc: such "magic" links (/dev/stdout →
/// /proc/self/fd/1, /dev/fd/N, /proc/self/fd/N) name an open file, not a path a rename may replace.
struct ProcLink {
  bool found = false;
  int own_fd = -1;  ///< N when the link is this process's /proc/<pid>/fd/N
};

/// If `link` (a symlink) lives in a /proc folder, says so, and which of our descriptors it is.
void CheckProcLink(const std::string& link, ProcLink* proc) {
  const std::size_t slash = link.rfind('/');
  const std::string folder = slash == std::string::npos ? "." : link.substr(0, slash + 1);
  const std::string name = slash == std::string::npos ? link : link.substr(slash + 1);
  char real[PATH_MAX];
  if (::realpath(folder.c_str(), real) == nullptr) return;
  const std::string dir(real);
  if (dir.rfind("/proc/", 0) != 0) return;
  proc->found = true;
  const std::string own = "/proc/" + std::to_string(::getpid()) + "/";
  const bool fd_folder = dir.size() >= 3 && dir.compare(dir.size() - 3, 3, "/fd") == 0;
  if (dir.rfind(own, 0) == 0 && fd_folder && !name.empty() && name.size() < 9 &&
      name.find_first_not_of("0123456789") == std::string::npos)
    proc->own_fd = std::stoi(name);
}

/// Follows the symlink chain of the last path component (directories are resolved by the
/// kernel; the rename happens in the final target's folder), noting links that live in /proc.
std::string ResolveFinalSymlinks(const std::string& path, ProcLink* proc) {
  std::string p = path;
  for (int depth = 0; depth < 40; ++depth) {
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return p;
    if (!proc->found) CheckProcLink(p, proc);
    char buf[PATH_MAX];
    const ssize_t n = ::readlink(p.c_str(), buf, sizeof(buf) - 1);
    if (n < 0)
      throw std::runtime_error("cannot write " + path + ": cannot read the symbolic link " + p +
                               " (" + Reason(errno) + ")");
    const std::string link(buf, static_cast<std::size_t>(n));
    if (!link.empty() && link.front() == '/') {
      p = link;
    } else {
      const std::size_t slash = p.rfind('/');
      p = slash == std::string::npos ? link : p.substr(0, slash + 1) + link;
    }
  }
  throw std::runtime_error("cannot write " + path + ": too many levels of symbolic links");
}

constexpr std::size_t kBufferSize = std::size_t{1} << 18;

/// Whether an existing regular file must not be replaced: the rename needs write permission on
/// the folder only, so the file's own permission is checked here, as `cp` and the shell's `>`
/// would (for the effective user, ACLs included). For root, which the kernel lets write anything,
/// a file with no write bit at all (e.g. 0444) counts as write-protected too: such a file is
/// protected on purpose (docs/robustness.md).
bool WriteProtected(const std::string& file, const struct stat& st) {
  if (::geteuid() == 0) return (st.st_mode & 0222) == 0;
  return ::faccessat(AT_FDCWD, file.c_str(), W_OK, AT_EACCESS) != 0 && errno == EACCES;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// AtomicWriter

AtomicWriter::AtomicWriter(std::string path) : path_(std::move(path)), target_(path_) {
  if (path_.empty()) throw std::runtime_error("cannot write an output file: the path is empty");
  buffer_.reserve(kBufferSize);
  if (path_ == "-") {
    mode_ = Mode::kStdout;
    fd_ = STDOUT_FILENO;
    stdout_first_ = true;
    return;
  }

  struct stat st {};
  const bool exists = ::stat(path_.c_str(), &st) == 0;
  if (exists && S_ISDIR(st.st_mode))
    throw std::runtime_error("cannot write " + path_ + ": it is a folder; give a file name (e.g. " +
                             (path_.back() == '/' ? path_ : path_ + "/") + "NAME)");
  if (path_.back() == '/')
    throw std::runtime_error("cannot write " + path_ +
                             ": a file name cannot end in '/' (and no such folder exists)");
  if (exists && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode)) {
    if (!S_ISCHR(st.st_mode) && !S_ISFIFO(st.st_mode))
      throw std::runtime_error("cannot write " + path_ + ": it is " +
                               (S_ISBLK(st.st_mode) ? "a block device" : "not a file") +
                               "; write to a regular file, a character device, a FIFO or - "
                               "(standard output)");
    mode_ = Mode::kDirect;
  }
  ProcLink proc;
  if (mode_ == Mode::kReplace) target_ = ResolveFinalSymlinks(path_, &proc);
  if (proc.found && exists) {
    // e.g. /dev/stdout while standard output is redirected to a file: never replace that file.
    mode_ = Mode::kDirect;
    target_ = path_;
    if (proc.own_fd >= 0) {
      // One of our own descriptors (/dev/stdout, /dev/fd/N): write through a duplicate, which
      // shares its offset and flags, so `>> file` still appends, as with `-`.
      fd_ = ::fcntl(proc.own_fd, F_DUPFD_CLOEXEC, 0);
      if (fd_ >= 0) {
        stdout_first_ = proc.own_fd == STDOUT_FILENO;
        return;
      }
    }
  }

  if (mode_ == Mode::kDirect) {
    fd_ = ::open(path_.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC | O_NOCTTY);
    if (fd_ < 0) throw std::runtime_error("cannot write " + path_ + ": " + Reason(errno));
    return;
  }

  static std::atomic<unsigned> counter{0};
  const bool keep_mode = exists && S_ISREG(st.st_mode);
  if (keep_mode && WriteProtected(target_, st)) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    throw std::runtime_error("cannot write " + path_ + ": " +
                             (target_ != path_ ? "its target " + target_ + " " : std::string()) +
                             "is write-protected (mode " + mode +
                             "); the file was not changed. Make it writable (chmod u+w) or remove "
                             "it first, or write elsewhere");
  }
  int error = 0;
  // A name left by a hard-killed run whose pid is reused: try the next one (O_EXCL never opens an
  // existing file or a planted link).
  for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
    tmp_ = target_ + ".tmp." + std::to_string(::getpid()) + "." +
           std::to_string(counter.fetch_add(1, std::memory_order_relaxed));
    // Registered before it exists: a signal between open() and registration must not leak it.
    registry_slot_ = Register(tmp_);
    fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC,
                 keep_mode ? (st.st_mode & 0777) : 0666);
    if (fd_ >= 0) break;
    error = errno;
    Unregister(registry_slot_);
    registry_slot_ = -1;
    if (error != EEXIST) break;
  }
  if (fd_ < 0) {
    throw std::runtime_error("cannot write " + path_ +
                             ": cannot create a temporary file next to it (" + Reason(error) +
                             "); the file was not changed");
  }
  if (keep_mode) {
    // Owner and group first (chown may clear set-id bits), then the exact mode. Both are best
    // effort: a user may not give a file away, and some file systems have no modes.
    if ((st.st_uid != ::geteuid() || st.st_gid != ::getegid()) &&
        ::fchown(fd_, st.st_uid, st.st_gid) != 0) {
      // keep our own ownership
    }
    if (::fchmod(fd_, st.st_mode & 07777) != 0) {
      // keep the creation mode
    }
  }
}

AtomicWriter::~AtomicWriter() { CloseQuietly(); }

void AtomicWriter::CloseQuietly() noexcept {
  if (fd_ >= 0 && mode_ != Mode::kStdout) ::close(fd_);
  fd_ = -1;
  if (mode_ == Mode::kReplace && !committed_ && !tmp_.empty()) ::unlink(tmp_.c_str());
  Unregister(registry_slot_);
  registry_slot_ = -1;
}

void AtomicWriter::Fail(const std::string& what, int error) {
  CloseQuietly();
  std::string msg = "cannot write " + path_ + ": " + what + " (" + Reason(error) + ")";
  if (mode_ == Mode::kReplace) msg += "; the file was not changed";
  throw std::runtime_error(msg);
}

void AtomicWriter::Flush() {
  if (fd_ < 0) throw std::logic_error("AtomicWriter::Flush after Commit or a failure: " + path_);
  if (buffer_.empty()) return;
  // Text the command printed to standard output before must come first.
  if (stdout_first_) std::fflush(stdout);
  std::size_t done = 0;
  while (done < buffer_.size()) {
    const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      Fail("write failed", errno);
    }
    done += static_cast<std::size_t>(n);
  }
  buffer_.clear();
}

void AtomicWriter::Append(std::string_view text) {
  if (fd_ < 0) throw std::logic_error("AtomicWriter::Append after Commit or a failure: " + path_);
  if (buffer_.size() + text.size() > kBufferSize) Flush();
  buffer_.append(text);
  if (buffer_.size() >= kBufferSize) Flush();
}

void AtomicWriter::Commit() {
  if (fd_ < 0) throw std::logic_error("AtomicWriter::Commit twice or after a failure: " + path_);
  Flush();
  switch (mode_) {
    case Mode::kStdout:
      fd_ = -1;
      break;
    case Mode::kDirect: {
      const int rc = ::close(fd_);
      fd_ = -1;
      if (rc != 0) Fail("close failed", errno);
      break;
    }
    case Mode::kReplace: {
      if (::fsync(fd_) != 0) Fail("fsync failed", errno);
      const int rc = ::close(fd_);
      fd_ = -1;
      if (rc != 0) Fail("close failed", errno);
      if (::rename(tmp_.c_str(), target_.c_str()) != 0) Fail("rename failed", errno);
      break;
    }
  }
  committed_ = true;
  Unregister(registry_slot_);  // after the rename: a signal in between finds no file, harmless
  registry_slot_ = -1;
}

void WriteFileAtomic(const std::string& path, const std::string& text) {
  AtomicWriter w(path);
  w.Append(text);
  w.Commit();
}

// ---------------------------------------------------------------------------------------------
// Cleanup

void RemoveTemporaryFiles() noexcept {
  const pid_t self = ::getpid();
  for (auto& slot : g_slots)
    if (slot.state.load(std::memory_order_acquire) == kLive &&
        slot.owner.load(std::memory_order_relaxed) == self)
      ::unlink(slot.path);
}

void InstallTemporaryFileCleanup() {
  struct sigaction sa {};
  sa.sa_handler = &RemoveTemporaryFilesAndDie;
  sigemptyset(&sa.sa_mask);
  for (int sig : kCleanupSignals) sigaddset(&sa.sa_mask, sig);
  sa.sa_flags = SA_RESTART;
  for (int sig : kCleanupSignals) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    ::sigaction(sig, &sa, nullptr);
  }
}

int RegisteredTemporaryFiles() noexcept {
  int n = 0;
  for (const auto& slot : g_slots)
    if (slot.state.load(std::memory_order_acquire) == kLive) ++n;
  return n;
}

}  // namespace scw::io
