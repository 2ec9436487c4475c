#include "fleet/mpi_queue.h"

// Only the C API; no C++ bindings (OpenMPI, MPICH).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <thread>

namespace axis {
namespace {

// Message tags of the queue.
constexpr int kTagReady = 1;   // worker -> 0: ready for a task (no payload)
constexpr int kTagTask = 2;    // 0 -> worker: a task index, or -1: stop
constexpr int kTagResult = 3;  // worker -> 0: "<index>\n<result text>"

// Pause between polls of a waiting rank.
constexpr auto kPollPause = std::chrono::milliseconds(2);

void Check(int code, const char* what) {
  if (code != MPI_SUCCESS) {
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    throw std::runtime_error(std::string("MPI: ") + what + " failed: " +
                             std::string(text, static_cast<size_t>(length)));
  }
}

// Blocks until a message from `source` with `tag` can be received, polling
// with pauses (a blocking MPI_Recv spins at 100 % CPU in OpenMPI).
void WaitForMessage(int source, int tag) {
  int flag = 0;
  while (true) {
    Check(MPI_Iprobe(source, tag, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE), "MPI_Iprobe");
    if (flag) return;
    std::this_thread::sleep_for(kPollPause);
  }
}

void SendInt(int value, int destination, int tag) {
  Check(MPI_Send(&value, 1, MPI_INT, destination, tag, MPI_COMM_WORLD), "MPI_Send");
}

// A task on a thread of rank 0.
class LocalTask {
 public:
  LocalTask() = default;
  LocalTask(const LocalTask&) = delete;
  LocalTask& operator=(const LocalTask&) = delete;
  // Waits for a task still running (the queue failed meanwhile).
  ~LocalTask() {
    if (thread_.joinable()) thread_.join();
  }

  bool running() const { return thread_.joinable(); }
  bool finished() const { return done_.load(); }

  void Start(const QueueTask& task, size_t index) {
    index_ = index;
    done_ = false;
    thread_ = std::thread([this, &task, index]() {
      try {
        result_ = task(index);
      } catch (...) {
        error_ = std::current_exception();
      }
      done_ = true;
    });
  }

  // Joins the finished thread; its index and result. Rethrows what the
  // task threw as std::runtime_error.
  size_t Take(std::string* result) {
    thread_.join();
    if (error_) {
      std::exception_ptr error = error_;
      error_ = nullptr;
      try {
        std::rethrow_exception(error);
      } catch (const std::exception& e) {
        throw std::runtime_error("task " + std::to_string(index_) + " threw: " + e.what());
      } catch (...) {
        throw std::runtime_error("task " + std::to_string(index_) + " threw");
      }
    }
    *result = std::move(result_);
    return index_;
  }

