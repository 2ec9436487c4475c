// report.html of the two example jobs as a person runs them (issue 14):
// the paper's identification (configs/jobs/x_axis_paper.yaml, ~30–60 s)
// and the EMPS benchmark with discovery and the published reference
// (configs/jobs/emps.yaml, ~1–2 min), each rendered in headless Chromium
// and checked (tests/browser_checks.h). Labelled slow (tests/CMakeLists.txt);
// tests/html_report_test.cc has quick versions on short windows.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "tests/browser_checks.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;

// fit-params on the job file `job` (relative to the source tree) into a
// temporary folder; returns the folder, its output in *log.
std::string RunJob(const std::string& job, std::string* log) {
  const std::string out = testing_files::TestTempDir() + "out";
  std::filesystem::remove_all(out);
  EXPECT_EQ(browser_checks::RunFitParamsCli(kRoot + "/" + job, out, log), 0) << *log;
  return out;
}

// With the whole optimum check and profile intervals: their progress lines
// too.
TEST(HtmlReportJobsTest, PaperJobInChromium) {
  std::string log;
  const std::string out = RunJob("configs/jobs/x_axis_paper.yaml", &log);
  for (const char* stage : {"; fit: start 1 of 1, horizon 0.050 s (stage 1 of 7)",
                            "; fit: optimum check, probe round 1 (at most 8)",
                            "; fit: local restart 1 of 10 (pass 1)",
                            "; fit: profile-likelihood interval of T_p (5 of 5); profile "
                            "intervals ~"}) {
    EXPECT_NE(log.find(stage), std::string::npos) << stage << "\n" << log;
  }
  browser_checks::CheckInBrowser(out, {"summary", "data", "parameters", "correlation",
                                       "experiments", "validation", "diagnostics", "solver"});
}

TEST(HtmlReportJobsTest, EmpsJobInChromium) {
  std::string log;
  const std::string out = RunJob("configs/jobs/emps.yaml", &log);
  EXPECT_NE(log.find("; discovery backward pass: refit without "), std::string::npos) << log;
  browser_checks::CheckInBrowser(out, {"summary", "data", "parameters", "correlation",
                                       "experiments", "validation", "diagnostics", "discovery",
                                       "published", "solver"});
}

}  // namespace
}  // namespace axis
