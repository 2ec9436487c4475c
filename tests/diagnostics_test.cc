// The residual diagnostics (discovery/diagnostics.h) against residuals planted in
// noise-free data: a step in the arm velocity shows in the bins of v with
// the planted bin means, and a residual that follows the input 7 samples
// late shows as a cross-correlation peak at lag 7.
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/statistics.h"
#include "discovery/diagnostics.h"
#include "estimation/fit_result.h"
#include "run/load_fit_job.h"
#include "sim/config.h"
#include "io/csv.h"
#include "sim/experiment.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;
constexpr double kStepInV = 0.02;  // V on tach where v > 0.3 m/s
constexpr double kVelocityEdge = 0.3;
constexpr double kDelayedGain = 0.01;  // m/s² per V of u, 7 samples late
constexpr int kLag = 7;

TEST(DiagnosticsTest, PlantedResidualsAreFound) {
  // The PRBS record of issue 9, noise-free, at the model's own parameters:
  // the fit residual is then the planted one (to CSV round-off).
  const ExperimentConfig e = LoadExperiment(kRoot + "/configs/experiments/x_prbs.yaml");
  const Trace<double> trace = RunExperiment(e);
  ASSERT_TRUE(trace.finite);
  const std::vector<double>& u = trace[Channel::kU];
  const std::vector<double>& v = trace[Channel::kV];
  std::vector<double> tach = trace[Channel::kTach], a = trace[Channel::kA];
  for (size_t k = 0; k < v.size(); ++k) {
    // residual = simulated − measured
    tach[k] -= v[k] > kVelocityEdge ? kStepInV : 0.0;
    a[k] -= k >= kLag ? kDelayedGain * u[k - kLag] : 0.0;
  }
  const std::string dir = testing_files::TestTempDir();
  WriteCsvAtomic(dir + "planted.csv", {"t", "u", "a", "tach"}, {trace.t, u, a, tach}, 17);
  const std::string job_path = testing_files::WriteTemp(
      "job.yaml", "model: " + kRoot + "/configs/axes/x_axis.yaml\n"
                  "free:\n  B_a: {initial: 200, lower: 10, upper: 2000}\n"
                  "experiments:\n  - name: prbs\n    data: planted.csv\n"
                  "    channels: {u: u, a: a, tach: tach}\n"
                  "    input: {column: u, interpolation: hold}\n"
                  "    fit: {a: 0.02, tach: 0.005}\n");
  const std::vector<ChannelDiagnostics> d = DiagnoseResiduals(LoadFitJob(job_path).problem);
  ASSERT_EQ(d.size(), 2u);
  const ChannelDiagnostics& da = d[0].channel == "a" ? d[0] : d[1];
  const ChannelDiagnostics& dt = d[0].channel == "tach" ? d[0] : d[1];

  // Tach vs v: bins wholly above the edge have mean kStepInV, bins wholly
  // below have mean 0 (the CSV holds 17 digits: round-off only).
  const BinnedResidual* by_v = nullptr;
  for (const BinnedResidual& b : dt.bins) {
    if (b.variable == "v") by_v = &b;
  }
  ASSERT_NE(by_v, nullptr);
  ASSERT_GE(by_v->center.size(), 8u);
  const double half_width = (by_v->center[1] - by_v->center[0]) / 2;
  int above = 0, below = 0;
  for (size_t j = 0; j < by_v->center.size(); ++j) {
    if (by_v->center[j] - half_width > kVelocityEdge) {
      EXPECT_NEAR(by_v->mean[j], kStepInV, 1e-9) << by_v->center[j];
      ++above;
    } else if (by_v->center[j] + half_width < kVelocityEdge) {
      EXPECT_NEAR(by_v->mean[j], 0.0, 1e-9) << by_v->center[j];
      ++below;
    }
  }
  EXPECT_GE(above, 2);
  EXPECT_GE(below, 2);
  EXPECT_LT(by_v->p_value, 1e-10);

  // The accelerometer residual is the input, 7 samples late: the
  // normalised cross-correlation peaks at that lag, at 1 up to the first 7
  // samples the shifted copy lacks.
  EXPECT_EQ(da.xcorr_lag, kLag);
  EXPECT_GT(std::abs(da.xcorr_peak), 0.99);
  // Structured, not white.
  EXPECT_LT(da.ljung_box_p, 1e-10);
}

