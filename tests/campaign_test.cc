// The Monte Carlo campaign (fit/campaign.h, fit-campaign): the strict
// loader, the Clopper–Pearson rates against closed forms, and a small
// campaign end to end (a 0.4 s sine record, B_a alone free, no discovery):
// every seed draws its own noise, the tallies match the per-seed outcomes,
// and the files are written.
#include <cmath>
#include <fstream>
#include <set>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fit/campaign.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;

// A short generating config and a job fitting B_a on it, in the test's
// folder; the campaign file is `campaign` with the job and generator keys
// prepended.
std::string WriteCampaign(const std::string& campaign) {
  testing_files::WriteTemp(
      "sine.yaml", "model: " + kRoot + "/configs/axes/x_axis.yaml\n"
                   "duration: 0.4\nstep: 1.0e-5\noutput_rate: 1000\n"
                   "channels: [u, a, tach]\nnoise: {a: 0.02, tach: 0.005}\nseed: 7\n"
                   "input: {type: sine, amplitude: 3, frequency: 2}\n");
  testing_files::WriteTemp(
      "job.yaml", "model: " + kRoot + "/configs/axes/x_axis.yaml\n"
                  "free:\n  B_a: {initial: 150, lower: 10, upper: 2000}\n"
                  "experiments:\n  - name: sine\n    data: replaced.csv\n"
                  "    channels: {u: u, a: a, tach: tach}\n    input: {column: u}\n"
                  "    fit: {a: 0.02, tach: 0.005}\n"
                  "uncertainty: {method: gauss_newton}\n");
  return testing_files::WriteTemp("campaign.yaml",
                                  "job: job.yaml\ngenerate: {sine: sine.yaml}\n" + campaign);
}

// LoadCampaign's message for the file `path` ("" if it loads).
std::string ErrorLoading(const std::string& path) {
  try {
    LoadCampaign(path);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

std::string LoadError(const std::string& campaign) {
  return ErrorLoading(WriteCampaign(campaign));
}

TEST(CampaignTest, StrictLoader) {
  const std::string ok = "seeds: {first: 1, last: 2}\noutput: {dir: out}\n";
  EXPECT_EQ(LoadError(ok), "");
  std::string e = LoadError(ok + "seeds_typo: 3\n");
  EXPECT_NE(e.find("seeds_typo"), std::string::npos) << e;
  e = LoadError("seeds: {first: 5, last: 2}\noutput: {dir: out}\n");
  EXPECT_NE(e.find("campaign.yaml:3"), std::string::npos) << e;
  EXPECT_NE(e.find("seeds.last"), std::string::npos) << e;
  e = LoadError(ok + "truth: {effects: [friction]}\n");
  EXPECT_NE(e.find("truth.effects"), std::string::npos) << e;
  EXPECT_NE(e.find("got 'friction'"), std::string::npos) << e;
  e = LoadError(ok + "truth: {verdict: maybe}\n");
  EXPECT_NE(e.find("truth.verdict"), std::string::npos) << e;
  // A generating config for an experiment the job does not have.
  const std::string path = WriteCampaign(ok);
  std::ofstream(path) << "job: job.yaml\ngenerate: {sine: sine.yaml, step: sine.yaml}\n" << ok;
  e = ErrorLoading(path);
  EXPECT_NE(e.find("generate.step"), std::string::npos) << e;
  // An experiment of the job without a generating config.
  std::ofstream(path) << "job: job.yaml\ngenerate: {other: sine.yaml}\n" << ok;
  e = ErrorLoading(path);
  EXPECT_NE(e.find("experiment 'sine'"), std::string::npos) << e;
}

// Clopper–Pearson: k = 0 of n has upper bound 1 − 0.025^(1/n); k = n has
// lower bound 0.025^(1/n); 5 of 10 gives [0.1871, 0.8129] (tables, e.g.
// Clopper & Pearson 1934).
TEST(CampaignTest, ClopperPearsonRates) {
  const Rate none = RateOf(0, 10);
  EXPECT_EQ(none.low, 0.0);
  EXPECT_NEAR(none.high, 1.0 - std::pow(0.025, 0.1), 1e-9);
  const Rate all = RateOf(10, 10);
  EXPECT_NEAR(all.low, std::pow(0.025, 0.1), 1e-9);
  EXPECT_EQ(all.high, 1.0);
  const Rate half = RateOf(5, 10);
  EXPECT_NEAR(half.low, 0.18709, 1e-4);
  EXPECT_NEAR(half.high, 0.81291, 1e-4);
}

TEST(CampaignTest, SmallCampaignEndToEnd) {
  CampaignConfig config = LoadCampaign(WriteCampaign(
      "seeds: {first: 3, last: 6}\ndiscover: false\n"
      "truth: {values: {B_a: 200}, verdict: explained}\noutput: {dir: out}\n"));
  const std::vector<SeedOutcome> outcomes = RunCampaign(config, 2, nullptr);
  ASSERT_EQ(outcomes.size(), 4u);
  std::set<double> estimates;
  int covered = 0, explained = 0;
  for (size_t k = 0; k < outcomes.size(); ++k) {
    const SeedOutcome& o = outcomes[k];
    EXPECT_EQ(o.seed, 3 + static_cast<int>(k));
    ASSERT_EQ(o.error, "") << o.seed;
    ASSERT_EQ(o.value.size(), 1u);
    // The estimate is near the truth (a 0.4 s record determines B_a to a
    // few N·s/m) and each seed's noise gives another value.
    EXPECT_NEAR(o.value[0], 200.0, 20.0);
    estimates.insert(o.value[0]);
    covered += o.ci95_low[0] <= 200.0 && 200.0 <= o.ci95_high[0];
    explained += o.verdict == "explained";
  }
  EXPECT_EQ(estimates.size(), 4u);
  const CampaignSummary s = Summarize(config, outcomes);
  EXPECT_EQ(s.seeds, 4);
  EXPECT_EQ(s.failed, 0);
  ASSERT_EQ(s.covered.size(), 1u);
  EXPECT_EQ(s.covered[0].k, covered);
  EXPECT_EQ(s.covered[0].n, 4);
  EXPECT_EQ(s.explained, explained);
  EXPECT_EQ(s.false_discovery.n, 0);  // no discovery run
  const std::string dir = testing_files::TestTempDir() + "campaign_out";
  WriteCampaign(dir, config, s, outcomes);
  std::ifstream csv(dir + "/results.csv");
  int lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, 5);
  std::ifstream in(dir + "/summary.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["coverage"]["B_a"]["k"], covered);
  EXPECT_EQ(j["seeds"]["run"], 4);
}

TEST(CampaignTest, CommandLineErrorsExitWithTwo) {
  const auto r = testing_files::RunCommand(std::string(BINARY_DIR) + "/fit-campaign",
                                           testing_files::TestTempDir() + "missing.yaml", true);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing.yaml"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace axis
