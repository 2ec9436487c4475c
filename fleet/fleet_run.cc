#include "fleet/fleet_run.h"

// Only the C API; no C++ bindings (OpenMPI, MPICH).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <thread>

#include "fit/report.h"

namespace axis {
namespace {

// Message tags of the queue.
constexpr int kTagReady = 1;   // worker -> 0: ready for a job (no payload)
constexpr int kTagJob = 2;     // 0 -> worker: a job index, or -1: stop
constexpr int kTagResult = 3;  // worker -> 0: {"index": k, "row": row} as JSON text

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

// Job indices, longest expected first (ties in manifest order).
std::vector<size_t> QueueOrder(const FleetManifest& manifest) {
  std::vector<size_t> order(manifest.entries.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&manifest](size_t a, size_t b) {
    return manifest.entries[a].expected_cost > manifest.entries[b].expected_cost;
  });
  return order;
}

// A job on a thread of rank 0.
class LocalJob {
 public:
  LocalJob() = default;
  LocalJob(const LocalJob&) = delete;
  LocalJob& operator=(const LocalJob&) = delete;
  // Waits for a job still running (the queue failed meanwhile).
  ~LocalJob() {
    if (thread_.joinable()) thread_.join();
  }

  bool running() const { return thread_.joinable(); }
  bool finished() const { return done_.load(); }

  void Start(const FleetManifest& manifest, size_t index, const std::string& out_dir) {
    index_ = index;
    done_ = false;
    thread_ = std::thread([this, &manifest, index, &out_dir]() {
      try {
        row_ = RunFleetEntry(manifest, index, out_dir);
      } catch (const std::exception& e) {  // std::bad_alloc
        row_ = FleetRow();
        row_.status = "failed";
        row_.error = e.what();
      }
      done_ = true;
    });
  }

  // Joins the finished thread; its index and row.
  size_t Take(FleetRow* row) {
    thread_.join();
    *row = std::move(row_);
    return index_;
  }

 private:
  std::thread thread_;
  std::atomic<bool> done_{false};
  size_t index_ = 0;
  FleetRow row_;
};

// Rank 0: serves the queue and fits with a LocalJob.
std::vector<FleetRow> Coordinate(const FleetManifest& manifest, const std::string& out_dir,
                                 int ranks, std::ostream* progress) {
  const std::vector<size_t> order = QueueOrder(manifest);
  const size_t n = order.size();
  std::vector<std::optional<FleetRow>> rows(n);
  size_t next = 0, received = 0;
  int stopped = 0;
  LocalJob local;
  const auto record = [&](size_t index, FleetRow row, int rank) {
    if (index >= n || rows[index]) {
      throw std::runtime_error("fit-fleet: rank " + std::to_string(rank) +
                               " returned job " + std::to_string(index) +
                               ", not one it was given");
    }
    row.rank = rank;
    if (progress != nullptr) {
      *progress << "[" << received + 1 << "/" << n << "] " << row.axis << " " << row.log << ": "
                << row.status << ", " << FormatNumber(row.seconds, 3) << " s, rank " << rank
                << (row.status == "failed" ? ": " + row.error : std::string()) << std::endl;
    }
    rows[index] = std::move(row);
    ++received;
  };
  // The next job for `rank`, or -1 (stop) once the queue is empty.
  const auto dispatch = [&](int rank) {
    const int index = next < n ? static_cast<int>(order[next++]) : -1;
    SendInt(index, rank, kTagJob);
    if (index < 0) ++stopped;
  };
  while (received < n || stopped < ranks - 1 || local.running()) {
    bool busy = false;
    if (local.running() && local.finished()) {
      FleetRow row;
      const size_t index = local.Take(&row);
      record(index, std::move(row), 0);
      busy = true;
    }
    if (!local.running() && next < n) {
      local.Start(manifest, order[next++], out_dir);
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
        nlohmann::json message;
        try {
          message = nlohmann::json::parse(text);
          record(message.at("index").get<size_t>(),
                 FleetRowFromJson(message.at("row"), "row from rank " +
                                                         std::to_string(status.MPI_SOURCE)),
                 status.MPI_SOURCE);
        } catch (const std::invalid_argument& e) {
          throw std::runtime_error(std::string("fit-fleet: a garbled row: ") + e.what());
        } catch (const nlohmann::json::exception& e) {
          throw std::runtime_error(std::string("fit-fleet: a garbled row: ") + e.what());
        }
      } else if (status.MPI_TAG != kTagReady) {
        throw std::runtime_error("fit-fleet: unexpected message tag " +
                                 std::to_string(status.MPI_TAG));
      }
      dispatch(status.MPI_SOURCE);
    }
    if (!busy) std::this_thread::sleep_for(kPollPause);
  }
  std::vector<FleetRow> out;
  out.reserve(n);
  for (std::optional<FleetRow>& r : rows) out.push_back(std::move(*r));
  return out;
}

