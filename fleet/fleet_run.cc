#include "fleet/fleet_run.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <numeric>
#include <optional>
#include <stdexcept>

#include "common/format.h"
#include "fleet/write_fleet_table.h"
#include "io/output_staging.h"

namespace axis {
namespace {

// Job indices, longest expected first (ties in manifest order).
std::vector<size_t> QueueOrder(const FleetManifest& manifest) {
  std::vector<size_t> order(manifest.entries.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&manifest](size_t a, size_t b) {
    return manifest.entries[a].expected_cost > manifest.entries[b].expected_cost;
  });
  return order;
}

}  // namespace

std::vector<FleetRow> RunFleetJobs(const FleetManifest& manifest, const std::string& out_dir,
                                   const MpiSession& mpi, std::ostream* progress) {
  const size_t n = manifest.entries.size();
  const int rank = mpi.rank();
  // A job's row as JSON text; a failure that escapes RunFleetEntry
  // (std::bad_alloc) is a failed row, not a broken queue.
  const QueueTask task = [&](size_t index) {
    FleetRow row;
    try {
      row = RunFleetEntry(manifest, index, out_dir);
    } catch (const std::exception& e) {
      row = FleetRow();
      row.status = "failed";
      row.error = e.what();
    }
    row.rank = rank;
    // Invalid UTF-8 (an error message quoting a data file) replaced, not thrown on.
    return FleetRowToJson(row).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  };
  std::vector<std::optional<FleetRow>> rows(n);
  size_t received = 0;
  const QueueResult result = [&](size_t index, std::string text, int from) {
    FleetRow row = ParseQueueResult(
        text,
        [from](const nlohmann::json& j) {
          return FleetRowFromJson(j, "row from rank " + std::to_string(from));
        },
        "fit-fleet: a garbled row");
    row.rank = from;
    ++received;
    if (progress != nullptr) {
      *progress << "[" << received << "/" << n << "] " << row.axis << " " << row.log << ": "
                << row.status << ", " << FormatNumber(row.seconds, 3) << " s, rank " << from
                << (row.status == "failed" ? ": " + row.error : std::string()) << std::endl;
    }
    rows[index] = std::move(row);
  };
  RunMpiQueue(mpi, n, rank == 0 ? QueueOrder(manifest) : std::vector<size_t>(), task, result);
  if (rank != 0) return {};
  std::vector<FleetRow> out;
  out.reserve(n);
  for (std::optional<FleetRow>& r : rows) out.push_back(std::move(*r));
  return out;
}

int RunFitFleet(const FitFleetOptions& options, const MpiSession& mpi, std::ostream& out,
                std::ostream& err) {
  const bool root = mpi.rank() == 0;
  // Input, on every rank; all must agree before the queue starts.
  FleetManifest manifest;
  std::vector<FleetRow> baseline;
  std::string out_dir;
  const auto load = [&]() {
    manifest = LoadFleetManifest(options.manifest_path);
    out_dir = options.out_dir.empty() ? manifest.out_dir : options.out_dir;
    if (out_dir.empty()) {
      throw std::invalid_argument(options.manifest_path +
                                  ": expected an output folder (--out DIR or output.dir in "
                                  "the manifest), got none");
    }
    CheckOutputDirectory(out_dir);  // before the jobs, not after them
    if (!options.baseline_path.empty()) baseline = LoadFleetJson(options.baseline_path);
  };
  if (!LoadOnEveryRank(mpi, load, "fit-fleet", "the manifest or the baseline", err)) {
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
    mpi.Abort(1);
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