// JudgeResiduals against hand-computed figures: 4 tests (s², Ljung–Box,
// two binned variables) at alpha = 1e-3 give a threshold of 2.5e-4 each.
TEST(DiagnosticsTest, VerdictFromHandComputedTests) {
  ChannelDiagnostics d;
  d.experiment = "e";
  d.channel = "a";
  d.unit = "m/s^2";
  d.rms = 0.02;
  d.sigma = 0.02;
  d.ljung_box_p = 0.5;
  BinnedResidual v;
  v.variable = "v";
  v.unit = "m/s";
  v.width = 0.1;
  v.center = {0.05, 0.15, 0.25, 0.35};
  v.mean = {0.0, 0.0, 0.0, 0.0};
  v.std_error = {0.001, 0.001, 0.001, 0.001};
  v.count = {100, 100, 100, 100};
  v.dof = 4;
  v.chi2 = 0.0;
  v.p_value = 1.0;
  BinnedResidual x = v;
  x.variable = "x";
  x.unit = "m";
  d.bins = {v, x};
  FitResult fit;
  fit.num_residuals = 1000;
  fit.residual_dof = 995.0;  // five free parameters
  fit.residual_variance = 1.0;

  ResidualVerdict verdict = JudgeResiduals({d}, fit, 1e-3);
  EXPECT_EQ(verdict.tests, 4);
  EXPECT_DOUBLE_EQ(verdict.threshold, 2.5e-4);
  EXPECT_DOUBLE_EQ(verdict.s2, 1.0);
  EXPECT_EQ(verdict.verdict, "explained");
  EXPECT_TRUE(verdict.remains.empty());

  // A step in v above 0.2 m/s: bins 3 and 4 at 10 and 12 standard errors
  // (χ² 244 on 4 dof) → significant, and named as the range [0.2, 0.4].
  d.bins[0].mean = {0.0, 0.0, 0.010, 0.012};
  d.bins[0].chi2 = 244.0;
  d.bins[0].p_value = ChiSquaredSurvival(244.0, 4);
  verdict = JudgeResiduals({d}, fit, 1e-3);
  EXPECT_EQ(verdict.verdict, "incomplete");
  ASSERT_EQ(verdict.remains.size(), 1u);
  EXPECT_NE(verdict.remains[0].find("depends on v"), std::string::npos) << verdict.remains[0];
  EXPECT_NE(verdict.remains[0].find("in [0.2, 0.4] m/s"), std::string::npos)
      << verdict.remains[0];

  // s² = 1200/995: (1200 − 995)/√(2·995) = 4.6 standard deviations of χ²₉₉₅
  // above its mean, p ≈ 2e-6 < 2.5e-4; and a coloured residual.
  d.bins[0] = v;
  d.ljung_box_p = 1e-5;
  fit.residual_variance = 1200.0 / 995.0;
  verdict = JudgeResiduals({d}, fit, 1e-3);
  EXPECT_EQ(verdict.verdict, "incomplete");
  EXPECT_NEAR(verdict.s2, 1200.0 / 995.0, 1e-12);
  EXPECT_LT(verdict.s2_p_value, 1e-5);
  EXPECT_GT(verdict.s2_p_value, 1e-7);
  ASSERT_EQ(verdict.remains.size(), 2u);
  EXPECT_NE(verdict.remains[1].find("not white"), std::string::npos);

  // After a kept force map the degrees of freedom are m − edf (21.4 here),
  // not an integer: the tail is taken at the nearest integer, 979.
  d.ljung_box_p = 0.5;
  fit.residual_dof = 1000.0 - 21.4;
  fit.residual_variance = 1.1;
  verdict = JudgeResiduals({d}, fit, 1e-3);
  EXPECT_DOUBLE_EQ(verdict.s2, 1.1);
  EXPECT_DOUBLE_EQ(verdict.s2_p_value, ChiSquaredSurvival(1.1 * 978.6, 979));
  // No degrees of freedom left: no s² test.
  fit.residual_dof = 0.0;
  verdict = JudgeResiduals({d}, fit, 1e-3);
  EXPECT_TRUE(std::isnan(verdict.s2));

  EXPECT_THROW(JudgeResiduals({d}, fit, 0.0), std::invalid_argument);
  EXPECT_THROW(JudgeResiduals({d}, fit, -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace axis
