// report.html of the two example jobs as a person runs them (issue 14):
// the paper's identification (configs/jobs/x_axis_paper.yaml, ~2-5 s)
// and the EMPS benchmark with discovery and the published reference
// (configs/jobs/emps.yaml, ~1–2 min), each rendered in headless Chromium
// and checked (tests/browser_checks.h). Labelled slow (tests/CMakeLists.txt);
// tests/html_report_test.cc has quick versions on short windows.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run/job_run.h"
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
// too. The same run is the paper job's statistical check (it was
// FitTest.NoisyDataTruthWithinIntervals, which fitted the same job once
// more): on the noisy steps (σ_a = 0.02 m/s², σ_tach = 0.005 V, white by
// construction) every estimate lies within 3 standard errors of the truth
// of the generating configs and its 95 % interval holds it.
TEST(HtmlReportJobsTest, PaperJobInChromium) {
  std::string log;
  const std::string out = RunJob("configs/jobs/x_axis_paper.yaml", &log);
  const nlohmann::json report = nlohmann::json::parse(browser_checks::ReadFile(out + "/report.json"));
  EXPECT_TRUE(report["converged"].get<bool>()) << report["termination"];
  EXPECT_TRUE(report["undetermined"].empty()) << report["undetermined"];
  const std::map<std::string, double> truth = {
      {"V_L", 2.7}, {"B_a", 200.0}, {"b_g", 1500.0}, {"k_g", 5.0e6}, {"T_p", 0.04}};
  int checked = 0;
  for (const nlohmann::json& p : report["parameters"]) {
    const auto it = truth.find(p["name"].get<std::string>());
    if (it == truth.end()) continue;
    ++checked;
    SCOPED_TRACE(it->first);
    const double value = p["value"].get<double>(), se = p["std_error"].get<double>();
    EXPECT_GT(se, 0.0);
    EXPECT_LT(std::abs(value - it->second), 3.0 * se) << value << " ± " << se;
    EXPECT_LE(p["ci95_low"].get<double>(), it->second);
    EXPECT_GE(p["ci95_high"].get<double>(), it->second);
  }
  EXPECT_EQ(checked, 5);
  // Weighted residuals ~ N(0, 1): residual variance near 1 (m ≈ 8000,
  // so its sampling spread is about sqrt(2/m) ≈ 0.016).
  EXPECT_NEAR(report["residual_variance"].get<double>(), 1.0, 0.08);
  // The progress line's stages (the remaining time it adds after a second
  // in a phase depends on the machine's speed: ProgressTest). The cost is
  // the quadratic of its covariance out to the probes' 10 standard
  // deviations here, so the local restarts are not run and say why.
  for (const char* stage : {"; fit: start 1 of 1, horizon 0.050 s (stage 1 of 7)",
                            "; fit: optimum check, probe round 1 (at most 8)",
                            "; fit: profile-likelihood interval of T_p (5 of 5)"}) {
    EXPECT_NE(log.find(stage), std::string::npos) << stage << "\n" << log;
  }
  EXPECT_NE(report["optimum"]["check"].get<std::string>().find(
                "local restarts not run: along every principal axis the cost rose as the "
                "covariance predicts (within 10 %) out to 10 standard deviations"),
            std::string::npos)
      << report["optimum"]["check"];
  EXPECT_EQ(report["optimum"]["local_starts"].get<int>(), 0);
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
