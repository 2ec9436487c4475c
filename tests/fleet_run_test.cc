// fit-fleet (issue 12) on the whole synthetic fleet of configs/fleet/ (label
// `slow`: three fleet runs of eight 1 s logs, about 35 s of CPU): the
// "last month" fleet in one process and on two MPI ranks gives the same
// table; the "now" fleet on two ranks against the one-process table as
// baseline flags exactly the two aged axes (r03/x's grown Coulomb friction,
// r06/x's new load offset) and no other; its fleet.html, with the changes
// on top, in Chromium.
#include <set>
#include <string>
#include <utility>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/fleet_checks.h"
#include "tests/test_files.h"

namespace axis {
namespace {

using ::testing::HasSubstr;

const std::string kFleet = std::string(PROJECT_SOURCE_DIR) + "/configs/fleet";

TEST(FleetSyntheticTest, MpiTableEqualsOneProcessAndTheAgedAxesAreFlagged) {
  const std::string dir = testing_files::TestTempDir();
  std::string log;
  // Last month, one process (a singleton MPI process, no mpirun).
  ASSERT_EQ(fleet_checks::RunFitFleet(kFleet + "/last_month.yaml --out '" + dir + "single'", 1,
                                      dir + "single.log", &log),
            0)
      << log;
  EXPECT_THAT(log, HasSubstr("8 jobs: 8 ok, 0 not converged, 0 failed; 1 rank(s)"));
  // Last month, two ranks.
  ASSERT_EQ(fleet_checks::RunFitFleet(kFleet + "/last_month.yaml --out '" + dir + "mpi'", 2,
                                      dir + "mpi.log", &log),
            0)
      << log;
  EXPECT_THAT(log, HasSubstr("8 jobs: 8 ok, 0 not converged, 0 failed; 2 rank(s)"));
  const nlohmann::json single = fleet_checks::ReadJson(dir + "single/fleet.json");
  const nlohmann::json mpi = fleet_checks::ReadJson(dir + "mpi/fleet.json");
  EXPECT_EQ(single["ranks"], 1);
  EXPECT_EQ(mpi["ranks"], 2);
  // Both ranks fitted (rank 0 too).
  std::set<int> ranks;
  for (const auto& row : mpi["rows"]) ranks.insert(row["rank"].get<int>());
  EXPECT_EQ(ranks, (std::set<int>{0, 1}));
  // The same table, bit for bit, but for the times and ranks.
  EXPECT_EQ(fleet_checks::WithoutTimes(single).dump(1), fleet_checks::WithoutTimes(mpi).dump(1));
  ASSERT_EQ(single["rows"].size(), 8u);
  for (const auto& row : single["rows"]) {
    EXPECT_EQ(row["status"], "ok") << row["axis"];
    EXPECT_EQ(row["verdict"], "explained") << row["axis"];
  }

  // Now, two ranks, against last month's one-process table.
  ASSERT_EQ(fleet_checks::RunFitFleet(kFleet + "/now.yaml --out '" + dir + "now' --baseline '" +
                                          dir + "single/fleet.json'",
                                      2, dir + "now.log", &log),
            0)
      << log;
  const nlohmann::json now = fleet_checks::ReadJson(dir + "now/fleet.json");
  const nlohmann::json& comparison = now["comparison"];
  EXPECT_EQ(comparison["tests"], 24);  // 3 free parameters of 8 axes
  EXPECT_TRUE(comparison["not_compared"].empty()) << comparison["not_compared"];
  std::set<std::pair<std::string, std::string>> flagged;
  for (const auto& change : comparison["changes"]) {
    flagged.emplace(change["axis"].get<std::string>(), change["name"].get<std::string>());
  }
  EXPECT_EQ(flagged, (std::set<std::pair<std::string, std::string>>{{"r03/x", "F_c"},
                                                                    {"r06/x", "F_0"}}))
      << comparison["changes"].dump(1);
  for (const auto& change : comparison["changes"]) {
    if (change["axis"] == "r03/x") {  // 25 -> 40 N in the generating configs
      EXPECT_NEAR(change["baseline_value"].get<double>(), 25.0, 0.5);
      EXPECT_NEAR(change["value"].get<double>(), 40.0, 0.5);
      EXPECT_THAT(change["text"].get<std::string>(),
                  HasSubstr("axis r03/x (now): F_c 40.0"));
    } else {  // 0 -> 50 N
      EXPECT_NEAR(change["baseline_value"].get<double>(), 0.0, 0.5);
      EXPECT_NEAR(change["value"].get<double>(), 50.0, 0.5);
    }
  }
  EXPECT_THAT(log, HasSubstr("## Changes since"));
  fleet_checks::CheckFleetInBrowser(dir + "now", {"changes", "axes"});
}

}  // namespace
}  // namespace axis
