// A hand-built FitResult for the report writers' tests (tests/report_test.cc,
// tests/html_report_test.cc).
#ifndef TESTS_FIT_RESULT_FIXTURE_H_
#define TESTS_FIT_RESULT_FIXTURE_H_

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "estimation/fit_result.h"

namespace axis {
namespace fixture {

// A channel whose measured trace is gain·sin(5t) plus a small ripple and
// whose simulated one is shifted by 0.01 rad; fixed statistics.
inline ChannelFit MakeChannel(const std::string& name, const std::string& unit,
                              bool fitted, const std::vector<double>& t, double gain) {
  ChannelFit c;
  c.channel = name;
  c.unit = unit;
  c.fitted = fitted;
  c.sigma = fitted ? 0.01 : 0.0;
  for (double s : t) {
    c.measured.push_back(gain * std::sin(5.0 * s) + 0.001 * std::cos(97.0 * s));
    c.simulated.push_back(gain * std::sin(5.0 * s + 0.01));
  }
  c.rms = 0.012;
  c.fit_percent = 98.5;
  c.max_error = 0.03;
  c.relative_error_percent = 1.5;
  c.ljung_box_q = 42.0;
  c.ljung_box_lags = 20;
  c.ljung_box_p = 0.0025;
  c.input_xcorr_peak = -0.31;
  c.input_xcorr_lag = 2;
  return c;
}

// Two free parameters (one not determined), one fixed; a fitted experiment
// with two channels (`samples` samples 5 ms apart) and a validation
// experiment with one (100 samples).
inline FitResult MakeResult(int samples = 200) {
  FitResult r;
  ParameterEstimate fixed;
  fixed.name = "m_L";
  fixed.unit = "kg";
  fixed.value = fixed.initial = 2.5;
  fixed.free = false;
  fixed.std_error = fixed.ci95_low = fixed.ci95_high = std::numeric_limits<double>::quiet_NaN();
  ParameterEstimate vl;
  vl.name = "V_L";
  vl.unit = "V";
  vl.value = 0.1234;
  vl.initial = 0.1;
  vl.free = true;
  vl.std_error = 0.002;
  vl.ci95_low = 0.1194;
  vl.ci95_high = 0.1274;
  ParameterEstimate kt;
  kt.name = "K_t";
  kt.unit = "V*s/rad";
  kt.value = 0.05;
  kt.initial = 0.04;
  kt.free = true;
  kt.std_error = std::numeric_limits<double>::quiet_NaN();  // e.g. covariance failed
  kt.ci95_low = kt.ci95_high = std::numeric_limits<double>::quiet_NaN();
  kt.determined = false;
  // Fixed first on purpose: the writers put free parameters first.
  r.parameters = {fixed, vl, kt};
  r.free_names = {"V_L", "K_t"};
  r.correlation.resize(2, 2);
  r.correlation << 1.0, 0.995, 0.995, 1.0;
  r.undetermined = {"K_t"};

  ExperimentFit step;
  step.name = "step 1";
  step.role = "fit";
  for (int k = 0; k < samples; ++k) step.t.push_back(0.005 * k);
  step.channels = {MakeChannel("a", "m/s^2", true, step.t, 2.0),
                   MakeChannel("x", "m", true, step.t, 0.1)};
  ExperimentFit validate;
  validate.name = "chirp";
  validate.role = "validate";
  for (int k = 0; k < 100; ++k) validate.t.push_back(0.01 * k);
  validate.channels = {MakeChannel("v", "m/s", false, validate.t, 0.5)};
  validate.channels[0].ljung_box_p = std::numeric_limits<double>::quiet_NaN();
  validate.channels[0].fit_percent = -std::numeric_limits<double>::infinity();
  r.experiments = {step, validate};

  r.initial_cost = 120.5;
  r.final_cost = 3.25;
  r.converged = true;
  r.start_costs = {3.25, 7.5, std::numeric_limits<double>::quiet_NaN()};
  r.num_residuals = 600;
  r.residual_variance = 2.0 * 3.25 / 598.0;
  r.aic = 6.5 + 4.0;
  r.bic = 6.5 + 2.0 * std::log(600.0);
  r.iterations = 17;
  r.simulations = 40;
  r.jacobian_evaluations = 18;
  r.termination = "Function tolerance reached. |cost_change|/cost: 1e-9";
  return r;
}

}  // namespace fixture
}  // namespace axis

#endif  // TESTS_FIT_RESULT_FIXTURE_H_
