// The EMPS controller reconstruction (MODEL.md §5, configs/axes/emps.yaml)
// checked on the real data: replaying the estimation run in closed loop with
// the published parameters reproduces the measured controller output and
// position about as well as the authors' own simulation does.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "common/statistics.h"
#include "discovery/discovery.h"
#include "estimation/evaluate_experiment.h"
#include "estimation/fit.h"
#include "estimation/fit_result.h"
#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "io/csv.h"
#include "sim/experiment.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;

TEST(EmpsReplayTest, PublishedModelReproducesTheMeasuredRun) {
  const ExperimentConfig e =
      LoadExperiment(kRoot + "/configs/experiments/emps_replay.yaml");
  const Trace<double> trace = RunExperiment(e);
  const CsvTable data = ReadCsv(kRoot + "/testdata/emps/DATA_EMPS.csv");
  ASSERT_EQ(trace.t.size(), data.num_rows());
  const double vir_error = RelativeErrorPercent(data.Column("vir_V"), trace[Channel::kU]);
  const double qm_error = RelativeErrorPercent(data.Column("qm_m"), trace[Channel::kX]);
  RecordProperty("vir_relative_error_percent", std::to_string(vir_error));
  RecordProperty("qm_relative_error_percent", std::to_string(qm_error));
  // The authors' simulation of the same model: 5.85 % (vir) and 0.0138 %
  // (qm). Measured here without controller delay (configs/axes/emps.yaml):
  // 5.14 % and 0.0012 %; with their one-sample delay 6.59 % and 0.0016 %.
  // Bounds: within 20 % of their vir figure, and below their qm figure.
  EXPECT_LT(vir_error, 1.2 * 5.85);
  EXPECT_LT(qm_error, 0.0138);
}

// configs/jobs/emps.yaml on the first 12 s of the estimation run (half the
// record, one discovery step and no validation runs, to keep the suite
// fast): starting from M and B_a only, the discovery loop's first addition
// is Coulomb friction, near the published 20.39 N, and M lands within 2 % of
// the published 95.11 kg.
// configs/jobs/emps.yaml with its paths made absolute, each experiment cut
// to [0, `seconds`] s, and `extra` YAML appended; written to `name` in the
// test's temporary folder and loaded.
FitJob ShortEmpsJob(double seconds, const std::string& name, const std::string& extra = "") {
  std::string text = axis::testing_files::JobTextWithAbsolutePaths("emps.yaml");
  const std::string window = "    window: [0, " + std::to_string(seconds) + "]\n";
  for (size_t at = 0; (at = text.find("    reference: {column: qg_m}", at)) != std::string::npos;) {
    text.insert(at, window);
    at += window.size() + 20;
  }
  const std::string path = axis::testing_files::TestTempDir() + name;
  std::ofstream(path) << text << extra;
  FitJob job = LoadFitJob(path);
  job.problem.solver.progress = false;
  return job;
}

TEST(EmpsJobTest, DiscoveryFindsCoulombFrictionOnAShortWindow) {
  FitJob job = ShortEmpsJob(12.0, "emps_short.yaml");
  ASSERT_NEAR(job.problem.experiments[0].t.back(), 12.0, 0.002);
  job.problem.validate.clear();
  job.discover.max_effects = 1;
  FitResult result = FitParameters(job.problem);
  const DiscoveryReport report = Discover(job.discover, &job.problem, &result, nullptr);
  ASSERT_FALSE(report.selected.empty()) << report.stop_reason;
  EXPECT_EQ(report.selected.front(), "coulomb");
  double f_c = 0.0, mass = 0.0;
  for (const ParameterEstimate& p : result.parameters) {
    if (p.name == "F_c") f_c = p.value;
    if (p.name == "M") mass = p.value;
  }
  RecordProperty("F_c", std::to_string(f_c));
  RecordProperty("M", std::to_string(mass));
  // Loose: a different estimator (closed-loop output error, with whatever
  // else the loop adds) from the published IDIM-LS figure.
  EXPECT_NEAR(f_c, 20.39, 0.25 * 20.39);
  EXPECT_NEAR(mass, 95.11, 0.02 * 95.11);
}

