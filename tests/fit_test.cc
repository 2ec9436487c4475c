// fit-params on synthetic ground truth (testdata/, truth = MODEL.md §2):
// recovery from factor-2 starts on noise-free data, coverage of the
// uncertainty on noisy data, multi-start from random points, and the
// autodiff Jacobian of the cost against central differences.
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "fit/experiment_cost.h"
#include "sim/random.h"
#include "fit/fit.h"
#include "fit/job.h"
#include "tests/cost_checks.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;
const std::map<std::string, double> kTruth = {
    {"V_L", 2.7}, {"B_a", 200.0}, {"b_g", 1500.0}, {"k_g", 5.0e6}, {"T_p", 0.04}};

// The paper job (configs/jobs/x_axis_paper.yaml) on `suffix` data ("" noisy,
// "_clean" noise-free), with the given initial values.
std::string PaperJob(const std::string& suffix,
                     const std::map<std::string, double>& initial,
                     int starts = 0, int seed = 1, double window = 0.0,
                     int probe_rounds = 8) {
  std::ostringstream y;
  y << "model: " << kRoot << "/configs/axes/x_axis.yaml\n"
    << "free:\n"
    << "  V_L: {initial: " << initial.at("V_L") << ", lower: 0.5, upper: 20}\n"
    << "  B_a: {initial: " << initial.at("B_a") << ", lower: 10, upper: 2000}\n"
    << "  b_g: {initial: " << initial.at("b_g") << ", lower: 100, upper: 20000}\n"
    << "  k_g: {initial: " << initial.at("k_g") << ", lower: 5.0e5, upper: 5.0e7}\n"
    << "  T_p: {initial: " << initial.at("T_p") << ", lower: 0.005, upper: 1.0}\n"
    << "experiments:\n";
  for (const char* name : {"x_step_10V", "x_step_4V"}) {
    y << "  - name: " << name << "\n"
      << "    data: " << kRoot << "/testdata/" << name << suffix << ".csv\n"
      << "    channels: {u: u, a: a, tach: tach}\n"
      << "    input: {column: u}\n"
      << "    fit: {a: 0.02, tach: 0.005}\n";
    if (window > 0.0) y << "    window: [0, " << window << "]\n";
  }
  y << "solver: {starts: " << starts << ", seed: " << seed
    << ", threads: 2, max_iterations: 200, probe_rounds: " << probe_rounds << "}\n";
  const std::string path = axis::testing_files::TestTempDir() + "paper_job_" +
                           std::to_string(std::hash<std::string>()(y.str())) + ".yaml";
  std::ofstream(path) << y.str();
  return path;
}

std::map<std::string, double> Scaled(double factor_even, double factor_odd) {
  std::map<std::string, double> out;
  int k = 0;
  for (const char* name : {"V_L", "B_a", "b_g", "k_g", "T_p"}) {
    out[name] = kTruth.at(name) * (k++ % 2 == 0 ? factor_even : factor_odd);
  }
  return out;
}

const ParameterEstimate& Estimate(const FitResult& r, const std::string& name) {
  for (const ParameterEstimate& p : r.parameters) {
    if (p.name == name) return p;
  }
  throw std::runtime_error("no parameter " + name);
}

// `method`: the interval method (the job's default, profile likelihood,
// unless a test that asserts only the estimate asks for Gauss–Newton, which
// skips the profile's refits).
FitResult Fit(const std::string& job_path,
              UncertaintySettings::Method method = UncertaintySettings::Method::kProfile) {
  FitJob job = LoadFitJob(job_path);
  job.solver.progress = false;
  job.uncertainty.method = method;
  return FitParameters(job);
}

// Noise-free data: the truth is the exact minimum (up to the RK4 error, which
// is identical in data and model because both use the same 10 µs grid), so
// the estimates must reach it to the solver's tolerance; 1e-4 relative is
// the requirement. Every parameter starts a factor of 2 off,
// alternating direction, both ways. From the second start a single LM run
// ends in a T_p local minimum (T_p ≈ 0.018 s): two extra random starts
// (multi-start, allowed by the issue) find the truth. The optimum check
// (solver.probe_rounds) is off: the starts alone must reach it (with the
// check, the test took 34 s of the suite instead of 8 s).
TEST(FitTest, NoiseFreeRecoveryFromFactorTwoAboveAndBelow) {
  for (const auto& start : {Scaled(2.0, 0.5), Scaled(0.5, 2.0)}) {
    const FitResult r = Fit(PaperJob("_clean", start, /*starts=*/2, 1, 0.0,
                                     /*probe_rounds=*/0),
                            UncertaintySettings::Method::kGaussNewton);
    for (const auto& [name, truth] : kTruth) {
      const ParameterEstimate& e = Estimate(r, name);
      EXPECT_NEAR(e.value / truth, 1.0, 1e-4)
          << name << " from " << start.at(name) << ": " << e.value;
    }
    RecordProperty("final_cost", std::to_string(r.final_cost));
  }
}