// Ranks other than 0: ask, fit, send back, until told to stop.
void Work(const FleetManifest& manifest, const std::string& out_dir, int rank) {
  Check(MPI_Send(nullptr, 0, MPI_CHAR, 0, kTagReady, MPI_COMM_WORLD), "MPI_Send");
  while (true) {
    WaitForMessage(0, kTagJob);
    int index = -1;
    Check(MPI_Recv(&index, 1, MPI_INT, 0, kTagJob, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
          "MPI_Recv");
    if (index < 0) return;
    FleetRow row = RunFleetEntry(manifest, static_cast<size_t>(index), out_dir);
    row.rank = rank;
    // Invalid UTF-8 (an error message quoting a data file) replaced, not thrown on.
    const std::string text = nlohmann::json{{"index", index}, {"row", FleetRowToJson(row)}}.dump(
        -1, ' ', false, nlohmann::json::error_handler_t::replace);
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

std::vector<FleetRow> RunFleetJobs(const FleetManifest& manifest, const std::string& out_dir,
                                   const MpiSession& mpi, std::ostream* progress) {
  if (mpi.rank() == 0) return Coordinate(manifest, out_dir, mpi.size(), progress);
  Work(manifest, out_dir, mpi.rank());
  return {};
}

int RunFitFleet(const FitFleetOptions& options, const MpiSession& mpi, std::ostream& out,
                std::ostream& err) {
  const bool root = mpi.rank() == 0;
  // Input, on every rank; all must agree before the queue starts.
  FleetManifest manifest;
  std::vector<FleetRow> baseline;
  std::string out_dir, error;
  try {
    manifest = LoadFleetManifest(options.manifest_path);
    out_dir = options.out_dir.empty() ? manifest.out_dir : options.out_dir;
    if (out_dir.empty()) {
      throw std::invalid_argument(options.manifest_path +
                                  ": expected an output folder (--out DIR or output.dir in "
                                  "the manifest), got none");
    }
    if (!options.baseline_path.empty()) baseline = LoadFleetJson(options.baseline_path);
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (!mpi.AllTrue(error.empty())) {
    if (root) {
      err << "fit-fleet: error: "
          << (error.empty() ? "another rank could not load the manifest or the baseline "
                              "(are the files visible to every rank?)"
                            : error)
          << "\n";
    }
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  if (root) {
    out << "fit-fleet: " << manifest.title << "\n  " << manifest.entries.size() << " job(s) on "
        << mpi.size() << " rank(s), " << manifest.threads << " solver thread(s) each; output "
        << out_dir << std::endl;
  }
  std::vector<FleetRow> rows;
  try {
    rows = RunFleetJobs(manifest, out_dir, mpi, root ? &out : nullptr);
  } catch (const std::exception& e) {
    // The queue is broken: the other ranks would wait for it for ever.
    err << "fit-fleet: error: rank " << mpi.rank() << ": " << e.what() << "\n";
    err.flush();
    MPI_Abort(MPI_COMM_WORLD, 1);
    return 1;
  }
  if (!root) return 0;
  try {
    FleetTable table;
    table.title = manifest.title;
    table.manifest = manifest.path;
    table.rows = std::move(rows);
    table.ranks = mpi.size();
    table.threads = manifest.threads;
    if (!options.baseline_path.empty()) {
      table.compared = true;
      table.comparison =
          CompareFleets(table.rows, baseline, manifest.alpha, options.baseline_path);
    }
    table.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    WriteFleetTable(out_dir, table);
    out << "\n" << FormatFleetMarkdown(table) << "\nwrote " << out_dir
        << "/{fleet.csv, fleet.md, fleet.html, fleet.json}\n";
  } catch (const std::exception& e) {
    err << "fit-fleet: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace axis
