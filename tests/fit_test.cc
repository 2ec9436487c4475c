// fit-params on synthetic ground truth (testdata/, truth = MODEL.md §2):
// recovery from factor-2 starts on noise-free data, coverage of the
// uncertainty on noisy data, multi-start from random points, and the
// autodiff Jacobian of the cost against central differences, and the
// random starts a fit adds when its own start ends far above the noise.
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "estimation/current_loop_check.h"
#include "estimation/fit.h"
#include "estimation/fit_result.h"
#include "estimation/internal/start_agreement.h"
#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "estimation/solver_settings.h"
#include "run/job_run.h"
#include "sim/experiment.h"
#include "sim/random.h"
#include "tests/cost_checks.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;
const std::map<std::string, double> kTruth = {
    {"V_L", 2.7}, {"B_a", 200.0}, {"b_g", 1500.0}, {"k_g", 5.0e6}, {"T_p", 0.04}};

// The noise-free trace of testdata/generate/quasi_steady/<name>.yaml (the
// paper job's fitting model: quasi-steady current loop at 100 µs), written
// once per test directory; returns its path.
std::string QuasiSteadyRecord(const std::string& name) {
  const std::string csv = testing_files::TestTempDir() + "quasi_steady_" + name + ".csv";
  static std::map<std::string, bool> written;
  if (!written[csv]) {
    const ExperimentConfig g =
        LoadExperiment(kRoot + "/testdata/generate/quasi_steady/" + name + ".yaml");
    SimulateAxisOptions options;
    options.no_noise = true;
    WriteTraceCsv(csv, SimulateExperiment(g, options), g.options.channels);
    written[csv] = true;
  }
  return csv;
}

