// The one writer behind every output file of the workspace (params exports, tuned files,
// comparisons, manifests, summaries, traces, controller logs, replay outputs, sweep tables, a
// resumed tune's evaluation log). No other code renames a temporary file onto an output.
//
// What the target path is decides how it is written (issue 15, "output files never damage
// anything"):
//   * a regular file, or a path that does not exist yet: atomically. The text goes to a temporary
//     file next to the target (`<target>.tmp.<pid>.<n>`, same folder, so the rename is atomic),
//     which Commit() flushes, fsyncs and renames onto the target. An existing file keeps its
//     permission bits (and, where the process may set them, its owner and group); a new file gets
//     0666 minus the umask, as any Unix tool would.
//   * a symbolic link: the link is followed (also when it dangles) and its final target is written
//     atomically as above; the link itself stays a link.
//   * a character device (/dev/null, a terminal), a FIFO, a /proc "magic" link such as
//     /dev/stdout → /proc/self/fd/1, or `-` (standard output): written directly, in place. These
//     are not files that a rename could replace without damage (replacing /dev/stdout with a
//     regular file breaks every program on the machine). A link to one of our own descriptors
//     (/dev/stdout, /dev/fd/N) writes through that descriptor, so `-o /dev/stdout >> log`
//     appends like `-o - >> log`. A failed direct write may have written part of the text.
//   * a block device or a socket: refused (std::runtime_error naming the path).
//   * a folder, or a path ending in '/': refused at once (std::runtime_error naming the path);
//     the folder is untouched.
//   * an existing regular file that is write-protected: refused at once, the file unchanged. The
//     rename needs write permission on the folder only, so the writer checks the file itself, as
//     `cp` does: for the effective user (faccessat, ACLs included), and for root, which may write
//     anything, a file without any write bit (e.g. 0444).
//
// Interruption: while a temporary file exists its name is in a process-wide registry (fixed size,
// no allocation). RemoveTemporaryFiles() unlinks every registered name and is async-signal-safe;
// InstallTemporaryFileCleanup() calls it from SIGINT/SIGTERM/SIGHUP handlers, so Ctrl-C in any
// command leaves no `*.tmp.*` file behind. Only SIGKILL or a power loss can.
//
// Errors throw std::runtime_error whose message starts with `cannot write <path>:`. Not
// thread-safe (one writer per thread); any number of writers may exist in different threads.
#pragma once

#include <string>
#include <string_view>

namespace scw::io {

class AtomicWriter {
 public:
  /// How the target is written (see the file comment).
  enum class Mode {
    kReplace,  ///< temporary file + rename (regular file, new file, followed symlink)
    kDirect,   ///< opened and written in place (character device, FIFO, /proc magic link)
    kStdout,   ///< `-`: standard output (file descriptor 1, not closed)
  };

  /// Opens the target (kDirect/kStdout) or creates the temporary file (kReplace). Throws
  /// std::runtime_error naming `path` if that is not possible. Opening a FIFO waits for a reader.
  explicit AtomicWriter(std::string path);
  /// Without Commit(): closes and removes the temporary file; the target keeps its content.
  ~AtomicWriter();
  AtomicWriter(const AtomicWriter&) = delete;
  AtomicWriter& operator=(const AtomicWriter&) = delete;

  /// Appends text (buffered). Throws std::runtime_error naming the path on a write error; the
  /// writer is then closed (kReplace: the temporary file is removed, the target unchanged) and
  /// further calls throw std::logic_error.
  void Append(std::string_view text);

  /// Writes what is buffered to the file (kReplace: still the temporary file) without finishing
  /// it, for a log that must report a full disk at the row that did not fit. Throws like Append.
  void Flush();

  /// Writes what is buffered and finishes the file: kReplace: fsync, close, rename onto the
  /// target; kDirect: close; kStdout: flush only. Throws std::runtime_error naming the path on
  /// failure (kReplace: the target is then unchanged and the temporary file removed).
  void Commit();

  /// The path as given (used in messages).
  const std::string& path() const noexcept { return path_; }
  /// The file actually written: the final target of a symlink chain (kReplace), else path().
  const std::string& target() const noexcept { return target_; }
  Mode mode() const noexcept { return mode_; }
  bool committed() const noexcept { return committed_; }

 private:
  void CloseQuietly() noexcept;
  [[noreturn]] void Fail(const std::string& what, int error);

  std::string path_;
  std::string target_;
  std::string tmp_;  ///< kReplace only
  Mode mode_ = Mode::kReplace;
  int fd_ = -1;
  int registry_slot_ = -1;
  bool committed_ = false;
  bool stdout_first_ = false;  ///< writes to standard output: flush stdio's buffer first
  std::string buffer_;
};

/// Writes `text` to `path` through an AtomicWriter (the rules above). Throws std::runtime_error
/// naming the path on failure; a regular target is then untouched and no temporary file remains.
void WriteFileAtomic(const std::string& path, const std::string& text);

/// Unlinks the temporary file of every AtomicWriter of this process that has not finished.
/// Async-signal-safe (reads the registry, calls unlink(2) only); the writers' destructors later
/// find their files gone, which is harmless.
void RemoveTemporaryFiles() noexcept;

/// Installs handlers for SIGINT, SIGTERM and SIGHUP that call RemoveTemporaryFiles() and then end
/// the process by the same signal with its default action (the exit status still says "killed
/// by SIGINT"). A signal that was ignored when the process started (nohup, background jobs) stays
/// ignored. A command that installs its own SIGINT handler for a graceful stop (scw tune) takes
/// precedence while it is installed. Call once, early in main().
void InstallTemporaryFileCleanup();

/// Number of temporary files currently registered (tests).
int RegisteredTemporaryFiles() noexcept;

}  // namespace scw::io
