#include "fleet/campaign_run.h"

#include <algorithm>
#include <exception>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>

#include "io/output_staging.h"
#include "run/campaign.h"

namespace axis {

std::vector<SeedOutcome> RunCampaignOnRanks(const CampaignConfig& config, const MpiSession& mpi,
                                            std::ostream* progress) {
  const size_t n = static_cast<size_t>(config.last_seed - config.first_seed + 1);
  const QueueTask task = [&config](size_t index) {
    const SeedOutcome o = RunCampaignSeed(config, config.first_seed + static_cast<int>(index), 1);
    // Invalid UTF-8 (an error message quoting a data file) replaced, not thrown on.
    return SeedOutcomeToJson(o).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  };
  std::vector<std::optional<SeedOutcome>> outcomes(n);
  size_t received = 0;
  const QueueResult result = [&](size_t index, std::string text, int rank) {
    SeedOutcome o = ParseQueueResult(
        text,
        [rank](const nlohmann::json& j) {
          return SeedOutcomeFromJson(j, "outcome from rank " + std::to_string(rank));
        },
        "fit-campaign: a garbled outcome");
    if (o.seed != config.first_seed + static_cast<int>(index) ||
        o.value.size() != config.truth_values.size()) {
      throw std::runtime_error("fit-campaign: rank " + std::to_string(rank) +
                               " returned an outcome that is not seed " +
                               std::to_string(config.first_seed + static_cast<int>(index)) +
                               "'s");
    }
    ++received;
    if (progress != nullptr) {
      *progress << "[" << received << "/" << n << "] " << FormatSeedLine(o) << ", rank " << rank
                << std::endl;
    }
    outcomes[index] = std::move(o);
  };
  std::vector<size_t> order;
  if (mpi.rank() == 0) {
    order.resize(n);
    std::iota(order.begin(), order.end(), size_t{0});
  }
  RunMpiQueue(mpi, n, order, task, result);
  if (mpi.rank() != 0) return {};
  std::vector<SeedOutcome> out;
  out.reserve(n);
  for (std::optional<SeedOutcome>& o : outcomes) out.push_back(std::move(*o));
  return out;
}

int RunFitCampaign(const FitCampaignOptions& options, const MpiSession& mpi, std::ostream& out,
                   std::ostream& err) {
  const bool root = mpi.rank() == 0;
  // Input, on every rank; all must agree before the queue starts.
  CampaignConfig config;
  const auto load = [&]() {
    if (mpi.size() > 1 && options.jobs > 1) {
      throw std::invalid_argument("--jobs: expected 1 (or none) under mpirun, where each of "
                                  "the " + std::to_string(mpi.size()) +
                                  " ranks runs one seed at a time, got " +
                                  std::to_string(options.jobs));
    }
    for (const auto& [flag, seed] : {std::pair{"--first", options.first},
                                     std::pair{"--last", options.last}}) {
      if (seed < -1 || seed > kMaxCampaignSeed) {  // -1: not given
        throw std::invalid_argument(std::string(flag) + ": expected an integer in 0.." +
                                    std::to_string(kMaxCampaignSeed) +
                                    " (the range of seeds.first and seeds.last), got " +
                                    std::to_string(seed));
      }
    }
    config = LoadCampaign(options.campaign_path);
    if (options.first >= 0) config.first_seed = options.first;
    if (options.last >= 0) config.last_seed = options.last;
    if (config.last_seed < config.first_seed) {
      throw std::invalid_argument("--first/--last: expected first <= last, got " +
                                  std::to_string(config.first_seed) + " > " +
                                  std::to_string(config.last_seed));
    }
    if (!options.out_dir.empty()) config.out_dir = options.out_dir;
    if (config.out_dir.empty()) {
      throw std::invalid_argument(options.campaign_path +
                                  ": expected an output folder (--out DIR or output.dir in "
                                  "the campaign), got none");
    }
    // Before the seeds, not after them (the files go into it directly).
    CheckOutputDirectory(config.out_dir, /*staged=*/false);
  };
  if (!LoadOnEveryRank(mpi, load, "fit-campaign", "the campaign", err)) return 2;
  const int jobs = options.jobs > 0
                       ? options.jobs
                       : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (root) {
    out << "fit-campaign: " << config.title << ", seeds " << config.first_seed << "-"
        << config.last_seed << ", "
        << (mpi.size() > 1 ? std::to_string(mpi.size()) + " MPI ranks, one seed each at a time"
                           : std::to_string(jobs) + " in parallel")
        << std::endl;
  }
  std::vector<SeedOutcome> outcomes;
  try {
    outcomes = mpi.size() > 1 ? RunCampaignOnRanks(config, mpi, root ? &out : nullptr)
                              : RunCampaign(config, jobs, &out);
  } catch (const std::exception& e) {
    err << "fit-campaign: error: rank " << mpi.rank() << ": " << e.what() << "\n";
    err.flush();
    if (mpi.size() > 1) mpi.Abort(1);  // the other ranks would wait for the queue for ever
    return 1;
  }
  if (!root) return 0;
  try {
    const CampaignSummary summary = Summarize(config, outcomes);
    WriteCampaign(config.out_dir, config, summary, outcomes);
    out << "\n" << FormatCampaign(config, summary, outcomes) << "\nwrote " << config.out_dir
        << "/{results.csv, summary.md, summary.json}\n";
  } catch (const std::exception& e) {
    err << "fit-campaign: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace axis
