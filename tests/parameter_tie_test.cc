// Tied parameters (job key `tie:`, estimation/parameter_tie.h): K_e takes
// K_tau's value in the fit's parameter map (values and derivatives), the
// loader refuses ties it cannot honour, and on a voltage drive's record
// the tied fit with R free is the same fit as K_tau and K_e free with R
// fixed: the records determine only K_tau/R and K_tau*K_e/R (MODEL.md §4),
// so the two optima map onto each other in closed form.
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>

#include <ceres/jet.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "estimation/experiment_cost.h"
#include "estimation/fit_result.h"
#include "estimation/parameter_tie.h"
#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "tests/test_files.h"
#include "tune/interval_ends.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;
const std::string kBin = BINARY_DIR;

FreeParameter Free(const std::string& name, double lower, double upper) {
  FreeParameter f;
  f.name = name;
  f.initial = lower;
  f.lower = lower;
  f.upper = upper;
  f.log = lower > 0.0;
  return f;
}

TEST(ParameterTieTest, ATiedParameterTakesItsSourcesValueAndDerivatives) {
  AxisParams<double> base;
  base.K_tau = 0.3;
  base.K_e = 0.9;
  const ParameterMap map(base, {Free("K_tau", 0.05, 2.0), Free("R", 0.1, 20.0)},
                         {{"K_e", "K_tau"}});
  EXPECT_EQ(map.base().K_e, 0.3);  // a fixed source's value at once
  using J = ceres::Jet<double, 4>;
  const J theta[2] = {J(std::log(0.4), 0), J(std::log(5.0), 1)};
  const AxisParams<J> p = map.Apply(theta);
  // K_tau = exp(θ_0): value 0.4, dK_tau/dθ_0 = 0.4; K_e the same, R alone.
  EXPECT_DOUBLE_EQ(p.K_e.a, 0.4);
  EXPECT_DOUBLE_EQ(p.K_e.v[0], 0.4);
  EXPECT_EQ(p.K_e.v[1], 0.0);
  EXPECT_DOUBLE_EQ(p.R.v[1], 5.0);
  const double plain[2] = {std::log(0.7), std::log(5.0)};
  EXPECT_DOUBLE_EQ(map.Apply(plain).K_e, 0.7);
  EXPECT_THROW(TieIndices({{"K_e", "K_nothing"}}), std::invalid_argument);
  EXPECT_EQ(TiedTo({{"K_e", "K_tau"}}, "K_e"), "K_tau");
  EXPECT_EQ(TiedTo({{"K_e", "K_tau"}}, "K_tau"), "");
}

// After the fit: a tied estimate carries its free source's initial value,
// errors and interval, and a model moved away from the estimate (the
// tuner's interval ends) keeps the tie; a parameter both free and tied is
// refused.
TEST(ParameterTieTest, TheTieHoldsAfterTheFitAndCannotBeFree) {
  FitResult result;
  ParameterEstimate kt;
  kt.name = "K_tau";
  kt.value = 0.4;
  kt.initial = 0.3;
  kt.free = true;
  kt.std_error = 0.01;
  kt.ci95_low = 0.38;
  kt.ci95_high = 0.42;
  kt.interval_method = "profile likelihood";
  ParameterEstimate ke;
  ke.name = "K_e";
  ke.value = 0.4;
  ke.initial = 0.4;
  ke.std_error = ke.ci95_low = ke.ci95_high = NAN;
  ke.tied_to = "K_tau";
  result.parameters = {kt, ke};
  result.free_names = {"K_tau"};
  CopyTiedUncertainty(&result);
  EXPECT_EQ(result.parameters[1].initial, 0.3);
  EXPECT_EQ(result.parameters[1].std_error, 0.01);
  EXPECT_EQ(result.parameters[1].ci95_high, 0.42);
  EXPECT_EQ(result.parameters[1].interval_method, "profile likelihood");
  AxisConfig model;
  model.params.K_tau = model.params.K_e = 0.4;
  const std::vector<IntervalEnd> ends = IntervalEnds(result, model, {});
  ASSERT_EQ(ends.size(), 2u);
  for (const IntervalEnd& end : ends) {
    EXPECT_EQ(end.model.params.K_e, end.model.params.K_tau);
    EXPECT_NE(end.model.params.K_e, 0.4);
  }
  EXPECT_THROW(ParameterMap(AxisParams<double>(), {Free("K_e", 0.1, 1.0)}, {{"K_e", "K_tau"}}),
               std::invalid_argument);
}

