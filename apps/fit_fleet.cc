// fit-fleet MANIFEST.yaml [--out DIR] [--baseline OLD/fleet.json]
//   mpirun -np N fit-fleet ...   (or srun -n N under Slurm; alone: one process)
//
// Fits every job of a fleet manifest (fleet/manifest.h), spread over the MPI
// ranks, and writes the fleet table (fleet/fleet_run.h): fleet.csv,
// fleet.md, fleet.html, fleet.json, and every job's own folder. Exit codes:
// 0 table written (failed jobs are in it), 2 bad input (command line,
// manifest, baseline), 1 other failures.
#include <cstdio>
#include <exception>
#include <iostream>

#include <CLI/CLI.hpp>
#include <glog/logging.h>

#include "common/allocator.h"
#include "apps/mpi_command_line.h"
#include "fleet/fleet_run.h"

int main(int argc, char** argv) {
  axis::KeepFreedMemory();  // common/allocator.h: a fit reuses its buffers
  google::InitGoogleLogging(argv[0]);
  FLAGS_minloglevel = google::GLOG_FATAL;  // as fit-params: the fits report their own trouble
  try {
    axis::MpiSession mpi(&argc, &argv);
    CLI::App app{"Fit every axis and log of a fleet manifest over MPI ranks; one table"};
    axis::FitFleetOptions options;
    app.add_option("manifest", options.manifest_path, "fleet manifest YAML file")->required();
    app.add_option("--out", options.out_dir, "output folder (default: the manifest's output.dir)");
    app.add_option("--baseline", options.baseline_path,
                   "an earlier fleet.json: flag what changed since");
    if (const auto code = axis::ParseOnEveryRank(app, argc, argv, mpi.rank())) return *code;
    return axis::RunFitFleet(options, mpi, std::cout, std::cerr);
  } catch (const std::exception& e) {  // MPI could not start
    std::fprintf(stderr, "fit-fleet: error: %s\n", e.what());
    return 1;
  }
}
