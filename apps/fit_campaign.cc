// fit-campaign CAMPAIGN.yaml [--out DIR] [--jobs N] [--first N] [--last N]
//   mpirun -np N fit-campaign ...   (or srun -n N under Slurm; alone: one process)
//
// Runs a Monte Carlo campaign (run/campaign.h): the campaign's fitting job
// on freshly simulated data for every seed, the discovery loop after each
// fit, and one table of false discoveries, power, coverage and verdicts;
// the seeds spread over MPI ranks or over the threads of one process
// (fleet/campaign_run.h). Writes results.csv, summary.md and summary.json
// into the output folder. Exit codes: 0 success (also when some seeds
// failed: they are counted), 2 bad input (command line, campaign, job or
// generating config), 1 other failures.
#include <cstdio>
#include <exception>
#include <iostream>
#include <limits>

#include <CLI/CLI.hpp>
#include <glog/logging.h>

#include "common/allocator.h"
#include "apps/integer_option.h"
#include "apps/mpi_command_line.h"
#include "fleet/campaign_run.h"
#include "run/campaign.h"

int main(int argc, char** argv) {
  axis::KeepFreedMemory();  // common/allocator.h: a fit reuses its buffers
  google::InitGoogleLogging(argv[0]);
  FLAGS_minloglevel = google::GLOG_FATAL;
  try {
    axis::MpiSession mpi(&argc, &argv);
    CLI::App app{"Run a fitting job over many simulated noise seeds and tally the discovery loop"};
    axis::FitCampaignOptions options;
    app.add_option("campaign", options.campaign_path, "campaign YAML file")->required();
    app.add_option("--out", options.out_dir,
                   "output directory (default: the campaign's output.dir)");
    app.add_option("--jobs", options.jobs,
                   "seeds run in parallel in one process (default: the number of cores); "
                   "under mpirun each rank runs one seed at a time")
        ->check(axis::PositiveInteger(std::numeric_limits<int>::max(), "seeds at once"));
    const CLI::Validator seed =
        axis::IntegerIn(0, axis::kMaxCampaignSeed, "the range of seeds.first and seeds.last");
    app.add_option("--first", options.first, "first seed (overrides seeds.first)")->check(seed);
    app.add_option("--last", options.last, "last seed (overrides seeds.last)")->check(seed);
    if (const auto code = axis::ParseOnEveryRank(app, argc, argv, mpi.rank())) return *code;
    return axis::RunFitCampaign(options, mpi, std::cout, std::cerr);
  } catch (const std::exception& e) {  // MPI could not start
    std::fprintf(stderr, "fit-campaign: error: %s\n", e.what());
    return 1;
  }
}