// A job of the X axis (one step record, the tachometer fitted) with `keys`
// (free:, tie:, set: ...) beside the model.
std::string XAxisJob(const std::string& keys) {
  return "model: " + kRoot + "/configs/axes/x_axis.yaml\n" + keys +
         "experiments:\n"
         "  - name: s\n"
         "    data: " + kRoot + "/testdata/x_step_10V.csv\n"
         "    channels: {u: u, tach: tach}\n"
         "    input: {column: u}\n"
         "    fit: {tach: 0.005}\n";
}

// The loader's message for the job with K_e free and `tie_block`, or "" if
// it loads.
std::string TieError(const std::string& tie_block) {
  const std::string job = testing_files::WriteTemp(
      "tie_job.yaml",
      XAxisJob("free:\n  K_e: {initial: 0.3, lower: 0.1, upper: 1}\n" + tie_block));
  try {
    LoadFitJob(job);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ParameterTieTest, TheLoaderRefusesTiesItCannotHonour) {
  EXPECT_EQ(TieError("tie: {K_tau: K_e}\n"), "");
  EXPECT_NE(TieError("tie: {K_e: K_tau}\n").find("key 'tie.K_e': expected a parameter that is "
                                                 "not free"),
            std::string::npos);
  EXPECT_NE(TieError("tie: {K_x: K_e}\n").find("key 'tie.K_x': expected a parameter name"),
            std::string::npos);
  EXPECT_NE(TieError("tie: {K_tau: K_x}\n").find("key 'tie.K_tau': expected the name of the "
                                                 "model parameter K_tau"),
            std::string::npos);
  EXPECT_NE(TieError("tie: {K_tau: K_tau}\n").find("expected another parameter"),
            std::string::npos);
  EXPECT_NE(TieError("tie: {K_tau: K_e, R: K_tau}\n").find("expected no chain of ties"),
            std::string::npos);
  EXPECT_NE(TieError("tie: [K_tau]\n").find("tie"), std::string::npos);
  // The job's model takes the tie at once: K_tau = K_e's model value.
  const std::string ok = testing_files::WriteTemp(
      "tie_ok.yaml", XAxisJob("set: {K_e: 0.5}\n"
                              "free:\n  B_a: {initial: 100, lower: 10, upper: 2000}\n"
                              "tie: {K_tau: K_e}\n"));
  const FitJob job = LoadFitJob(ok);
  EXPECT_EQ(job.problem.model.params.K_tau, 0.5);
  ASSERT_EQ(job.problem.ties.size(), 1u);
  EXPECT_EQ(job.problem.ties[0].source, "K_e");
}

nlohmann::json Parameter(const nlohmann::json& report, const std::string& name) {
  for (const nlohmann::json& p : report["parameters"]) {
    if (p["name"] == name) return p;
  }
  ADD_FAILURE() << "no parameter " << name;
  return nlohmann::json::object();
}

nlohmann::json FitReport(const std::string& dir, const std::string& name,
                         const std::string& job_text) {
  const std::string job = testing_files::WriteTemp(name + ".yaml", job_text);
  const std::string out = dir + name;
  const auto fitted = testing_files::RunCommand(kBin + "/fit-params", job + " --out " + out, true);
  EXPECT_EQ(fitted.exit_code, 0) << fitted.err;
  std::ifstream in(out + "/report.json");
  return nlohmann::json::parse(in);
}

// A DC motor on a voltage drive (truth K_tau = K_e = 0.4, R = 4 Ohm),
// a PRBS voltage with the drive switched off for a third of the record
// (the shaft then coasts on B_a alone, which separates B_a from the
// back-EMF's damping K_tau*K_e/R), the speed at 1 kHz with noise 0.01
// rad/s (fixed seed). Fitted (A) with K_tau, K_e, B_a free and R fixed at
// a wrong 5 Ohm, and (B) with K_e tied to K_tau and K_tau, R, B_a free.
TEST(ParameterTieTest, TiedWithRFreeIsTheSameFitAsTwoConstantsWithRFixed) {
  const std::string dir = testing_files::TestTempDir();
  const std::string model = testing_files::WriteTemp(
      "dc.yaml",
      "name: dc\nmotion: rotary\namplifier: voltage_drive\ncoupling: rigid\n"
      "parameters: {r_g: 1, J_m: 0.002, B_m: 0, K_tau: 0.4, K_e: 0.4, R: 4, M: 0.001, "
      "B_a: 0.003}\n");
  const std::string enable =
      "{type: table, interpolation: hold, points: [[0, 1], [1, 0], [1.5, 1], [2.5, 0], "
      "[3, 1], [3.5, 0]]}";
  const std::string experiment = testing_files::WriteTemp(
      "dc_prbs.yaml", "model: " + model +
                          "\nduration: 4.0\nstep: 1.0e-4\noutput_rate: 1000\n"
                          "channels: [u, v]\nnoise: {v: 0.01}\nseed: 11\n"
                          "input: {type: prbs, amplitude: 6, bit_time: 0.05, order: 9, seed: 5}\n"
                          "enable: " + enable + "\n");
  const std::string csv = dir + "dc.csv";
  const auto simulated = testing_files::RunCommand(kBin + "/simulate-axis",
                                                   experiment + " --out " + csv, true);
  ASSERT_EQ(simulated.exit_code, 0) << simulated.err;
  const std::string experiments =
      "experiments:\n"
      "  - name: prbs\n"
      "    data: " + csv + "\n"
      "    channels: {u: u, v: v}\n"
      "    input: {column: u, interpolation: hold}\n"
      "    enable: " + enable + "\n"
      "    fit: {v: 0.01}\n";
  const nlohmann::json a = FitReport(dir, "untied",
                                     "model: " + model + "\nset: {R: 5}\n"
                                     "free:\n"
                                     "  K_tau: {initial: 0.3, lower: 0.05, upper: 2}\n"
                                     "  K_e:   {initial: 0.3, lower: 0.05, upper: 2}\n"
                                     "  B_a:   {initial: 0.005, lower: 0.0001, upper: 0.1}\n" +
                                         experiments);
  const nlohmann::json b = FitReport(dir, "tied",
                                     "model: " + model + "\nset: {R: 5}\n"
                                     "free:\n"
                                     "  K_tau: {initial: 0.3, lower: 0.05, upper: 2}\n"
                                     "  R:     {initial: 5, lower: 0.5, upper: 50}\n"
                                     "  B_a:   {initial: 0.005, lower: 0.0001, upper: 0.1}\n"
                                     "tie: {K_e: K_tau}\n" +
                                         experiments);
  const double kt_a = Parameter(a, "K_tau")["value"], ke_a = Parameter(a, "K_e")["value"];
  const nlohmann::json kt_b = Parameter(b, "K_tau"), r_b = Parameter(b, "R");
  const nlohmann::json ke_b = Parameter(b, "K_e"), ba_b = Parameter(b, "B_a");
  const double se_kt = kt_b["std_error"], se_r = r_b["std_error"], se_ba = ba_b["std_error"];
  // Two minimisations of one function, each stopped by the solver's
  // relative function tolerance (1e-6 of a cost of about 2000 at the
  // default, a parameter within about 0.06 standard errors of the minimum):
  // the costs and the mapped estimates agree to 0.1 standard errors.
  const double cost_a = a["cost"]["final"], cost_b = b["cost"]["final"];
  EXPECT_NEAR(cost_a, cost_b, 1e-5 * cost_b);
  EXPECT_NEAR(kt_b["value"].get<double>(), ke_a, 0.1 * se_kt);          // k = K_e(A)
  EXPECT_NEAR(r_b["value"].get<double>(), 5.0 * ke_a / kt_a, 0.1 * se_r);  // R = 5·K_e/K_tau
  EXPECT_NEAR(ba_b["value"].get<double>(), Parameter(a, "B_a")["value"].get<double>(),
              0.1 * se_ba);
  // A's R, 1.25 times the truth, shows as K_tau ≠ K_e (K_tau·1.25 = 0.5 and
  // K_e = 0.4 in the limit); B finds
  // the truth within 3 standard errors and reports K_e as tied.
  EXPECT_GT(kt_a - ke_a, 10.0 * Parameter(a, "K_e")["std_error"].get<double>());
  EXPECT_NEAR(kt_b["value"].get<double>(), 0.4, 3.0 * se_kt);
  EXPECT_NEAR(r_b["value"].get<double>(), 4.0, 3.0 * se_r);
  EXPECT_EQ(ke_b["tied_to"], "K_tau");
  EXPECT_EQ(ke_b["value"], kt_b["value"]);
  EXPECT_EQ(ke_b["std_error"], kt_b["std_error"]);
  EXPECT_FALSE(ke_b["free"].get<bool>());
}

}  // namespace
}  // namespace axis
