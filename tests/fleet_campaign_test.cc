// fit-campaign on the fleet's MPI engine (issue 12; fleet/campaign_run.h):
// a small campaign (tests/campaign_files.h: four seeds of a 0.4 s record,
// B_a free, with the discovery loop) run by `mpirun -np 2` gives the same
// per-seed outcomes and summary as the one-process run with one solver
// thread per seed, both ranks run seeds, and --jobs above 1 under mpirun is
// refused as bad input.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "run/campaign.h"
#include "tests/campaign_files.h"
#include "tests/fleet_checks.h"
#include "tests/test_files.h"

namespace axis {
namespace {

using ::testing::HasSubstr;

// Runs fit-campaign with `args` on `ranks` ranks (1: alone); its exit code,
// stdout and stderr in *log.
int RunFitCampaign(const std::string& args, int ranks, const std::string& log_path,
                   std::string* log) {
  const std::string command = fleet_checks::Launcher(ranks) + std::string(BINARY_DIR) +
                              "/fit-campaign " + args + " >'" + log_path + "' 2>&1";
  const int status = std::system(command.c_str());
  *log = browser_checks::ReadFile(log_path);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// results.csv without its `seconds` column (the 7th), the wall times.
std::string WithoutSeconds(const std::string& path) {
  std::ifstream in(path);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> fields;
    std::stringstream row(line);
    for (std::string f; std::getline(row, f, ',');) fields.push_back(f);
    if (fields.size() > 6) fields.erase(fields.begin() + 6);
    for (size_t k = 0; k < fields.size(); ++k) out += (k ? "," : "") + fields[k];
    out += "\n";
  }
  return out;
}

TEST(FleetCampaignTest, MpiCampaignEqualsOneProcess) {
  const std::string campaign = campaign_files::WriteCampaign(
      "seeds: {first: 3, last: 6}\ntruth: {values: {B_a: 200}, verdict: explained}\n"
      "output: {dir: out}\n");
  const std::string dir = testing_files::TestTempDir();
  std::string log;
  // One process, four seeds at once; then two ranks, one seed each at a
  // time. The job has one experiment, hence one residual block: the solver
  // threads RunCampaign shares out cannot reorder any sum, so the outcomes
  // may be compared bit for bit on any machine.
  ASSERT_EQ(RunFitCampaign("'" + campaign + "' --jobs 4 --out '" + dir + "single'", 1,
                           dir + "single.log", &log),
            0)
      << log;
  EXPECT_THAT(log, HasSubstr("4 in parallel"));
  ASSERT_EQ(RunFitCampaign("'" + campaign + "' --out '" + dir + "mpi'", 2, dir + "mpi.log", &log),
            0)
      << log;
  EXPECT_THAT(log, HasSubstr("2 MPI ranks, one seed each at a time"));
  EXPECT_THAT(log, HasSubstr(", rank 0\n"));
  EXPECT_THAT(log, HasSubstr(", rank 1\n"));
  const std::string single = WithoutSeconds(dir + "single/results.csv");
  EXPECT_EQ(std::count(single.begin(), single.end(), '\n'), 5) << single;
  EXPECT_EQ(single, WithoutSeconds(dir + "mpi/results.csv"));
  EXPECT_EQ(browser_checks::ReadFile(dir + "single/summary.json"),
            browser_checks::ReadFile(dir + "mpi/summary.json"));

  // --jobs 2 under mpirun: bad input, exit 2, nothing written.
  EXPECT_EQ(RunFitCampaign("'" + campaign + "' --jobs 2 --out '" + dir + "bad'", 2,
                           dir + "bad.log", &log),
            2)
      << log;
  EXPECT_THAT(log, HasSubstr("--jobs: expected 1 (or none) under mpirun"));
  EXPECT_FALSE(std::filesystem::exists(dir + "bad"));
}

}  // namespace
}  // namespace axis
