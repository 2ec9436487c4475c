// fit-campaign (issue 10's Monte Carlo campaigns, run/campaign.h) on the
// fleet's engine (issue 12): the seeds of a campaign spread over MPI ranks
// by the work queue of fleet/mpi_queue.h, one seed per rank at a time, or
// over the threads of one process when run without mpirun.
//
//   mpirun -np N fit-campaign CAMPAIGN.yaml   (srun -n N under Slurm)
//   fit-campaign CAMPAIGN.yaml --jobs 2       (one process, 2 seeds at once)
//
// Every rank loads the campaign itself (the files must be visible to all
// ranks) and simulates its seeds' records into a temporary folder of its
// own; rank 0 hands out the seeds in order and runs some too, gathers the
// outcomes (SeedOutcomeToJson) and writes results.csv, summary.md and
// summary.json. Each seed's outcome depends on the seed only, not on the
// rank or the number of ranks.
#ifndef FLEET_CAMPAIGN_RUN_H_
#define FLEET_CAMPAIGN_RUN_H_

#include <ostream>
#include <string>
#include <vector>

#include "fleet/mpi_queue.h"
#include "run/campaign.h"

namespace axis {

// Runs seeds config.first_seed..config.last_seed over the ranks of `mpi`,
// each seed's fit with one solver thread. Every rank must call it. On rank
// 0 returns the outcomes in seed order and prints one line per finished
// seed to `progress` (if not null): "[3/20] seed 5: selected {}, verdict
// explained (41 s), rank 1"; on the other ranks returns an empty list.
// Throws std::runtime_error if an MPI call fails or an outcome arrives
// garbled.
std::vector<SeedOutcome> RunCampaignOnRanks(const CampaignConfig& config, const MpiSession& mpi,
                                            std::ostream* progress);

// Options of the fit-campaign command.
struct FitCampaignOptions {
  std::string campaign_path;
  std::string out_dir;  // overrides the campaign's output.dir
  int jobs = 0;         // seeds at once in one process (0: the number of cores); 1 rank only
  int first = -1;       // overrides seeds.first (0..kMaxCampaignSeed; -1: not given)
  int last = -1;        // overrides seeds.last (0..kMaxCampaignSeed; -1: not given)
};

// fit-campaign: loads the campaign on every rank and checks that every rank
// could; on one rank runs RunCampaign with options.jobs threads, on several
// RunCampaignOnRanks; on rank 0 writes the files (WriteCampaign) and
// prints the progress and the summary to `out`. Every rank must call it.
// Returns the exit code: 0 when the files are written (also when some
// seeds failed: they are counted), 2 for bad input (campaign, job,
// generating config, first > last, --jobs > 1 with several ranks, neither
// --out nor output.dir, an output folder that cannot be written; rank 0
// prints "fit-campaign: error: …" to `err`), 1 for other failures. Never
// throws (except std::bad_alloc).
int RunFitCampaign(const FitCampaignOptions& options, const MpiSession& mpi, std::ostream& out,
                   std::ostream& err);

}  // namespace axis

#endif  // FLEET_CAMPAIGN_RUN_H_