// The paper job (configs/jobs/x_axis_paper.yaml) on `suffix` data ("" noisy,
// "_clean" noise-free, both from the full current loop at 10 µs, fitted with
// it; "quasi_steady": the noise-free QuasiSteadyRecord, fitted with the
// quasi-steady loop at 100 µs as the paper job does), with the given initial
// values.
std::string PaperJob(const std::string& suffix,
                     const std::map<std::string, double>& initial,
                     int starts = 0, int seed = 1, double window = 0.0,
                     int probe_rounds = 8) {
  const bool quasi_steady = suffix == "quasi_steady";
  std::ostringstream y;
  y << "model: " << kRoot << "/configs/axes/x_axis.yaml\n";
  if (quasi_steady) {
    y << "configuration: {current_loop: quasi_steady}\n"
      << "simulation: {step: 1.0e-4}\n";
  }
  y << "free:\n"
    << "  V_L: {initial: " << initial.at("V_L") << ", lower: 0.5, upper: 20}\n"
    << "  B_a: {initial: " << initial.at("B_a") << ", lower: 10, upper: 2000}\n"
    << "  b_g: {initial: " << initial.at("b_g") << ", lower: 100, upper: 20000}\n"
    << "  k_g: {initial: " << initial.at("k_g") << ", lower: 5.0e5, upper: 5.0e7}\n"
    << "  T_p: {initial: " << initial.at("T_p") << ", lower: 0.005, upper: 1.0}\n"
    << "experiments:\n";
  for (const char* name : {"x_step_10V", "x_step_4V"}) {
    const std::string data = quasi_steady ? QuasiSteadyRecord(name)
                                          : kRoot + "/testdata/" + name + suffix + ".csv";
    y << "  - name: " << name << "\n"
      << "    data: " << data << "\n"
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
  job.problem.solver.progress = false;
  job.problem.uncertainty.method = method;
  return FitParameters(job.problem);
}

// Noise-free data from the fitting model itself (the paper job's
// quasi-steady current loop at 100 µs): the truth is the exact minimum (up
// to the RK4 error, which is identical in data and model because both use
// the same grid), so
// the estimates must reach it to the solver's tolerance; 1e-4 relative is
// the requirement. Every parameter starts a factor of 2 off,
// alternating direction, both ways, with two random starts drawn by the fit
// (on the full loop's trace at 10 µs a single run from the second start
// ended in a T_p local minimum near 0.018 s; on this model a single run
// reaches the truth from both). The optimum check (solver.probe_rounds) is
// off: the starts alone must reach it.
TEST(FitTest, NoiseFreeRecoveryFromFactorTwoAboveAndBelow) {
  for (const auto& start : {Scaled(2.0, 0.5), Scaled(0.5, 2.0)}) {
    const FitResult r = Fit(PaperJob("quasi_steady", start, /*starts=*/2, 1, 0.0,
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

// Multi-start from random points in the bounds, on the paper job's fitting
// model (quasi-steady current loop at 100 µs) and its noise-free trace: the
// fit as a user runs it (two random starts drawn by the fit, the two lowest
// after the shorter horizons fitting the whole record, solver.finalists,
// then the optimum check at its default 8 probe rounds) reaches the truth
// (1e-3 relative) in at least 95 % of the seeds, i.e. in all 5 here. The
// starts alone (probe_rounds: 0) reach it in 8 of 10 seeds: seeds 3 and 8
// end in a local minimum with b_g at its upper bound (20000 N*s/m, k_g
// 1.7e6 N/m, cost 5.5e5 against 0), which the optimum check's probes leave.
// Larger rates are the optimum campaign's (scripts/optimum-campaign).
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
    const FitResult r = Fit(PaperJob("quasi_steady", start, /*starts=*/2, seed),
                            UncertaintySettings::Method::kGaussNewton);
    bool ok = true;
    for (const auto& [name, truth] : kTruth) {
      ok = ok && std::abs(Estimate(r, name).value / truth - 1.0) < 1e-3;
    }
    reached += ok;
    if (!ok) {
      std::cout << "seed " << seed << " final cost " << r.final_cost;
      for (const auto& [name, truth] : kTruth) {
        std::cout << " " << name << "=" << Estimate(r, name).value;
      }
      std::cout << "\n";
    }
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
    RecordProperty("column_" + job.problem.free[k].name, std::to_string(std::sqrt(den)));
    if (k == 4) {
      EXPECT_LT(std::sqrt(num), 1e-6 * col_scale) << job.problem.free[k].name;
    } else {
      EXPECT_LT(std::sqrt(num / den), 1e-4) << job.problem.free[k].name;
    }
    col_scale = std::max(col_scale, std::sqrt(den));
  }
}

// The paper's five unknowns free, each started at the paper's value (the X
// axis's truth, MODEL.md §2) within the paper job's bounds: a job's `free:`
// block for records of an axis with other values.
const char* const kPaperFreeFromTruth =
    "free:\n"
    "  V_L: {initial: 2.7, lower: 0.5, upper: 20}\n"
    "  B_a: {initial: 200, lower: 10, upper: 2000}\n"
    "  b_g: {initial: 1500, lower: 100, upper: 20000}\n"
    "  k_g: {initial: 5.0e6, lower: 5.0e5, upper: 5.0e7}\n"
    "  T_p: {initial: 0.04, lower: 0.005, upper: 1.0}\n";

// On data the job's values do not describe, the continuation from the job's
// start can end in a wrong minimum; fit-params then adds random starts
// (solver.auto_starts) and says so. The record
// (testdata/generate/starts/x_step_6V_other_axis.yaml, simulated here with
// the model the job fits, the quasi-steady current loop at 100 µs, noise
// seed fixed) is one +6 V step of an X axis with other values, fitted from
// the paper's values. Without added starts the fit ends at s² ≈ 96 (T_p
// 0.017 s for 0.07) and the report warns; with the default 8, every one a
// finalist, it ends at the noise: s² within 5 SD of 1 (SD √(2/(m − n)) =
// 0.026 for m = 3002 residuals) and every estimate within 4 standard
// errors of the truth (the model is the generating one: a miss has
// probability 6e-5 per parameter at the right minimum).
TEST(FitTest, AStartFarAboveTheNoiseAddsRandomStarts) {
  ExperimentConfig generator =
      LoadExperiment(kRoot + "/testdata/generate/starts/x_step_6V_other_axis.yaml");
  const std::string csv = testing_files::TestTempDir() + "step_6V.csv";
  WriteTraceCsv(csv, SimulateExperiment(generator, SimulateAxisOptions{}),
                generator.options.channels);
  const auto job_text = [&](int auto_starts) {
    std::ostringstream y;
    y << "model: " << kRoot << "/configs/axes/x_axis.yaml\n"
      << "configuration: {current_loop: quasi_steady}\n"
      << "simulation: {step: 1.0e-4}\n"
      << kPaperFreeFromTruth
      << "experiments:\n"
      << "  - name: step_6V\n"
      << "    data: " << csv << "\n"
      << "    channels: {u: u, a: a, tach: tach, i: i}\n"
      << "    input: {column: u}\n"
      << "    fit: {a: 0.02, tach: 0.005}\n"
      << "solver: {probe_rounds: 0, auto_starts: " << auto_starts << "}\n"
      << "uncertainty: {method: gauss_newton}\n";
    const FitJob job = ParseFitJob(YAML::Load(y.str()), "auto_starts.yaml",
                                   testing_files::TestTempDir());
    return FitParameters(job.problem, nullptr);
  };
  const FitResult alone = job_text(0);
  EXPECT_GT(alone.residual_variance, kAutoStartsAbove);
  EXPECT_NE(alone.residual_note, "");
  EXPECT_EQ(alone.auto_starts_note, "");

  const FitResult r = job_text(8);
  RecordProperty("s2_alone", std::to_string(alone.residual_variance));
  RecordProperty("s2_with_starts", std::to_string(r.residual_variance));
  EXPECT_NE(r.auto_starts_note, "");
  EXPECT_EQ(r.residual_note, "") << r.auto_starts_note;
  EXPECT_NEAR(r.residual_variance, 1.0, 5.0 * std::sqrt(2.0 / (r.num_residuals - 5)));
  const std::map<std::string, double> truth = {
      {"V_L", 1.8}, {"B_a", 320}, {"b_g", 2600}, {"k_g", 2.8e6}, {"T_p", 0.07}};
  for (const auto& [name, value] : truth) {
    const ParameterEstimate& e = Estimate(r, name);
    EXPECT_NEAR(e.value, value, 4.0 * e.std_error) << name;
  }
}

// Issue 42: a misfit of the model is not a wrong minimum. The records
// (testdata/generate/misfit/: a ±6 V square wave and a 5 V sweep of the X
// axis with the paper's values, the accelerometer sampled at the instant;
// noise seeds fixed) fitted with x_axis.yaml, which assumes the period mean,
// from the paper job's factor-2 start: the job's start ends far above the
// noise (s² ≈ 15), and the first kMisfitProbeStarts random starts land at
// its cost (or join its path), so the other five do not run and the note
// says the misfit is the model's. The estimate is the job-start-alone fit's
// or a probe's at most SameMinimumTolerance lower (never higher: 1e-9
// relative, the solver's round-off).
TEST(FitTest, AMisfitOfTheModelStopsAfterTheFirstRandomStarts) {
  std::ostringstream experiments;
  for (const std::string name : {"x_square_6V_instant", "x_sweep_5V_instant"}) {
    ExperimentConfig g = LoadExperiment(kRoot + "/testdata/generate/misfit/" + name + ".yaml");
    const std::string csv = testing_files::TestTempDir() + name + ".csv";
    WriteTraceCsv(csv, SimulateExperiment(g, SimulateAxisOptions{}), g.options.channels);
    experiments << "  - name: " << name << "\n    data: " << csv
                << "\n    channels: {u: u, a: a, tach: tach, i: i}\n"
                << "    input: {column: u" << (name.find("square") != std::string::npos ? ", interpolation: hold" : "")
                << "}\n    fit: {a: 0.02, tach: 0.005}\n";
  }
  const auto fit = [&](int auto_starts) {
    std::ostringstream y;
    y << "model: " << kRoot << "/configs/axes/x_axis.yaml\n"
      << "configuration: {current_loop: quasi_steady}\n"
      << "simulation: {step: 1.0e-4}\n"
      << "free:\n"
      << "  V_L: {initial: 5.4, lower: 0.5, upper: 20}\n"
      << "  B_a: {initial: 100, lower: 10, upper: 2000}\n"
      << "  b_g: {initial: 3000, lower: 100, upper: 20000}\n"
      << "  k_g: {initial: 2.5e6, lower: 5.0e5, upper: 5.0e7}\n"
      << "  T_p: {initial: 0.08, lower: 0.005, upper: 1.0}\n"
      << "experiments:\n" << experiments.str()
      << "solver: {probe_rounds: 0, auto_starts: " << auto_starts << "}\n"
      << "uncertainty: {method: gauss_newton}\n";
    const FitJob job =
        ParseFitJob(YAML::Load(y.str()), "misfit.yaml", testing_files::TestTempDir());
    return FitParameters(job.problem, nullptr);
  };
  const FitResult alone = fit(0);
  const FitResult r = fit(8);
  RecordProperty("s2", std::to_string(r.residual_variance));
  EXPECT_GT(alone.residual_variance, kAutoStartsAbove);
  EXPECT_NE(r.auto_starts_note.find("the misfit is the model's"), std::string::npos)
      << r.auto_starts_note;
  // The job's start and the probes only.
  EXPECT_EQ(r.start_costs.size(), 1u + kMisfitProbeStarts);
  EXPECT_LE(r.final_cost, alone.final_cost * (1.0 + 1e-9));
  EXPECT_GE(r.final_cost,
            alone.final_cost - SameMinimumTolerance(alone.residual_variance, 0.0));
  // Structured residuals at s² > 2: the intervals are conditional on the
  // model, and the sandwich standard errors are given.
  EXPECT_NE(r.misspecification_note.find("conditional on the model"), std::string::npos);
  for (const ParameterEstimate& e : r.parameters) {
    if (!e.free) continue;
    EXPECT_TRUE(std::isfinite(e.std_error_sandwich) && e.std_error_sandwich > 0.0) << e.name;
  }
}

// The quasi-steady current loop's cost on records it was not measured on:
// the Z axis with other values (testdata/generate/current_loop/, simulated
// here through the full loop at 10 µs, noise seeds fixed), fitted with the
// quasi-steady loop at 100 µs from the X axis's values. The check
// (estimation/current_loop_check.h) finds a shift of more than one standard error;
// with full_loop_refit_above: .inf the fit stays quasi-steady and says so
// in its note, with the default 1 it is refitted with the full loop. The
// check's shifts are the first-order difference of the two fits; they
// agree within a tenth of a standard error plus 25 % (second-order terms:
// on the paper job 0.562 predicted against 0.60 measured, 0.521 against
// 0.57). The full loop's estimate holds the truth within 4 standard errors
// (a miss has probability 6e-5 per parameter), where the quasi-steady
// one's largest error is printed.
TEST(FitTest, QuasiSteadyShiftPastOneStandardErrorRefitsTheFullLoop) {
  std::ostringstream experiments;
  for (const std::string name : {"z_sine", "z_step_m5"}) {
    ExperimentConfig g =
        LoadExperiment(kRoot + "/testdata/generate/current_loop/" + name + ".yaml");
    const std::string csv = testing_files::TestTempDir() + name + ".csv";
    WriteTraceCsv(csv, SimulateExperiment(g, SimulateAxisOptions{}), g.options.channels);
    experiments << "  - name: " << name << "\n    data: " << csv
                << "\n    channels: {u: u, a: a, tach: tach, i: i}\n    input: {column: u}\n"
                << "    fit: {a: 0.02, tach: 0.005}\n";
  }
  const auto run = [&](const std::string& refit_above) {
    std::ostringstream y;
    y << "model: " << kRoot << "/configs/axes/z_axis.yaml\n"
      << "configuration: {current_loop: quasi_steady}\n"
      << "simulation: {step: 1.0e-4, full_loop_refit_above: " << refit_above << "}\n"
      << kPaperFreeFromTruth
      << "experiments:\n" << experiments.str()
      << "solver: {probe_rounds: 0}\n"
      << "uncertainty: {method: gauss_newton}\n";
    FitJob job = ParseFitJob(YAML::Load(y.str()), "current_loop.yaml",
                             testing_files::TestTempDir());
    job.problem.solver.progress = false;
    std::ostringstream out;
    return RunJob(job, false, out);
  };
  const std::map<std::string, double> truth = {
      {"V_L", 2.2}, {"B_a", 180}, {"b_g", 3000}, {"k_g", 1.5e6}, {"T_p", 0.12}};
  const JobRun quasi = run(".inf");
  ASSERT_TRUE(quasi.loop_check.ran);
  EXPECT_FALSE(quasi.loop_check.refitted);
  EXPECT_GT(quasi.loop_check.largest, 1.0);
  EXPECT_NE(quasi.result.model_note.find("quasi-steady current loop shifts the estimate"),
            std::string::npos)
      << quasi.result.model_note;
  EXPECT_EQ(quasi.job.problem.model.structure.current_loop, CurrentLoop::kQuasiSteady);

  const JobRun full = run("1");
  EXPECT_TRUE(full.loop_check.refitted);
  EXPECT_EQ(full.job.problem.model.structure.current_loop, CurrentLoop::kFull);
  EXPECT_NE(full.result.model_note.find("refitted"), std::string::npos) << full.result.model_note;
  double quasi_worst = 0.0;
  for (size_t k = 0; k < quasi.loop_check.names.size(); ++k) {
    const std::string& name = quasi.loop_check.names[k];
    const ParameterEstimate& q = Estimate(quasi.result, name);
    const ParameterEstimate& f = Estimate(full.result, name);
    const double predicted = quasi.loop_check.shift_in_se[k];
    const double measured = (q.value - f.value) / q.std_error;
    EXPECT_NEAR(measured, predicted, 0.1 + 0.25 * std::abs(predicted)) << name;
    EXPECT_NEAR(f.value, truth.at(name), 4.0 * f.std_error) << name;
    quasi_worst = std::max(quasi_worst, std::abs(q.value - truth.at(name)) / q.std_error);
    RecordProperty(name + "_shift_predicted", std::to_string(predicted));
    RecordProperty(name + "_shift_measured", std::to_string(measured));
  }
  std::cout << "quasi-steady estimate's largest error " << quasi_worst
            << " standard errors; the check's largest shift " << quasi.loop_check.largest << "\n";
}

// The full loop's step (estimation/current_loop_check.h WithFullLoop): 10 µs on
// the paper job's 1 kHz records (its step 100 µs in 10); on a 3 kHz record
// fitted at 1/9000 s the largest whole fraction of that step at most 10 µs
// (12 of them: 1/108000 s, 36 per sample); refused, naming the
// limit, where the full loop is stable only below a microsecond (L = 0.1 mH:
// its eigenvalue −3.3·10⁶ 1/s, the limit 0.83 µs), where the check used to
// report a shift of 107 standard errors from an unstable integration.
TEST(FitTest, FullLoopStepDividesTheSamplePeriodAndStaysStable) {
  const std::string path = testing_files::WriteTemp(
      "paper.yaml", testing_files::JobTextWithAbsolutePaths("x_axis_paper.yaml"));
  FitJob job = LoadFitJob(path);
  double step = 0.0;
  const EstimationProblem full = WithFullLoop(job.problem, &step);
  EXPECT_EQ(full.model.structure.current_loop, CurrentLoop::kFull);
  EXPECT_NEAR(step, 1e-5, 1e-12);
  for (const FitExperiment& e : full.validate) EXPECT_NEAR(e.options.step, 1e-5, 1e-12);
  job.problem.experiments[0].options.output_period = 1.0 / 3000.0;
  job.problem.experiments[0].options.step = 1.0 / 9000.0;
  const EstimationProblem fast = WithFullLoop(job.problem, &step);
  EXPECT_NEAR(fast.experiments[0].options.step, 1.0 / 108000.0, 1e-15);
  EXPECT_NEAR(step, 1.0 / 108000.0, 1e-15);
  job.problem.model.params.L = 1e-4;
  try {
    WithFullLoop(job.problem);
    ADD_FAILURE() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("stable here only below an RK4 step of 8.3"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace axis
