// fit-campaign CAMPAIGN.yaml [--out DIR] [--jobs N] [--first N] [--last N]
//
// Runs a Monte Carlo campaign (fit/campaign.h): the campaign's fitting job
// on freshly simulated data for every seed, the discovery loop after each
// fit, and one table of false discoveries, power, coverage and verdicts.
// Writes results.csv, summary.md and summary.json into the output folder.
// Exit codes: 0 success (also when some seeds failed: they are counted),
// 2 bad input (command line, campaign, job or generating config), 1 other
// failures.
#include <cstdio>
#include <exception>
#include <iostream>
#include <stdexcept>
#include <thread>

#include <CLI/CLI.hpp>
#include <glog/logging.h>

#include "fit/campaign.h"

int main(int argc, char** argv) {
  google::InitGoogleLogging(argv[0]);
  FLAGS_minloglevel = google::GLOG_FATAL;
  CLI::App app{"Run a fitting job over many simulated noise seeds and tally the discovery loop"};
  std::string path, out_dir;
  int jobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  int first = -1, last = -1;
  app.add_option("campaign", path, "campaign YAML file")->required();
  app.add_option("--out", out_dir, "output directory (default: the campaign's output.dir)");
  app.add_option("--jobs", jobs, "seeds run in parallel (default: the number of cores)")
      ->check(CLI::PositiveNumber);
  app.add_option("--first", first, "first seed (overrides seeds.first)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--last", last, "last seed (overrides seeds.last)")
      ->check(CLI::NonNegativeNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    axis::CampaignConfig config = axis::LoadCampaign(path);
    if (first >= 0) config.first_seed = first;
    if (last >= 0) config.last_seed = last;
    if (config.last_seed < config.first_seed) {
      throw std::invalid_argument("--first/--last: expected first <= last, got " +
                                  std::to_string(config.first_seed) + " > " +
                                  std::to_string(config.last_seed));
    }
    if (!out_dir.empty()) config.out_dir = out_dir;
    std::cout << "fit-campaign: " << config.title << ", seeds " << config.first_seed << "-"
              << config.last_seed << ", " << jobs << " in parallel\n";
    const auto outcomes = axis::RunCampaign(config, jobs, &std::cout);
    const axis::CampaignSummary summary = axis::Summarize(config, outcomes);
    axis::WriteCampaign(config.out_dir, config, summary, outcomes);
    std::cout << "\n" << axis::FormatCampaign(config, summary, outcomes)
              << "\nwrote " << config.out_dir << "/{results.csv, summary.md, summary.json}\n";
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "fit-campaign: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fit-campaign: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