 private:
  std::thread thread_;
  std::atomic<bool> done_{false};
  size_t index_ = 0;
  std::string result_;
  std::exception_ptr error_;
};

// Rank 0: serves the queue and works with a LocalTask.
void Coordinate(int ranks, const std::vector<size_t>& order, const QueueTask& task,
                const QueueResult& result) {
  const size_t n = order.size();
  std::vector<bool> reported(n, false);
  size_t next = 0, received = 0;
  int stopped = 0;
  LocalTask local;
  const auto record = [&](size_t index, std::string text, int rank) {
    if (index >= n || reported[index]) {
      throw std::runtime_error("MPI queue: rank " + std::to_string(rank) + " returned task " +
                               std::to_string(index) + ", not one it was given");
    }
    reported[index] = true;
    ++received;
    result(index, std::move(text), rank);
  };
  // The next task for `rank`, or -1 (stop) once the queue is empty.
  const auto dispatch = [&](int rank) {
    const int index = next < n ? static_cast<int>(order[next++]) : -1;
    SendInt(index, rank, kTagTask);
    if (index < 0) ++stopped;
  };
  while (received < n || stopped < ranks - 1 || local.running()) {
    bool busy = false;
    if (local.running() && local.finished()) {
      std::string text;
      const size_t index = local.Take(&text);
      record(index, std::move(text), 0);
      busy = true;
    }
    if (!local.running() && next < n) {
      local.Start(task, order[next++]);
      busy = true;
    }
    int flag = 0;
    MPI_Status status;
    Check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe");
    if (flag) {
      busy = true;
      int count = 0;
      Check(MPI_Get_count(&status, MPI_CHAR, &count), "MPI_Get_count");
      std::string text(static_cast<size_t>(count), '\0');
      Check(MPI_Recv(text.data(), count, MPI_CHAR, status.MPI_SOURCE, status.MPI_TAG,
                     MPI_COMM_WORLD, MPI_STATUS_IGNORE),
            "MPI_Recv");
      if (status.MPI_TAG == kTagResult) {
        const size_t newline = text.find('\n');
        char* end = nullptr;
        const unsigned long index =
            newline == std::string::npos ? 0 : std::strtoul(text.c_str(), &end, 10);
        if (newline == std::string::npos || end != text.c_str() + newline) {
          throw std::runtime_error("MPI queue: a garbled result from rank " +
                                   std::to_string(status.MPI_SOURCE));
        }
        record(static_cast<size_t>(index), text.substr(newline + 1), status.MPI_SOURCE);
      } else if (status.MPI_TAG != kTagReady) {
        throw std::runtime_error("MPI queue: unexpected message tag " +
                                 std::to_string(status.MPI_TAG));
      }
      dispatch(status.MPI_SOURCE);
    }
    if (!busy) std::this_thread::sleep_for(kPollPause);
  }
}

// Ranks other than 0: ask, work, send back, until told to stop.
void Work(const QueueTask& task) {
  Check(MPI_Send(nullptr, 0, MPI_CHAR, 0, kTagReady, MPI_COMM_WORLD), "MPI_Send");
  while (true) {
    WaitForMessage(0, kTagTask);
    int index = -1;
    Check(MPI_Recv(&index, 1, MPI_INT, 0, kTagTask, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
          "MPI_Recv");
    if (index < 0) return;
    std::string text;
    try {
      text = std::to_string(index) + "\n" + task(static_cast<size_t>(index));
    } catch (const std::exception& e) {
      throw std::runtime_error("task " + std::to_string(index) + " threw: " + e.what());
    }
    Check(MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, 0, kTagResult,
                   MPI_COMM_WORLD),
          "MPI_Send");
  }
}

}  // namespace

MpiSession::MpiSession(int* argc, char*** argv) {
  int provided = 0;
  Check(MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  if (provided < MPI_THREAD_FUNNELED) {
    MPI_Finalize();
    throw std::runtime_error("MPI: expected thread support MPI_THREAD_FUNNELED, got level " +
                             std::to_string(provided));
  }
  Check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
  Check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
}

MpiSession::~MpiSession() { MPI_Finalize(); }

bool MpiSession::AllTrue(bool ok) const {
  int mine = ok ? 1 : 0, all = 0;
  Check(MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD), "MPI_Allreduce");
  return all != 0;
}

void MpiSession::Abort(int code) const {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::abort();  // MPI_Abort does not return; in case an implementation does
}

bool LoadOnEveryRank(const MpiSession& mpi, const std::function<void()>& load,
                     const std::string& program, const std::string& what, std::ostream& err) {
  std::string error;
  try {
    load();
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (mpi.AllTrue(error.empty())) return true;
  if (mpi.rank() == 0) {
    err << program << ": error: "
        << (error.empty() ? "another rank could not load " + what +
                                " (are the files visible to every rank?)"
                          : error)
        << "\n";
  }
  return false;
}

void RunMpiQueue(const MpiSession& mpi, size_t count, const std::vector<size_t>& order,
                 const QueueTask& task, const QueueResult& result) {
  if (mpi.rank() != 0) {
    Work(task);
    return;
  }
  std::vector<size_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  bool permutation = sorted.size() == count;
  for (size_t k = 0; permutation && k < count; ++k) permutation = sorted[k] == k;
  if (!permutation) {
    throw std::invalid_argument("RunMpiQueue: expected an order holding each of the " +
                                std::to_string(count) + " task indices once, got " +
                                std::to_string(order.size()) + " entries that do not");
  }
  Coordinate(mpi.size(), order, task, result);
}

}  // namespace axis
