// The settings of a Monte Carlo campaign (issue 10; the `fit-campaign`
// command): the campaign file's keys and their strict loader, with the
// checks that need no simulation. Running a campaign, and LoadCampaign,
// which adds the check of the job on the first seed's simulated data, are
// run/campaign.h.
#ifndef RUN_CAMPAIGN_SETTINGS_H_
#define RUN_CAMPAIGN_SETTINGS_H_

#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace axis {

// The largest seed of a campaign (seeds.first, seeds.last, fit-campaign
// --first and --last).
constexpr int kMaxCampaignSeed = 1000000;

// A campaign file (configs/campaigns/*.yaml; paths relative to it):
//   title: "..."
//   job: ../jobs/discover/none.yaml     # the fitting job
//   generate:                           # experiment name → generating config
//     step_p4V: ../../testdata/generate/discover/none_step_p4V.yaml
//   seeds: {first: 1, last: 100}
//   discover: true                      # run the discovery loop (default)
//   truth:
//     effects: [coulomb]                # undeclared effects in the data
//     values: {F_c: 30}                 # true values, for interval coverage
//     verdict: explained                # expected verdict (optional)
//     outside_library: [friction_patch] # generator-only forces in the data
//   output: {dir: ../../build/campaigns/none}   # optional with fit-campaign --out
// Every experiment of the job (fitted and validation) needs a generating
// config; seed s simulates each noise-free and adds noise with seed
// config.seed + 1000·s (AddNoise), the input as the config defines it.
struct CampaignConfig {
  std::string path;
  std::string title;
  std::string job_path;
  std::vector<std::pair<std::string, std::string>> generate;
  int first_seed = 1;  // both 0..kMaxCampaignSeed
  int last_seed = 10;
  bool discover = true;
  std::vector<std::string> truth_effects;  // Candidate names, sorted
  std::vector<std::pair<std::string, double>> truth_values;  // MODEL.md name, SI unit
  std::string truth_verdict;  // "", "explained" or "incomplete"
  // Forces outside MODEL.md §7 in the data (GeneratorOnlyEffectTable names,
  // sorted; each switched on in a generating config). With any, no final
  // set is exact and an effect selected is a stand-in, not a false
  // discovery: the measure is the verdict (`incomplete`).
  std::vector<std::string> truth_outside;
  std::string out_dir;  // output.dir resolved; "" if the file has no output block
};

// The experiments of a job document `root` (its `experiments:` and
// `validate:` entries, in that order, those with a scalar `name`), each as
// (name, its entry's node); entries that are not such are skipped (the job's
// loader refuses them). Never throws.
std::vector<std::pair<std::string, YAML::Node>> JobExperiments(YAML::Node root);

// Reads and checks campaign file `path`, all of LoadCampaign's checks
// (run/campaign.h) before it simulates: the file's keys, a job file without
// `benchmark:` whose experiments (JobExperiments) are those of `generate:`,
// each outside_library force switched on in a generating config (each
// config loaded once, only if there is any such force). Puts into
// `truth_value_keys` the YAML key of each truth value (the order of
// truth_values), for CheckTruthValues. Throws std::invalid_argument naming
// the file, line and key ("expected …, got …"): unknown keys, first > last,
// an unknown effect name, a verdict other than explained / incomplete, an
// outside_library force that is not a generator-only one or that no
// generating config switches on; LoadYamlFile's and LoadExperiment's
// errors (io/yaml_util.h, sim/config.h).
CampaignConfig LoadCampaignSettings(const std::string& path,
                                    std::vector<YAML::Node>* truth_value_keys);

// Checks that each of config.truth_values names a parameter the fits
// estimate: one of `free_names` (the job's free parameters) or of
// `effect_names` (those the discovery loop frees for truth.effects; empty
// without discovery). Throws std::invalid_argument "<config.path>:<line>:
// key 'truth.values.<name>': expected a free parameter of <job> (…) [or of
// an effect of truth.effects (…)], got '<name>'" for the first that does
// not, its line that of truth_value_keys (LoadCampaignSettings).
void CheckTruthValues(const CampaignConfig& config, const std::vector<std::string>& free_names,
                      const std::vector<std::string>& effect_names,
                      const std::vector<YAML::Node>& truth_value_keys);

}  // namespace axis

#endif  // RUN_CAMPAIGN_SETTINGS_H_
