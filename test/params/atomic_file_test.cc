// Output targets that are not plain files (issue 15): a symlink stays a symlink and its target gets
// the content, a FIFO and a character device are written in place, `-` is standard output (no
// file named `-`), a /proc magic link such as /dev/stdout is never replaced, an existing file
// keeps its mode, and the registry of temporary files lets a signal handler remove them.
//
// No test writes to a real device node or to /dev/stdout itself: a regression would then damage
// the machine running the tests (as `scw params init -o /dev/stdout` did, run as root). Links and
// device nodes are made inside the test's own folder.
#include "params/io/atomic_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "params/io/yaml_doc.h"

namespace scw::io {
namespace {

namespace fs = std::filesystem;
using params::ReadTextFile;

class AtomicWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("scw_atomic_writer_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
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

  static unsigned Mode(const std::string& path) {
    struct stat st {};
    EXPECT_EQ(::stat(path.c_str(), &st), 0) << path;
    return st.st_mode & 07777;
  }

  fs::path dir_;
};

// Points file descriptor 1 at `path` (a file or FIFO opened for writing) for its lifetime.
class StdoutTo {
 public:
  explicit StdoutTo(int fd) {
    std::fflush(stdout);
    saved_ = ::dup(STDOUT_FILENO);
    ::dup2(fd, STDOUT_FILENO);
  }
  ~StdoutTo() {
    std::fflush(stdout);
    ::dup2(saved_, STDOUT_FILENO);
    ::close(saved_);
  }