// The paper job on noisy data (truth within 3 standard errors and inside
// the 95 % intervals, residual variance near 1) is checked on its whole
// run in tests/html_report_jobs_test.cc (PaperJobInChromium), which fits
// it anyway.

// Multi-start from random points in the bounds: the fit reaches the truth
// (1e-3 relative on noise-free data) in at least 95 % of the seeds, i.e. in
// all 5 here. Each seed is a random initial point plus two random starts
// drawn by the fit (with one, 9 of 10 seeds reached the truth: not enough);
// the two lowest after the shorter horizons fit the whole record
// (solver.finalists). Over seeds 1–10 (commit a113df5) 10 of 10 reached it;
// larger rates are the optimum campaign's (scripts/optimum-campaign). The
// optimum check is off (probe_rounds: 0), so the starts alone are tested:
// 5 of 5 without it too (28 s alone instead of about 60 s with it).
TEST(FitTest, MultiStartReachesTheTruthFromRandomStarts) {
  const int kSeeds = 5;
  int reached = 0;
  RandomEngine rng(2024);
  for (int seed = 1; seed <= kSeeds; ++seed) {
    // A random initial point inside the bounds, log-uniform, and 2 more
    // random starts drawn by the fit itself.
    std::map<std::string, double> start;
    const std::map<std::string, std::pair<double, double>> bounds = {
        {"V_L", {0.5, 20}}, {"B_a", {10, 2000}}, {"b_g", {100, 20000}},
        {"k_g", {5e5, 5e7}}, {"T_p", {0.005, 1.0}}};
    for (const auto& [name, b] : bounds) {
      start[name] = std::exp(UniformReal(std::log(b.first), std::log(b.second), rng));
    }
    const FitResult r = Fit(PaperJob("_clean", start, /*starts=*/2, seed, 0.0,
                                     /*probe_rounds=*/0),
                            UncertaintySettings::Method::kGaussNewton);
    bool ok = true;
    for (const auto& [name, truth] : kTruth) {
      ok = ok && std::abs(Estimate(r, name).value / truth - 1.0) < 1e-3;
    }
    reached += ok;
  }
  RecordProperty("seeds_reaching_truth", std::to_string(reached) + "/" +
                                             std::to_string(kSeeds));
  std::cout << "multi-start reached the truth in " << reached << " of "
            << kSeeds << " seeds\n";
  EXPECT_GE(reached, static_cast<int>(std::ceil(0.95 * kSeeds)));
}

// The Jet Jacobian of one experiment's cost against central differences in
// θ (log parameters), at a point off the optimum, over the first 0.3 s of
// the 10 V step: the gear stays in contact (f_g > 0) and the preamp output
// is clamped, so the trajectory is smooth in the parameters. Records with
// many backlash contacts are checked in tests/switched_rk4_test.cc.
TEST(FitTest, CostJacobianMatchesCentralDifferences) {
  const FitJob job = LoadFitJob(PaperJob("_clean", Scaled(1.2, 0.9), 0, 1, 0.3));
  const std::vector<testing_files::ColumnCheck> checks =
      testing_files::CheckJobJacobian(job, 1e-6);
  double col_scale = 0.0;
  for (int k = 0; k < 5; ++k) {
    const double num = checks[k].error_norm * checks[k].error_norm;
    const double den = checks[k].difference_norm * checks[k].difference_norm;
    // Relative column error: central differences have O(h²) truncation and
    // O(ε/h) round-off (~1e-10 relative here); the initial backlash contact
    // crossed within ±h adds a little, so 1e-4 on the column norm. T_p has
    // no effect while the preamp is clamped: both columns are then ~0 and
    // are compared in absolute terms against the largest column.
    RecordProperty("column_" + job.free[k].name, std::to_string(std::sqrt(den)));
    if (k == 4) {
      EXPECT_LT(std::sqrt(num), 1e-6 * col_scale) << job.free[k].name;
    } else {
      EXPECT_LT(std::sqrt(num / den), 1e-4) << job.free[k].name;
    }
    col_scale = std::max(col_scale, std::sqrt(den));
  }
}

}  // namespace
}  // namespace axis
