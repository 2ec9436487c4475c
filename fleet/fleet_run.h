// fit-fleet (issue 12): the jobs of a fleet manifest (fleet/manifest.h)
// spread over MPI ranks by a work queue, and the fleet table
// (fleet/fleet_table.h) written by rank 0. The only part of the project
// that uses MPI (the plain C API of OpenMPI, Debian libopenmpi-dev); mpi.h
// is included by fleet_run.cc only.
//
// The queue: every rank loads the manifest itself (the files must be
// visible to all ranks: one machine, or a shared file system). Rank 0 hands
// out job indices, longest expected first (FleetEntry::expected_cost), to
// whichever rank asks, one at a time, and fits too (on a thread of its own
// while its main thread serves the queue); every rank sends back its row as
// JSON. Waiting ranks poll (MPI_Iprobe and 2 ms sleeps) rather than spin, so
// that a rank idle at the end of the queue leaves its core to the fits
// still running. Without mpirun (a singleton MPI process) the same code
// runs every job in one process.
#ifndef FLEET_FLEET_RUN_H_
#define FLEET_FLEET_RUN_H_

#include <ostream>
#include <string>
#include <vector>

#include "fleet/fleet_table.h"
#include "fleet/manifest.h"

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

 private:
  int rank_ = 0;
  int size_ = 1;
};

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