 private:
  int saved_ = -1;
};

TEST_F(AtomicWriterTest, RelativeSymlinkStaysALinkAndItsTargetGetsTheContent) {
  std::ofstream(Path("real.yaml")) << "old\n";
  fs::create_symlink("real.yaml", Path("link.yaml"));
  WriteFileAtomic(Path("link.yaml"), "new\n");
  EXPECT_TRUE(fs::is_symlink(Path("link.yaml")));
  EXPECT_EQ(fs::read_symlink(Path("link.yaml")), fs::path("real.yaml"));
  EXPECT_EQ(ReadTextFile(Path("real.yaml")), "new\n");
  EXPECT_EQ(Listing(), (std::set<std::string>{"link.yaml", "real.yaml"}));
}

TEST_F(AtomicWriterTest, SymlinkChainIntoAnotherFolderWritesTheFinalTarget) {
  fs::create_directories(dir_ / "car");
  const std::string real = (dir_ / "car" / "stability.yaml").string();
  std::ofstream(real) << "old\n";
  fs::create_symlink(real, Path("hop.yaml"));            // absolute
  fs::create_symlink("hop.yaml", Path("current.yaml"));  // relative, onto a link
  AtomicWriter w(Path("current.yaml"));
  EXPECT_EQ(w.mode(), AtomicWriter::Mode::kReplace);
  EXPECT_EQ(w.target(), real);
  w.Append("new\n");
  w.Commit();
  EXPECT_TRUE(fs::is_symlink(Path("current.yaml")));
  EXPECT_TRUE(fs::is_symlink(Path("hop.yaml")));
  EXPECT_EQ(ReadTextFile(real), "new\n");
  EXPECT_EQ(Listing(), (std::set<std::string>{"car", "current.yaml", "hop.yaml"}));
  EXPECT_EQ(fs::directory_iterator(dir_ / "car")->path().filename(), "stability.yaml");
}

TEST_F(AtomicWriterTest, DanglingSymlinkCreatesItsTarget) {
  fs::create_symlink("later.yaml", Path("link.yaml"));
  WriteFileAtomic(Path("link.yaml"), "a: 1.0\n");
  EXPECT_TRUE(fs::is_symlink(Path("link.yaml")));
  EXPECT_EQ(ReadTextFile(Path("later.yaml")), "a: 1.0\n");
}

TEST_F(AtomicWriterTest, FifoIsWrittenInPlaceAndStaysAFifo) {
  const std::string fifo = Path("pipe");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string text;
  for (int i = 0; i < 20000; ++i) text += "row " + std::to_string(i) + "\n";  // > a pipe buffer
  std::string received;
  std::thread reader([&] {
    std::ifstream in(fifo, std::ios::binary);
    received.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  });
  WriteFileAtomic(fifo, text);
  reader.join();
  EXPECT_EQ(received, text);
  struct stat st {};
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  EXPECT_EQ(Listing(), std::set<std::string>{"pipe"});
}

TEST_F(AtomicWriterTest, CharacterDeviceIsWrittenInPlace) {
  // A private /dev/null (major 1, minor 3) in the test folder; needs CAP_MKNOD and a container
  // that lets us open it.
  const std::string dev = Path("null");
  if (::mknod(dev.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0)
    GTEST_SKIP() << "cannot create a device node here (no CAP_MKNOD)";
  const int probe = ::open(dev.c_str(), O_WRONLY);
  if (probe < 0) GTEST_SKIP() << "device nodes cannot be opened here";
  ::close(probe);
  AtomicWriter w(dev);
  EXPECT_EQ(w.mode(), AtomicWriter::Mode::kDirect);
  w.Append("discarded\n");
  w.Commit();
  struct stat st {};
  ASSERT_EQ(::lstat(dev.c_str(), &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
  EXPECT_EQ(Listing(), std::set<std::string>{"null"});
}

TEST_F(AtomicWriterTest, DashIsStandardOutputAndCreatesNoFile) {
  const std::string capture = Path("capture.txt");
  const int fd = ::open(capture.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(fd, 0);
  const fs::path cwd = fs::current_path();
  fs::current_path(dir_);  // a file named "-" would appear here
  {
    StdoutTo redirect(fd);
    std::printf("before\n");  // buffered text printed earlier comes first
    AtomicWriter w("-");
    EXPECT_EQ(w.mode(), AtomicWriter::Mode::kStdout);
    w.Append("a: 1.0\n");
    w.Commit();
  }
  fs::current_path(cwd);
  ::close(fd);
  EXPECT_EQ(ReadTextFile(capture), "before\na: 1.0\n");
  EXPECT_EQ(Listing(), std::set<std::string>{"capture.txt"});
}

TEST_F(AtomicWriterTest, ProcMagicLinkLikeDevStdoutIsNeverReplaced) {
  // dir/stdout -> /proc/self/fd/1 is exactly what /dev/stdout is. Standard output is a regular
  // file here (the hard case: a rename would succeed and replace the link).
  const std::string link = Path("stdout");
  fs::create_symlink("/proc/self/fd/1", link);
  const std::string capture = Path("capture.txt");
  const int fd = ::open(capture.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(fd, 0);
  {
    StdoutTo redirect(fd);
    AtomicWriter w(link);
    EXPECT_EQ(w.mode(), AtomicWriter::Mode::kDirect);
    w.Append("a: 1.0\n");
    w.Commit();
  }
  ::close(fd);
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(fs::read_symlink(link), fs::path("/proc/self/fd/1"));
  EXPECT_EQ(ReadTextFile(capture), "a: 1.0\n");
  EXPECT_EQ(Listing(), (std::set<std::string>{"capture.txt", "stdout"}));
}

TEST_F(AtomicWriterTest, StdoutLinkWritesThroughTheDescriptorAndKeepsAppendMode) {
  // `scw params init -o /dev/stdout >> log` must append, as `-o - >> log` does. Both spellings of
  // the link: straight into /proc, and through /dev/fd (itself a link to /proc/self/fd).
  std::vector<std::string> targets = {"/proc/self/fd/1"};
  if (fs::is_symlink("/dev/fd")) targets.push_back("/dev/fd/1");
  for (const std::string& to : targets) {
    const std::string link = Path("out"), capture = Path("log.txt");
    fs::remove(link);
    fs::create_symlink(to, link);
    std::ofstream(capture) << "first\n";
    const int fd = ::open(capture.c_str(), O_WRONLY | O_APPEND);
    ASSERT_GE(fd, 0);
    {
      StdoutTo redirect(fd);
      AtomicWriter w(link);
      EXPECT_EQ(w.mode(), AtomicWriter::Mode::kDirect) << to;
      w.Append("a: 1.0\n");
      w.Commit();
    }
    ::close(fd);
    EXPECT_EQ(ReadTextFile(capture), "first\na: 1.0\n") << to;
    EXPECT_TRUE(fs::is_symlink(link)) << to;
    EXPECT_EQ(Listing(), (std::set<std::string>{"log.txt", "out"})) << to;
  }
}

TEST_F(AtomicWriterTest, ProcMagicLinkToAPipeIsWrittenInPlace) {
  const std::string link = Path("stdout");
  fs::create_symlink("/proc/self/fd/1", link);
  int p[2];
  ASSERT_EQ(::pipe(p), 0);
  std::string received;
  std::thread reader([&] {
    char buf[4096];
    ssize_t n;
    while ((n = ::read(p[0], buf, sizeof(buf))) > 0) received.append(buf, static_cast<size_t>(n));
  });
  {
    StdoutTo redirect(p[1]);
    ::close(p[1]);
    WriteFileAtomic(link, "a: 1.0\n");
  }  // fd 1 restored: the pipe's last writer is gone, the reader sees EOF
  reader.join();
  ::close(p[0]);
  EXPECT_EQ(received, "a: 1.0\n");
  EXPECT_TRUE(fs::is_symlink(link));
}

TEST_F(AtomicWriterTest, ExistingFileKeepsItsMode) {
  // A write-protected file (0444) is refused instead (WriteFailureTest).
  for (unsigned mode : {0600u, 0640u, 0755u, 0664u}) {
    const std::string path = Path("file_" + std::to_string(mode));
    std::ofstream(path) << "old\n";
    ASSERT_EQ(::chmod(path.c_str(), mode), 0);
    WriteFileAtomic(path, "new\n");
    EXPECT_EQ(Mode(path), mode) << std::oct << mode;
    EXPECT_EQ(ReadTextFile(path), "new\n");
  }
}

TEST_F(AtomicWriterTest, SymlinkTargetKeepsItsMode) {
  std::ofstream(Path("real.yaml")) << "old\n";
  ASSERT_EQ(::chmod(Path("real.yaml").c_str(), 0600), 0);
  fs::create_symlink("real.yaml", Path("link.yaml"));
  WriteFileAtomic(Path("link.yaml"), "new\n");
  EXPECT_EQ(Mode(Path("real.yaml")), 0600u);
}

TEST_F(AtomicWriterTest, NewFileGetsTheUmaskMode) {
  const mode_t previous = ::umask(027);
  WriteFileAtomic(Path("new.yaml"), "a: 1.0\n");
  ::umask(previous);
  EXPECT_EQ(Mode(Path("new.yaml")), 0640u);
}

TEST_F(AtomicWriterTest, TemporaryFilesAreRegisteredUntilCommitAndRemovable) {
  const int before = RegisteredTemporaryFiles();
  const std::string path = Path("trace.csv");
  {
    AtomicWriter a(path);
    a.Append("t\n");
    EXPECT_EQ(RegisteredTemporaryFiles(), before + 1);
    EXPECT_EQ(Listing().size(), 1u);  // the temporary file
    EXPECT_NE(Listing().begin()->find("trace.csv.tmp." + std::to_string(::getpid()) + "."),
              std::string::npos);
    RemoveTemporaryFiles();  // what the SIGINT/SIGTERM handler does
    EXPECT_TRUE(Listing().empty());
  }  // the destructor finds its file gone: harmless
  EXPECT_EQ(RegisteredTemporaryFiles(), before);
  {
    AtomicWriter b(path);
    b.Append("t\n");
    b.Commit();
    EXPECT_EQ(RegisteredTemporaryFiles(), before);
    RemoveTemporaryFiles();  // a committed file is not touched
  }
  EXPECT_EQ(ReadTextFile(path), "t\n");
  EXPECT_EQ(Listing(), std::set<std::string>{"trace.csv"});
}

TEST_F(AtomicWriterTest, LargeStreamedFileArrivesWhole) {
  const std::string path = Path("big.csv");
  std::string expected;
  {
    AtomicWriter w(path);
    for (int i = 0; i < 100000; ++i) {
      const std::string row = std::to_string(i) + ",0.125\n";
      expected += row;
      w.Append(row);
    }
    w.Commit();
  }
  EXPECT_EQ(ReadTextFile(path), expected);
}

}  // namespace
}  // namespace scw::io
