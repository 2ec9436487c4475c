// Helpers of the fit-fleet tests (tests/fleet_test.cc, quick;
// tests/fleet_run_test.cc, slow): running build/bin/fit-fleet alone or under
// `mpirun --oversubscribe -np N`, comparing fleet tables without their
// times, and checking fleet.html in headless Chromium (tests/browser_checks.h).
#ifndef TESTS_FLEET_CHECKS_H_
#define TESTS_FLEET_CHECKS_H_

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/browser_checks.h"
#include "tests/test_files.h"

namespace axis {
namespace fleet_checks {

// The command prefix that starts `ranks` MPI processes ("" for 1: the
// binary alone, a singleton MPI process). OpenMPI refuses root unless told.
inline std::string Launcher(int ranks) {
  if (ranks <= 1) return "";
  const std::string root =
      geteuid() == 0 ? "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " : "";
  return root + "mpirun --oversubscribe -np " + std::to_string(ranks) + " ";
}

// Runs fit-fleet with `args` on `ranks` ranks; returns its exit code, its
// stdout and stderr in *log (also kept in `log_path`).
inline int RunFitFleet(const std::string& args, int ranks, const std::string& log_path,
                       std::string* log) {
  const std::string command = Launcher(ranks) + std::string(BINARY_DIR) + "/fit-fleet " + args +
                              " >'" + log_path + "' 2>&1";
  const int status = std::system(command.c_str());
  *log = browser_checks::ReadFile(log_path);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// fleet.json without what differs from run to run: the wall times, the
// rank that ran each job, the number of ranks.
inline nlohmann::json WithoutTimes(nlohmann::json table) {
  table.erase("wall_seconds");
  table.erase("ranks");
  for (auto& row : table["rows"]) {
    row.erase("seconds");
    row.erase("rank");
  }
  return table;
}

// Renders `dir`/fleet.html in Chromium: a screenshot that is not blank,
// and in the loaded DOM the `sections`, one table row per row of
// fleet.json (its axis in it, linked to <folder>/report.html, which exists,
// unless the job failed), nothing loaded from outside and no link but to
// the page's anchors and the axes' reports. The screenshot stays in
// `dir`/fleet.png for a person to look at.
inline void CheckFleetInBrowser(const std::string& dir, const std::vector<std::string>& sections) {
  browser_checks::RenderedPage page;
  browser_checks::RenderInChromium(std::filesystem::absolute(dir + "/fleet.html").string(),
                                   std::filesystem::absolute(dir + "/fleet.png").string(), &page);
  if (!page.loaded) return;
  // A blank page is one colour; this one has a heading, text and tables
  // (in the upper part of the 4000 px tall window).
  EXPECT_GT(page.picture.colours, 50u) << dir << "/fleet.png";
  EXPECT_GT(page.picture.non_white, 0.005) << dir << "/fleet.png";
  EXPECT_GT(page.picture.dark, 0.001) << dir << "/fleet.png";
  const std::string& dom = page.dom;
  for (const std::string& id : sections) {
    EXPECT_NE(dom.find("<section id=\"" + id + "\">"), std::string::npos) << "no section " << id;
  }
  const nlohmann::json table = ReadJson(dir + "/fleet.json");
  std::vector<std::string> links;
  for (const auto& row : table["rows"]) {
    const std::string axis = row["axis"].get<std::string>();
    if (row["status"] == "failed") {
      EXPECT_NE(dom.find("<td>" + axis + "</td>"), std::string::npos) << axis;
      continue;
    }
    const std::string link = row["folder"].get<std::string>() + "/report.html";
    links.push_back(link);
    EXPECT_NE(dom.find("<a href=\"" + link + "\">" + axis + "</a>"), std::string::npos)
        << "no link to " << link;
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + link)) << link;
  }
  // One <tr> per row in the axes table plus its header.
  const size_t axes_at = dom.find("<section id=\"axes\">");
  ASSERT_NE(axes_at, std::string::npos);
  const std::string axes = dom.substr(axes_at, dom.find("</section>", axes_at) - axes_at);
  EXPECT_EQ(browser_checks::Count(axes, "<tr>"), table["rows"].size() + 1);
  EXPECT_NE(axes.find("class=\"sortable\""), std::string::npos) << "the table is not sortable";
  browser_checks::ExpectNothingLoadedFromOutside(dom);
  // Every href: an anchor of the page or an axis's report.
  for (size_t at = dom.find("href=\""); at != std::string::npos; at = dom.find("href=\"", at + 1)) {
    const size_t from = at + 6;
    const std::string target = dom.substr(from, dom.find('"', from) - from);
    const bool anchor = !target.empty() && target[0] == '#';
    const bool report = std::find(links.begin(), links.end(), target) != links.end();
    EXPECT_TRUE(anchor || report) << "a link out of the page: " << target;
  }
}

}  // namespace fleet_checks
}  // namespace axis

#endif  // TESTS_FLEET_CHECKS_H_
