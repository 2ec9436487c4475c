// Monte Carlo campaigns (issue 10): one fitting job run over many noise
// seeds of the configs that generate its data, with the discovery loop's
// outcome tallied against the truth the generating configs hold: false
// discoveries on null data, power (right effect first, exact final set),
// interval coverage of true values, the verdict. The `fit-campaign` command.
#ifndef RUN_CAMPAIGN_H_
#define RUN_CAMPAIGN_H_

#include <limits>
#include <map>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "run/campaign_settings.h"
#include "run/fit_job.h"

namespace axis {

// Loads and checks a campaign file: every generating config is loaded and
// the job is loaded with the first seed's simulated data (errors name their
// files; the job's own `data:` paths need not exist), each job experiment must have
// a generating config and each generating config must name a job
// experiment. Throws std::invalid_argument naming the file, line and key
// ("expected …, got …"): unknown keys, first > last, an unknown effect name,
// a verdict other than explained / incomplete, an outside_library force that
// is not a generator-only one or that no generating config switches on, a
// truth value that no fit estimates. The file's own checks are
// LoadCampaignSettings's (run/campaign_settings.h); the job on the first
// seed's data and the truth values are checked here (CheckTruthValues).
CampaignConfig LoadCampaign(const std::string& path);

// What one seed gave.
struct SeedOutcome {
  int seed = 0;
  std::string error;                   // non-empty: the seed failed (message)
  std::vector<std::string> selected;   // final selected effects, sorted
  std::string first_added;             // the first effect the loop kept, or ""
  // Effects whose refit failed from the score step and was retried from a
  // tenth of it (DiscoveryStep::retried), in the order of the steps.
  std::vector<std::string> retried;
  std::string verdict;                 // "explained" / "incomplete"
  double s2 = 0.0;                     // residual variance in σ units
  // With discover.force_map (discovery/force_map.h): the map the step kept
  // ("force_map.x_friction"), "" if none; `verdict` stays the library's.
  std::string force_map;
  // Per truth value (same order): estimate, 95 % interval; NaN if the
  // parameter is not in the final model.
  std::vector<double> value, ci95_low, ci95_high;
  double seconds = 0.0;                // wall time of simulate + fit + loop
  // With the job's `tune:` (tune/analog_loop_tuning.h): the proposed T_p
  // (s) and whether the spec holds with the proposal applied to the axis
  // that made the records (the first generating config's model, its
  // undeclared effects included): 1 yes, 0 no, −1 no tuning ran; the
  // first violation there, "" if none.
  double tuned_T_p = std::numeric_limits<double>::quiet_NaN();
  int spec_met_true = -1;
  std::string spec_violation_true;
  // The same for the move tuning (`tune.move:`): its proposal (K_1, T_p,
  // controller gains and move) on the true axis.
  int move_spec_met_true = -1;
  std::string move_spec_violation_true;
  // Whether the move tuning said its proposal meets the spec at the
  // estimate and at every check (MoveSetting::robust): 1, 0, −1 none.
  int move_robust = -1;
  // With tune.move.klipper: the setting with the shaper Klipper's rule
  // recommends (MoveTuning::klipper) on the true axis: 1, 0, −1 none; its
  // first violation there.
  int klipper_spec_met_true = -1;
  std::string klipper_spec_violation_true;
};

// The job of seed `seed`: each experiment of config.job_path simulated from
// its generating config with noise seed (the config's seed) + 1000·seed,
// written as <dir>/<experiment>.csv (`dir` must exist), and the job loaded
// (ParseFitJob) with its data paths pointing there. Throws
// std::invalid_argument as ParseFitJob, std::runtime_error if a simulation
// leaves the finite numbers or a file cannot be written.
FitJob CampaignSeedJob(const CampaignConfig& config, int seed, const std::string& dir);

// Seed `seed` of the campaign: its records simulated (CampaignSeedJob, into
// a temporary folder, removed after) and the job run through fit-params'
// own pipeline (RunJob, run/job_run.h: the fit, the current-loop check and
// full-loop refit, the discovery loop and force map if config.discover,
// the diagnostics) with `solver_threads` Ceres threads, its printed text
// dropped. With config.discover false the job's own `discover:` is off too
// (the verdict then judges the fitted model's diagnostics). A failure (bad
// data, a fit that throws) is recorded in SeedOutcome::error, not thrown
// (except std::bad_alloc).
SeedOutcome RunCampaignSeed(const CampaignConfig& config, int seed, int solver_threads);

// The progress line of a finished seed, without a newline:
// "seed 4: selected {coulomb}, verdict explained (31 s)" or
// "seed 4: failed: <message> (2 s)".
std::string FormatSeedLine(const SeedOutcome& outcome);

// A seed's outcome as JSON and back (the messages of the MPI campaign,
// fleet/campaign_run.h): numbers that are not finite are null (read back as
// NaN); doubles round-trip exactly. SeedOutcomeFromJson throws
// std::invalid_argument "<where>: expected …, got …" for a document that is
// not such an outcome.
nlohmann::json SeedOutcomeToJson(const SeedOutcome& outcome);
SeedOutcome SeedOutcomeFromJson(const nlohmann::json& json, const std::string& where);

// Runs seeds first..last on `threads` worker threads (each fit single
// threaded when threads > 1), writing one line per finished seed to
// `progress`. A seed whose fit throws is recorded with its message, not
// fatal (RunCampaignSeed catches every std::exception; anything else is
// rethrown after the other seeds have run, common/concurrency.h). Throws
// std::invalid_argument if threads < 1.
std::vector<SeedOutcome> RunCampaign(const CampaignConfig& config, int threads,
                                     std::ostream* progress);

// One rate: k of n, with its exact (Clopper–Pearson) 95 % interval
// (boost::math::binomial_distribution).
struct Rate {
  int k = 0;
  int n = 0;
  double low = 0.0, high = 1.0;
};
Rate RateOf(int k, int n);

// The campaign's figures: seeds run and failed, false discoveries (truth
// without effects) or right effect first and exact final set, per truth
// value coverage, verdict counts.
struct CampaignSummary {
  int seeds = 0;
  int failed = 0;
  // A plant effect selected (sensor front-end terms apart: they say how the
  // record was made, MODEL.md §6); only if truth_effects is empty.
  Rate false_discovery;
  // A front-end term selected; when the truth names none (records behind
  // an undeclared front end: found, or explained otherwise).
  Rate front_end_selected;
  Rate right_first;      // first added in truth_effects; only if not empty
  Rate exact_set;        // selected == truth_effects
  std::vector<Rate> covered;  // per truth value: inside the 95 % interval
  // All truth values pooled (seeds × values; only with two or more). The
  // values of one seed share its noise, so the Clopper–Pearson interval of
  // the pooled rate is narrower than its true spread.
  Rate covered_pooled;
  Rate verdict_as_expected;   // only if truth_verdict is set
  // With `tune:`: seeds whose proposal meets the spec on the true axis,
  // of those tuned.
  Rate spec_met_true;
  Rate move_spec_met_true;  // with `tune.move:`, likewise
  // With `tune.move:`: of the seeds whose proposal the tuning said meets
  // the spec at the estimate and every check (MoveSetting::robust), those
  // where it met it on the true axis: whether that claim holds.
  Rate move_claim_held;
  // With tune.move.klipper: the seeds whose Klipper-rule setting met the
  // move spec on the true axis (SeedOutcome::klipper_spec_met_true).
  Rate klipper_spec_met_true;
  int explained = 0, incomplete = 0;
  // Seeds per force map kept ("force_map.x_friction" → count), with
  // discover.force_map; empty without.
  std::map<std::string, int> force_maps;
};
CampaignSummary Summarize(const CampaignConfig& config,
                          const std::vector<SeedOutcome>& outcomes);

// The summary as a markdown table and the per-seed table.
std::string FormatCampaign(const CampaignConfig& config, const CampaignSummary& summary,
                           const std::vector<SeedOutcome>& outcomes);

// Writes results.csv (one row per seed), summary.md and summary.json into
// `dir` (created; each file written to a temporary name and renamed).
// Throws std::runtime_error if a file cannot be written.
void WriteCampaign(const std::string& dir, const CampaignConfig& config,
                   const CampaignSummary& summary,
                   const std::vector<SeedOutcome>& outcomes);

}  // namespace axis

#endif  // RUN_CAMPAIGN_H_