// The end point does not depend on the start (issue 17, reproducibility):
// the EMPS model's controller sees the position unquantised
// (configs/axes/emps.yaml), so the cost is smooth and M, B_a and the Coulomb
// friction fitted on 8 s of the estimation run from two starts far apart
// end at the same point, to 0.05 standard errors, on a convergence test of
// the cost or the gradient. With the rig's 5e-8 m quantum in the controller
// the cost is piecewise constant: the same two starts stop on the step size
// (the trust region collapsed) at points that differ by more than that, and
// the report says why (FitResult::stop_note).
TEST(EmpsJobTest, EndPointDoesNotDependOnTheStart) {
  const std::string coulomb = "effects:\n  coulomb: {F_c: 15}\n";
  const auto fit_from = [&](double mass, double b_a, const std::string& extra,
                            const std::string& name) {
    FitJob job = ShortEmpsJob(8.0, name, coulomb + extra);
    job.problem.validate.clear();
    job.problem.free[0].initial = mass;
    job.problem.free[1].initial = b_a;
    FreeParameter f_c;
    f_c.name = "F_c";
    f_c.unit = "N";
    f_c.initial = 15;
    f_c.lower = 0.1;
    f_c.upper = 200;
    f_c.log = true;  // as the loader sets it for a positive lower bound (run/load_fit_job.cc)
    job.problem.free.push_back(f_c);
    return FitParameters(job.problem);
  };
  const auto largest_difference_in_se = [](const FitResult& a, const FitResult& b) {
    double largest = 0.0;
    for (size_t k = 0; k < a.parameters.size(); ++k) {
      if (!a.parameters[k].free) continue;
      largest = std::max(largest, std::abs(a.parameters[k].value - b.parameters[k].value) /
                                      a.parameters[k].std_error);
    }
    return largest;
  };
  const FitResult a = fit_from(80, 150, "", "emps_start_a.yaml");
  const FitResult b = fit_from(110, 250, "", "emps_start_b.yaml");
  RecordProperty("smooth_difference_se", std::to_string(largest_difference_in_se(a, b)));
  EXPECT_LT(largest_difference_in_se(a, b), 0.05);
  for (const FitResult* r : {&a, &b}) {
    EXPECT_EQ(r->termination.rfind("Parameter tolerance", 0), std::string::npos) << r->termination;
    EXPECT_TRUE(r->stop_note.empty()) << r->stop_note;
  }
  const std::string quantised = "controller: {load_quantum: 5.0e-8}\n";
  const FitResult qa = fit_from(80, 150, quantised, "emps_quantised_a.yaml");
  const FitResult qb = fit_from(110, 250, quantised, "emps_quantised_b.yaml");
  RecordProperty("quantised_difference_se", std::to_string(largest_difference_in_se(qa, qb)));
  // Measured here: 6e-10 standard errors apart unquantised, 0.23 quantised,
  // where both stopped on the step size.
  int step_stops = 0;
  for (const FitResult* r : {&qa, &qb}) {
    if (r->termination.rfind("Parameter tolerance", 0) != 0) continue;
    ++step_stops;
    EXPECT_NE(r->stop_note.find("controller.load_quantum: quantum 5e-08 m"), std::string::npos)
        << r->stop_note;
  }
  EXPECT_GT(step_stops, 0) << qa.termination << " | " << qb.termination;
}

std::string Scientific(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

// The EMPS jobs integrate at the 1 ms sample period (configs/jobs/emps.yaml).
// Against a tenth of it, with the model the discovery loop selects on the
// whole estimation run (README, Real data: EMPS; the stiffest friction it
// has: Coulomb and Stribeck through tanh(v/v_eps)), the closed-loop run's
// simulated vir and qm and the open-loop pulse run's qm (the benchmark
// protocol) must agree to 1 % of the job's σ (0.1 V, 5e-6 m), and to 1 µm
// open loop (0.03 % of the benchmark errors of 3–10 mm). Measured: vir
// 3.5e-6 V, qm 6.6e-11 m closed loop; qm about 1e-7 m open loop.
TEST(EmpsReplayTest, OneMillisecondStepMatchesATenthOfIt) {
  const std::string discovered =
      "effects:\n"
      "  coulomb: {F_c: 22.2413}\n"
      "  viscous_asymmetry: {Delta_B: 71.8815}\n"
      "  stribeck: {F_st: 16.9473, v_st: 0.0246353}\n"
      "  spring: {k_x: 4.77967, x_0: 0}\n"
      "  load_offset: {F_0: -0.922012}\n"
      "set: {M: 95.2286, B_a: 150.614}\n";
  const FitJob job = ShortEmpsJob(24.84, "emps_steps.yaml", discovered);
  ASSERT_EQ(job.problem.experiments[0].options.step, 1e-3);
  const auto rms_difference = [&](const FitExperiment& e, const std::string& channel) {
    FitExperiment fine = e;
    fine.options.step = 1e-4;
    const ExperimentFit a = EvaluateExperiment(job.problem.model.structure, job.problem.model.params, e);
    const ExperimentFit b = EvaluateExperiment(job.problem.model.structure, job.problem.model.params, fine);
    for (size_t c = 0; c < a.channels.size(); ++c) {
      if (a.channels[c].channel == channel) {
        return Rms(b.channels[c].simulated, a.channels[c].simulated);
      }
    }
    ADD_FAILURE() << e.name << " has no channel " << channel;
    return 0.0;
  };
  const FitExperiment* open_loop = nullptr;
  for (const FitExperiment& e : job.problem.validate) {
    if (e.name == "emps_pulses_open_loop") open_loop = &e;
  }
  ASSERT_NE(open_loop, nullptr);
  const double vir = rms_difference(job.problem.experiments[0], "u");
  const double qm = rms_difference(job.problem.experiments[0], "x");
  const double qm_open = rms_difference(*open_loop, "x");
  RecordProperty("vir_rms_difference_V", Scientific(vir));
  RecordProperty("qm_rms_difference_m", Scientific(qm));
  RecordProperty("qm_open_loop_rms_difference_m", Scientific(qm_open));
  EXPECT_LT(vir, 0.01 * 0.1);
  EXPECT_LT(qm, 0.01 * 5e-6);
  EXPECT_LT(qm_open, 1e-6);
}

}  // namespace
}  // namespace axis
