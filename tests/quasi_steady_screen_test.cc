// The quasi-steady screen of a full-loop job (estimation/quasi_steady_screen.h,
// run/job_run.h RunJob): the screen's model and steps, the declared steps
// restored, and a whole run against the same job fitted with the full loop
// throughout (simulation.quasi_steady_screen: off).
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "estimation/quasi_steady_screen.h"
#include "run/job_run.h"
#include "run/load_fit_job.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;

// Two of the paper's unknowns from the first 0.3 s of the noisy 10 V step
// (testdata/x_step_10V.csv, 1 kHz; truth V_L = 2.7 V, B_a = 200 N·s/m) with
// the shipped model as it is: the full current loop, no step set (10 µs from
// the model, sim/auto_step.h). `simulation` is the job's `simulation:`
// block, or empty.
std::string ShippedJob(const std::string& name, const std::string& simulation) {
  const std::string path = testing_files::TestTempDir() + "screen_" + name + ".yaml";
  std::ofstream(path) << "title: screen\n"
                      << "model: " << kRoot << "/configs/axes/x_axis.yaml\n"
                      << "free:\n"
                      << "  V_L: {initial: 3.5, lower: 0.5, upper: 20}\n"
                      << "  B_a: {initial: 150, lower: 10, upper: 2000}\n"
                      << "experiments:\n"
                      << "  - name: step\n"
                      << "    data: " << kRoot << "/testdata/x_step_10V.csv\n"
                      << "    window: [0, 0.3]\n"
                      << "    channels: {u: u, a: a, tach: tach}\n"
                      << "    input: {column: u}\n"
                      << "    fit: {a: 0.02, tach: 0.005}\n"
                      << "solver: {threads: 1}\n"
                      << (simulation.empty() ? "" : "simulation: " + simulation + "\n");
  return path;
}

TEST(QuasiSteadyScreenTest, TheScreenIsTheQuasiSteadyLoopAtItsOwnCoarserStep) {
  const FitJob job = LoadFitJob(ShippedJob("model", ""));
  ASSERT_TRUE(HasQuasiSteadyScreen(job.problem));
  const double declared = job.problem.experiments[0].options.step;
  EXPECT_NEAR(declared, 1e-5, 1e-12);  // the full loop's automatic step
  const EstimationProblem screen = QuasiSteadyScreen(job.problem);
  EXPECT_EQ(screen.model.structure.current_loop, CurrentLoop::kQuasiSteady);
  EXPECT_FALSE(HasQuasiSteadyScreen(screen));
  const FitExperiment& e = screen.experiments[0];
  // The quasi-steady model is stable to about 139 µs on the X axis: the
  // automatic rule's step (at most 0.52 of that) is 50 µs, the largest round
  // step at most 0.9 of it that divides the 1 ms sample period and T_s =
  // 5 ms is 100 µs, taken because its traces at the start differ from the
  // full loop's about as little (the approximation's own error, measured at
  // most 0.022 σ at 100 µs on the paper's steps, tests/axis_model_test.cc).
  EXPECT_NEAR(e.options.step, 1e-4, 1e-15);
  const double per_sample = e.options.output_period / e.options.step;
  EXPECT_NEAR(per_sample, std::round(per_sample), 1e-9);
  const double per_control = job.problem.model.controller.T_s / e.options.step;
  EXPECT_NEAR(per_control, std::round(per_control), 1e-9);
  EXPECT_EQ(e.options.output_period, job.problem.experiments[0].options.output_period);
  EXPECT_EQ(e.options.duration, job.problem.experiments[0].options.duration);
  EXPECT_EQ(e.t, job.problem.experiments[0].t);

  EstimationProblem full = screen;
  full.model.structure.current_loop = CurrentLoop::kFull;
  EXPECT_DOUBLE_EQ(TakeFinerSteps(job.problem, &full), declared);
  EXPECT_DOUBLE_EQ(full.experiments[0].options.step, declared);
  EXPECT_DOUBLE_EQ(SmallestStep(screen), e.options.step);
}

TEST(QuasiSteadyScreenTest, AnUnknownScreenValueIsRefusedNamingTheKey) {
  try {
    LoadFitJob(ShippedJob("bad", "{quasi_steady_screen: sometimes}"));
    FAIL() << "expected the job to be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("simulation.quasi_steady_screen"), std::string::npos)
        << e.what();
  }
}

TEST(QuasiSteadyScreenTest, ModelsWithoutTheFullCurrentLoopHaveNoScreen) {
  FitJob job = LoadFitJob(ShippedJob("qs", ""));
  job.problem.model.structure.current_loop = CurrentLoop::kQuasiSteady;
  EXPECT_FALSE(HasQuasiSteadyScreen(job.problem));
  EXPECT_THROW(QuasiSteadyScreen(job.problem), std::invalid_argument);
  const FitJob emps = LoadFitJob(kRoot + "/configs/jobs/emps.yaml");  // a force source
  EXPECT_FALSE(HasQuasiSteadyScreen(emps.problem));
}

// The screened run reports the declared model: the full loop at the job's
// 10 µs step, refitted from the screen's estimate. Its values agree with the
// run on the full loop throughout to within 0.1 standard errors: the refit
// stops once a step would move the estimate by less than 0.05 standard
// errors (estimation/full_loop_refit.h kFullLoopRefitStepSe), and the
// unscreened fit ends well inside that at the solver's function tolerance;
// measured 1e-4 standard errors on V_L and B_a, interval widths within
// 0.07 %.
TEST(QuasiSteadyScreenTest, AScreenedRunReportsTheFullLoopAsAFullLoopFitDoes) {
  std::ostringstream discarded;
  const JobRun screened = RunJob(LoadFitJob(ShippedJob("auto", "")), false, discarded);
  const JobRun full =
      RunJob(LoadFitJob(ShippedJob("off", "{quasi_steady_screen: off}")), false, discarded);
  EXPECT_EQ(screened.job.problem.model.structure.current_loop, CurrentLoop::kFull);
  EXPECT_NEAR(screened.job.problem.experiments[0].options.step, 1e-5, 1e-12);
  EXPECT_TRUE(screened.loop_check.ran);
  EXPECT_TRUE(screened.loop_check.refitted);
  EXPECT_NE(screened.result.model_note.find("quasi_steady_screen: auto"), std::string::npos);
  EXPECT_FALSE(full.loop_check.ran);
  EXPECT_EQ(full.job.problem.model.structure.current_loop, CurrentLoop::kFull);
  ASSERT_EQ(screened.result.parameters.size(), full.result.parameters.size());
  for (size_t k = 0; k < full.result.parameters.size(); ++k) {
    const ParameterEstimate& a = screened.result.parameters[k];
    const ParameterEstimate& b = full.result.parameters[k];
    ASSERT_EQ(a.name, b.name);
    if (!b.free) continue;
    ASSERT_GT(b.std_error, 0.0) << b.name;
    EXPECT_LE(std::abs(a.value - b.value), 0.1 * b.std_error) << b.name;
    // The carried intervals' widths against the full loop's own profile
    // intervals: the two models' curvatures differ by the approximation's
    // share, within 2 % on the paper's steps (configs/jobs/x_axis_paper.yaml).
    const double carried = a.ci95_high - a.ci95_low;
    const double own = b.ci95_high - b.ci95_low;
    EXPECT_NEAR(carried / own, 1.0, 0.02) << b.name;
  }
}

}  // namespace
}  // namespace axis
