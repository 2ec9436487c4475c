// fit-fleet (issue 12): the jobs of a fleet manifest (fleet/manifest.h)
// spread over MPI ranks by the work queue of fleet/mpi_queue.h, and the
// fleet table (fleet/fleet_table.h) written by rank 0.
//
// Every rank loads the manifest itself (the files must be visible to all
// ranks: one machine, or a shared file system). Rank 0 hands out job
// indices, longest expected first (FleetEntry::expected_cost), to whichever
// rank asks, one at a time, and fits too; every rank sends back its row as
// JSON. Without mpirun (a singleton MPI process) the same code runs every
// job in one process.
#ifndef FLEET_FLEET_RUN_H_
#define FLEET_FLEET_RUN_H_

#include <ostream>
#include <string>
#include <vector>

#include "fleet/fleet_table.h"
#include "fleet/manifest.h"
#include "fleet/mpi_queue.h"

namespace axis {

// Runs every job of `manifest` (RunFleetEntry, outputs below `out_dir`)
// over the ranks of `mpi`, as described above. Every rank must call it. On
// rank 0 returns the rows in manifest order (FleetRow::rank set) and
// prints one line per finished job to `progress` (if not null), e.g.
// "[3/8] r01/x now: ok, 1.31 s, rank 1"; on the other ranks returns an
// empty list. Throws std::runtime_error if an MPI call fails or a row
// arrives garbled (MPI aborts the job on errors by default, before that).
std::vector<FleetRow> RunFleetJobs(const FleetManifest& manifest, const std::string& out_dir,
                                   const MpiSession& mpi, std::ostream* progress);

// Options of the fit-fleet command.
struct FitFleetOptions {
  std::string manifest_path;
  std::string out_dir;        // overrides the manifest's output.dir
  std::string baseline_path;  // an earlier fleet.json, or empty
};

// fit-fleet: loads the manifest (and the baseline) on every rank, checks
// that every rank could, runs the jobs (RunFleetJobs) and on rank 0 writes
// fleet.csv, fleet.md, fleet.html and fleet.json into the output folder
// (WriteFleetTable, after every job's own folder), printing the progress
// and fleet.md to `out`. Every rank must call it. Returns the exit code: 0
// when the table is written (also when some jobs failed: they are in it),
// 2 for bad input (manifest, baseline, no output folder; rank 0 prints
// the message to `err`, "fit-fleet: error: …"), 1 for other failures
// (an output that cannot be written). Never throws (except
// std::bad_alloc).
int RunFitFleet(const FitFleetOptions& options, const MpiSession& mpi, std::ostream& out,
                std::ostream& err);

}  // namespace axis

#endif  // FLEET_FLEET_RUN_H_
