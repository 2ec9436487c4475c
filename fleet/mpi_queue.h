// The MPI work queue of fit-fleet and fit-campaign (issue 12): tasks
// 0..n-1 handed out by rank 0 one at a time to whichever rank asks, rank 0
// working too (on a thread of its own while its main thread serves the
// queue); each task's result travels back to rank 0 as text. The only file
// pair of the project that includes mpi.h (the plain C API of OpenMPI,
// Debian libopenmpi-dev, MPI 3.1 standard).
//
// Waiting ranks poll (MPI_Iprobe and 2 ms sleeps) rather than spin, so that
// a rank idle at the end of the queue leaves its core to the tasks still
// running. Without mpirun (a singleton MPI process, MPI standard §10.5.2)
// the same code runs every task in one process, in `order`.
#ifndef FLEET_MPI_QUEUE_H_
#define FLEET_MPI_QUEUE_H_

#include <cstddef>
#include <functional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace axis {

// MPI for the life of the object: MPI_Init_thread (MPI_THREAD_FUNNELED:
// only the main thread calls MPI) and MPI_Finalize. One per process, made
// first thing in main (before the command line is parsed, so that only
// rank 0 reports its errors). Throws std::runtime_error if MPI cannot start
// or gives less than MPI_THREAD_FUNNELED.
class MpiSession {
 public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }

  // True on every rank if `ok` is true on every rank (MPI_Allreduce, a
  // collective: every rank must call it).
  bool AllTrue(bool ok) const;

  // Ends every rank of the job with exit code `code` (MPI_Abort): for a
  // broken queue, where the other ranks would wait for ever.
  [[noreturn]] void Abort(int code) const;

 private:
  int rank_ = 0;
  int size_ = 1;
};

// Loads a run's input on every rank (`load`, which throws
// std::exception on bad input) and agrees on the outcome (AllTrue): true if
// every rank loaded it. Otherwise false on every rank, and rank 0 writes
// "PROGRAM: error: MESSAGE" to `err`, its own message or, where only another
// rank failed, "another rank could not load WHAT (are the files visible to
// every rank?)". A collective: every rank must call it.
bool LoadOnEveryRank(const MpiSession& mpi, const std::function<void()>& load,
                     const std::string& program, const std::string& what, std::ostream& err);

// A task: runs task `index` (0 ≤ index < count) and returns its result as
// text (e.g. JSON). Called on rank 0's worker thread or on another rank's
// main thread; it must catch its own failures and report them in its
// result (an exception it lets out is rethrown by RunMpiQueue as
// std::runtime_error and breaks the queue).
using QueueTask = std::function<std::string(size_t index)>;

// Receives a finished task's result on rank 0's main thread, in the order
// the tasks finish, with the rank that ran it. May throw (e.g. a garbled
// result); RunMpiQueue lets that out.
using QueueResult = std::function<void(size_t index, std::string result, int rank)>;

// Runs tasks 0..count-1 over the ranks of `mpi`; every rank must call it
// with the same `count`. `order` (rank 0 only; a permutation of
// 0..count-1) is the order the tasks are handed out, e.g. longest expected
// first. `result` is called on rank 0 once per task. Returns when every
// task has reported (rank 0) or when told to stop (other ranks).
// Throws std::invalid_argument if `order` is not such a permutation (rank
// 0), std::runtime_error if an MPI call fails, a rank returns a task it was
// not given, or a task throws (MPI aborts the job on MPI errors by
// default, before that).
void RunMpiQueue(const MpiSession& mpi, size_t count, const std::vector<size_t>& order,
                 const QueueTask& task, const QueueResult& result);

// A task's result sent as JSON text, read back on rank 0:
// from_json(nlohmann::json::parse(text)), where from_json throws
// std::invalid_argument or nlohmann::json::exception for a document that is
// not a result. Throws std::runtime_error "<garbled>: <message>" then (the
// queue is broken: a rank sent what no task writes).
template <typename FromJson>
auto ParseQueueResult(const std::string& text, const FromJson& from_json,
                      const std::string& garbled) -> decltype(from_json(nlohmann::json())) {
  try {
    return from_json(nlohmann::json::parse(text));
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(garbled + ": " + e.what());
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(garbled + ": " + e.what());
  }
}

}  // namespace axis

#endif  // FLEET_MPI_QUEUE_H_
