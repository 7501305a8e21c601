#include "tuning/exec/mpi_backend.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <initializer_list>
#include <iostream>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#ifdef SCW_HAVE_MPI
#include <mpi.h>
#endif

#include "params/io/test_fault.h"
#include "tuning/exec/parallel_for.h"
#include "tuning/exec/wire.h"

namespace scw::tuning::exec::mpi {
namespace {

int g_ranks = 1;
int g_rank = 0;
bool g_launched = false;
bool g_finalized = false;
std::thread::id g_main_thread;

// The note printed when rank 0 is stopped by SIGTERM (see OnTerminate).
char g_note[4096];
std::atomic<std::size_t> g_note_size{0};

}  // namespace

void SetTerminationNote(const std::string& note) {
  g_note_size = 0;
  const std::size_t n = std::min(note.size(), sizeof g_note);
  std::memcpy(g_note, note.data(), n);
  g_note_size = n;
}

#ifdef SCW_HAVE_MPI

// Debian's sequential MUMPS (loaded with Ipopt) exports a fake one-process MPI_Init,
// MPI_Comm_rank, MPI_Finalize and MPI_Wtime, and the dynamic loader binds a name to the first
// library that has it. For these four this file calls the PMPI_ names (the standard's second name
// of every MPI function), which only the MPI library defines; it never needs MPI_Init itself.

namespace {

// The job handed out at position p of a batch: order[p], or p without an order.
int JobAt(const std::vector<int>& order, int p) {
  return order.empty() ? p : order[static_cast<std::size_t>(p)];
}

void CheckOrder(const std::vector<int>& order, int jobs) {
  if (!order.empty() && order.size() != static_cast<std::size_t>(jobs))
    throw std::logic_error("job order of the wrong length");
}

void RethrowFirst(const std::vector<std::exception_ptr>& errors) {
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

constexpr int kTagToWorker = 1;
constexpr int kTagToRoot = 2;

enum Message : std::int64_t {
  // rank 0 → worker
  kPrepare = 1,  // id, kind, threads, setup
  kRelease,      // id
  kBatch,        // id, batch, payload
  kJob,          // batch, index
  kWait,         // batch: no job ahead of time now; ask again when a thread is free
  kNone,         // batch: no job left
  kStop,
  // worker → rank 0
  kRequest,  // batch, ahead (the worker's threads are all busy: a job to queue)
  kResult,   // batch, index, ok, bytes
  kDone,     // batch: every request answered, every job sent back
};

// SIGTERM on rank 0: say why, then hand over to the handler installed before (which removes
// temporary files and dies by the signal). Only async-signal-safe calls.
struct sigaction g_previous_term {};

extern "C" void OnTerminate(int sig) {
  const int saved_errno = errno;
  static const char kHead[] =
      "\nscw: stopped by SIGTERM. Under mpirun this means that another rank ended abnormally "
      "(mpirun names it) or that the job was cancelled.\n";
  ssize_t ignored = ::write(2, kHead, sizeof kHead - 1);
  const std::size_t n = g_note_size.load();
  if (n > 0) ignored = ::write(2, g_note, n);
  (void)ignored;
  ::sigaction(sig, &g_previous_term, nullptr);
  ::raise(sig);  // blocked until this handler returns
  errno = saved_errno;
}

std::int64_t g_next_task_id = 0;
std::int64_t g_next_batch = 0;

// Sleeps between polls: short at first (a reply is usually quick), up to 1 ms. (A cap of 200 µs
// was measured slower on 2 cores: the polls of two main threads take time from the jobs.)
class Backoff {
 public:
  std::chrono::microseconds Next() {
    us_ = us_ == 0 ? 20 : std::min(2 * us_, 1000);
    return std::chrono::microseconds(us_);
  }
  void Reset() { us_ = 0; }

 private:
  int us_ = 0;
};

bool TryReceive(int source, int tag, std::string* bytes, int* from) {
  int flag = 0;
  MPI_Status st;
  MPI_Iprobe(source, tag, MPI_COMM_WORLD, &flag, &st);
  if (!flag) return false;
  int n = 0;
  MPI_Get_count(&st, MPI_CHAR, &n);
  bytes->resize(static_cast<std::size_t>(n));
  MPI_Recv(bytes->data(), n, MPI_CHAR, st.MPI_SOURCE, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  if (from) *from = st.MPI_SOURCE;
  return true;
}

std::string WaitFromRoot() {
  std::string bytes;
  Backoff backoff;
  while (!TryReceive(0, kTagToWorker, &bytes, nullptr)) std::this_thread::sleep_for(backoff.Next());
  return bytes;
}

void SendToRoot(const std::string& bytes) {
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_CHAR, 0, kTagToRoot, MPI_COMM_WORLD);
}

// Rank 0's sends, all non-blocking (a worker busy preparing a task must not stall rank 0); the
// bytes live until the send completed. MPI keeps the order of messages to one worker.
class Outbox {
 public:
  void Post(int dest, std::shared_ptr<const std::string> bytes) {
    Item item{MPI_REQUEST_NULL, std::move(bytes)};
    MPI_Isend(item.bytes->data(), static_cast<int>(item.bytes->size()), MPI_CHAR, dest,
              kTagToWorker, MPI_COMM_WORLD, &item.request);
    items_.push_back(std::move(item));
  }
  void PostAll(const std::string& bytes) {
    const auto shared = std::make_shared<const std::string>(bytes);
    for (int w = 1; w < g_ranks; ++w) Post(w, shared);
  }
  /// Forgets the sends that completed.
  void Progress() {
    std::erase_if(items_, [](Item& item) {
      int done = 0;
      MPI_Test(&item.request, &done, MPI_STATUS_IGNORE);
      return done != 0;
    });
  }
  void Flush() {
    for (auto& item : items_) MPI_Wait(&item.request, MPI_STATUS_IGNORE);
    items_.clear();
  }

 private:
  struct Item {
    MPI_Request request;
    std::shared_ptr<const std::string> bytes;
  };
  std::vector<Item> items_;
};

Outbox& TheOutbox() {
  static Outbox outbox;
  return outbox;
}

std::string Header(Message type, std::int64_t a) {
  WireWriter w;
  w.Int(type);
  w.Int(a);
  return w.Take();
}

[[noreturn]] void ProtocolError(const std::string& what) {
  throw std::logic_error("MPI protocol error: " + what);
}

// A worker's copy of one task.
struct TaskSlot {
  std::unique_ptr<WorkerTask> task;
  std::string error;  // preparing it failed: every job answers this
  int threads = 1;
};

struct Done {
  int index;
  bool ok;
  std::string bytes;
};

// One batch on a worker. Each job thread has one job running and, while many jobs remain, one
// queued (asked for ahead of time, so the thread never waits for rank 0's answer); a result goes
// back as soon as its job ends. When rank 0 has said "none" and everything is answered and sent,
// the worker says "done". Returns false when rank 0 said stop instead.
bool ServeBatch(TaskSlot* slot, std::int64_t batch, std::string_view payload) {
  std::string error = slot->error;
  if (error.empty() && !slot->task) error = "the task was not prepared on this rank";
  if (error.empty()) {
    try {
      slot->task->StartBatch(payload);
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  const int threads = std::max(1, slot->threads);
  std::mutex mutex;
  std::condition_variable todo_cv, done_cv;
  std::deque<int> todo;
  std::deque<Done> done;
  bool closing = false;
  auto work = [&] {
    while (true) {
      int i = 0;
      {
        std::unique_lock<std::mutex> lock(mutex);
        todo_cv.wait(lock, [&] { return closing || !todo.empty(); });
        if (closing) return;
        i = todo.front();
        todo.pop_front();
      }
      Done d{i, error.empty(), error};
      if (d.ok) {
        try {
          d.bytes = slot->task->Run(i);
        } catch (const std::exception& e) {
          d = {i, false, e.what()};
        } catch (...) {
          d = {i, false, "unknown exception"};
        }
      }
      {
        const std::lock_guard<std::mutex> lock(mutex);
        done.push_back(std::move(d));
      }
      done_cv.notify_one();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(work);
  const auto close_pool = [&] {
    {
      const std::lock_guard<std::mutex> lock(mutex);
      closing = true;
    }
    todo_cv.notify_all();
    for (auto& t : pool) t.join();
  };
  bool stop = false;
  try {
    int asked = 0;      // requests not answered yet
    int held = 0;       // jobs received and not sent back (queued or running)
    bool ahead = true;  // rank 0 still gives jobs ahead of time
    bool none = false;  // rank 0 has no job left
    Backoff backoff;
    while (!stop) {
      while (!none && held + asked < (ahead ? 2 : 1) * threads) {
        WireWriter w;
        w.Int(kRequest);
        w.Int(batch);
        w.Bool(held + asked >= threads);
        SendToRoot(w.bytes());
        ++asked;
      }
      if (none && asked == 0 && held == 0) break;
      std::deque<Done> finished;
      {
        std::unique_lock<std::mutex> lock(mutex);
        // Waiting for an answer: poll. Only jobs running: nothing can arrive, just wait.
        if (asked > 0)
          done_cv.wait_for(lock, backoff.Next(), [&] { return !done.empty(); });
        else
          done_cv.wait(lock, [&] { return !done.empty(); });
        finished.swap(done);
      }
      for (auto& d : finished) {
        WireWriter w;
        w.Int(kResult);
        w.Int(batch);
        w.Int(d.index);
        w.Bool(d.ok);
        w.String(d.bytes);
        SendToRoot(w.bytes());
        --held;
      }
      std::string msg;
      while (asked > 0 && TryReceive(0, kTagToWorker, &msg, nullptr)) {
        backoff.Reset();
        WireReader r(msg);
        const std::int64_t type = r.Int();
        if (type == kStop) {
          stop = true;
          break;
        }
        if ((type != kJob && type != kWait && type != kNone) || r.Int() != batch)
          ProtocolError("unexpected message (type " + std::to_string(type) + ") during a batch");
        --asked;
        if (type == kWait) ahead = false;
        if (type == kNone) none = true;
        if (type == kJob) {
          const int index = static_cast<int>(r.Int());
          // Tests let a worker die here, at a defined job (mpi_test.sh killed_worker).
          static std::atomic<long> jobs_received{0};
          io::TestFaultPoint("worker-job", ++jobs_received);
          {
            const std::lock_guard<std::mutex> lock(mutex);
            todo.push_back(index);
          }
          todo_cv.notify_one();
          ++held;
        }
      }
    }
    if (!stop) SendToRoot(Header(kDone, batch));
  } catch (...) {
    close_pool();
    throw;
  }
  close_pool();
  return !stop;
}

}  // namespace

bool BuiltIn() { return true; }

std::string LibraryVersion() {
  char text[MPI_MAX_LIBRARY_VERSION_STRING];
  int n = 0;
  MPI_Get_library_version(text, &n);  // allowed before MPI_Init
  std::string s(text, static_cast<std::size_t>(std::max(0, n)));
  s = s.substr(0, s.find_first_of(",\n"));
  return s;
}

void Init(int* argc, char*** argv) {
  g_main_thread = std::this_thread::get_id();
  // Launchers announce themselves in the environment: Open MPI's mpirun, PMIx (srun
  // --mpi=pmix, Open MPI), PMI-1/2 (MPICH's hydra, srun --mpi=pmi2).
  bool launched = false;
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
    launched = launched || std::getenv(v) != nullptr;
  if (!launched) return;
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  g_launched = true;
  MPI_Comm_size(MPI_COMM_WORLD, &g_ranks);
  PMPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  if (provided < MPI_THREAD_FUNNELED) {
    if (g_rank == 0)
      std::cerr << "scw: error: the MPI library does not support threads (MPI_THREAD_FUNNELED)\n";
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  if (g_rank == 0 && g_ranks > 1) {
    struct sigaction sa {};
    sa.sa_handler = &OnTerminate;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    ::sigaction(SIGTERM, &sa, &g_previous_term);
  }
}

const std::string& StartupError() {
  static const std::string kNone;
  return kNone;
}

void Finalize() {
  if (!g_launched || g_finalized) return;
  if (g_rank == 0) {
    TheOutbox().PostAll(Header(kStop, 0));
    TheOutbox().Flush();
  }
  g_finalized = true;
  PMPI_Finalize();
}

int RunWorker(const TaskKinds& kinds) {
  std::map<std::int64_t, TaskSlot> tasks;
  try {
    while (true) {
      const std::string msg = WaitFromRoot();
      WireReader r(msg);
      switch (r.Int()) {
        case kPrepare: {
          const std::int64_t id = r.Int();
          const std::string kind = r.String();
          TaskSlot& slot = tasks[id];
          slot.threads = static_cast<int>(r.Int());
          const std::string setup = r.String();
          const auto it = kinds.find(kind);
          if (it == kinds.end()) {
            slot.error = "no task kind '" + kind + "' on this rank";
            break;
          }
          try {
            slot.task = it->second(setup, slot.threads);
          } catch (const std::exception& e) {
            slot.error = e.what();
          }
          break;
        }
        case kRelease:
          tasks.erase(r.Int());
          break;
        case kBatch: {
          const std::int64_t id = r.Int();
          const std::int64_t batch = r.Int();
          TaskSlot& slot = tasks[id];
          if (!ServeBatch(&slot, batch, r.Rest())) return 0;
          break;
        }
        case kStop:
          return 0;
        default:
          ProtocolError("unknown message");
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "scw (MPI rank " << g_rank << "): error: " << e.what() << '\n';
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  return 1;
}

RemoteTask::RemoteTask(const std::string& kind, const std::string& setup, int threads)
    : id_(static_cast<int>(g_next_task_id++)), threads_(std::max(1, threads)) {
  WireWriter w;
  w.Int(kPrepare);
  w.Int(id_);
  w.String(kind);
  w.Int(threads_);
  w.String(setup);
  TheOutbox().PostAll(w.bytes());
}

RemoteTask::~RemoteTask() {
  if (!g_finalized) TheOutbox().PostAll(Header(kRelease, id_));
}

void RemoteTask::Run(const std::string& payload, int jobs, const std::function<void(int)>& local,
                     const std::function<void(int, std::string_view)>& remote,
                     const std::vector<int>& order) const {
  if (jobs <= 0) return;
  CheckOrder(order, jobs);
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(jobs));
  if (g_finalized || std::this_thread::get_id() != g_main_thread) {
    ParallelFor(jobs, threads_, order, local);
    return;
  }
  Outbox& outbox = TheOutbox();
  const std::int64_t batch = g_next_batch++;
  {
    WireWriter w;
    w.Int(kBatch);
    w.Int(id_);
    w.Int(batch);
    outbox.PostAll(w.bytes() + payload);
  }
  // Job threads of this rank; they take indices from the same counter as the workers.
  std::atomic<int> next{0};
  std::mutex mutex;
  std::condition_variable cv;
  int done = 0;
  auto work = [&] {
    for (int p = next.fetch_add(1); p < jobs; p = next.fetch_add(1)) {
      const int i = JobAt(order, p);
      try {
        local(i);
      } catch (...) {
        errors[static_cast<std::size_t>(i)] = std::current_exception();
      }
      {
        const std::lock_guard<std::mutex> lock(mutex);
        ++done;
      }
      cv.notify_one();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads_; ++t) pool.emplace_back(work);

  // Serve the workers until every job is done and every worker has said "done" (so no message
  // of this batch is left for the next one). A job ahead of time only while more jobs remain
  // than all ranks have threads: near the end a job goes to a thread that is free.
  const int all_threads = g_ranks * threads_;
  int done_workers = 0;
  Backoff backoff;
  std::string msg;
  int from = 0;
  try {
    while (true) {
      while (TryReceive(MPI_ANY_SOURCE, kTagToRoot, &msg, &from)) {
        backoff.Reset();
        WireReader r(msg);
        const std::int64_t type = r.Int();
        if (r.Int() != batch)
          ProtocolError("a message of another batch from rank " + std::to_string(from));
        if (type == kDone) {
          ++done_workers;
        } else if (type == kResult) {
          const std::int64_t index = r.Int();
          if (index < 0 || index >= jobs) ProtocolError("job index out of range");
          const bool ok = r.Bool();
          const std::string bytes = r.String();
          auto& error = errors[static_cast<std::size_t>(index)];
          if (ok) {
            try {
              remote(static_cast<int>(index), bytes);
            } catch (...) {
              error = std::current_exception();
            }
          } else {
            error = std::make_exception_ptr(
                std::runtime_error(bytes + " (on MPI rank " + std::to_string(from) + ")"));
          }
          const std::lock_guard<std::mutex> lock(mutex);
          ++done;
        } else if (type == kRequest) {
          const bool ahead = r.Bool();
          WireWriter w;
          int p = jobs;
          if (!ahead || next.load() + all_threads < jobs) p = next.fetch_add(1);
          if (p < jobs) {
            w.Int(kJob);
            w.Int(batch);
            w.Int(JobAt(order, p));
          } else {
            w.Int(ahead && next.load() < jobs ? kWait : kNone);
            w.Int(batch);
          }
          outbox.Post(from, std::make_shared<const std::string>(w.Take()));
        } else {
          ProtocolError("unexpected message from rank " + std::to_string(from));
        }
      }
      outbox.Progress();
      std::unique_lock<std::mutex> lock(mutex);
      if (done == jobs && done_workers == g_ranks - 1) break;
      cv.wait_for(lock, backoff.Next());
    }
  } catch (const std::exception& e) {  // a bug, not a result: end the whole run
    std::cerr << "scw: error: " << e.what() << '\n';
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  for (auto& t : pool) t.join();
  RethrowFirst(errors);
}

#else  // no MPI in this build: one process, every job local

namespace {
std::string g_startup_error;

int EnvNumber(std::initializer_list<const char*> names) {
  for (const char* name : names)
    if (const char* v = std::getenv(name)) return std::atoi(v);
  return -1;
}
}  // namespace

bool BuiltIn() { return false; }
std::string LibraryVersion() { return ""; }

void Init(int*, char***) {
  g_main_thread = std::this_thread::get_id();
  if (EnvNumber({"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) > 1) {
    g_rank = std::max(0, EnvNumber({"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"}));
    g_startup_error =
        "this scw is built without MPI, so it cannot share a run between processes: run it "
        "without mpirun, or rebuild it with MPI (Debian: libopenmpi-dev; cmake -DSCW_WITH_MPI=ON)";
  }
}

const std::string& StartupError() { return g_startup_error; }
void Finalize() {}
int RunWorker(const TaskKinds&) { return 0; }

RemoteTask::RemoteTask(const std::string&, const std::string&, int threads)
    : id_(0), threads_(std::max(1, threads)) {}
RemoteTask::~RemoteTask() = default;

void RemoteTask::Run(const std::string&, int jobs, const std::function<void(int)>& local,
                     const std::function<void(int, std::string_view)>&,
                     const std::vector<int>& order) const {
  ParallelFor(jobs, threads_, order, local);
}

#endif

bool Launched() { return g_launched; }
int Ranks() { return g_ranks; }
int Rank() { return g_rank; }

std::shared_ptr<const RemoteTask> MaybeRemote(const std::string& kind,
                                              const std::function<std::string()>& setup,
                                              int threads) {
  if (!g_launched || g_finalized || g_ranks < 2 || g_rank != 0 ||
      std::this_thread::get_id() != g_main_thread)
    return nullptr;
  return std::make_shared<const RemoteTask>(kind, setup(), threads);
}

}  // namespace scw::tuning::exec::mpi
