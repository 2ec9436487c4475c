// What a fit produces: parameter estimates with their uncertainty, goodness
// of fit per experiment and channel, and the solver's account. Filled by
// estimation/fit.cc, written by report/report.cc.
#ifndef ESTIMATION_FIT_RESULT_H_
#define ESTIMATION_FIT_RESULT_H_

#include <array>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "estimation/horizon_checkpoint.h"

namespace axis {

// One model parameter in the report (free or fixed).
struct ParameterEstimate {
  std::string name;   // MODEL.md name, e.g. "V_L"
  std::string unit;   // SI unit, e.g. "V"
  double value = 0.0;
  double initial = 0.0;
  bool free = false;
  // Free parameters only (NaN for fixed): standard error from the
  // covariance of FitResult::uncertainty_method scaled by the residual
  // variance, and the 95 % interval value ± t_{0.975, m−n}·std_error
  // (m residuals, n free parameters).
  double std_error = 0.0;
  // The Gauss–Newton standard error ((JᵀJ)⁻¹ at the estimate), reported
  // beside std_error whatever the method.
  double std_error_gauss_newton = 0.0;
  // Residual bootstrap (estimation/uncertainty.h): standard deviation of the
  // refits and their 2.5 / 97.5 % percentiles; NaN unless
  // uncertainty.bootstrap > 0.
  double std_error_bootstrap = 0.0;
  double bootstrap_low = 0.0;
  double bootstrap_high = 0.0;
  double ci95_low = 0.0;
  double ci95_high = 0.0;
  // Where ci95_low/high and std_error come from (free parameters; "" for
  // fixed): "profile likelihood", "likelihood ratio", "Gauss–Newton", or
  // "Gauss–Newton at the smooth scale" (a Jacobian by central differences
  // at about one standard error, where the profile's intervals were
  // artifacts of a rough cost: estimation/internal/smooth_scale.h).
  std::string interval_method;
  // The sandwich (Newey–West) standard error, which allows for the model's
  // misfit (estimation/internal/sandwich_covariance.h); NaN unless
  // FitResult::misspecification_note is set.
  double std_error_sandwich = std::numeric_limits<double>::quiet_NaN();
  // False if the data cannot determine it: the Jacobian is rank deficient
  // in its direction, or |correlation| > 0.99 with another free parameter.
  bool determined = true;
  // A fixed parameter tied to another (job key `tie:`,
  // estimation/parameter_tie.h): that parameter's name, its value here, and
  // where the source is free its standard errors and interval; "" if not
  // tied.
  std::string tied_to;
};

// Goodness of fit of one channel of one experiment (MODEL.md §6 channel).
struct ChannelFit {
  std::string channel;     // canonical name, e.g. "a"
  std::string unit;
  double sigma = 0.0;      // σ used to weight the residual (fitted channels), else 0
  bool fitted = false;     // residual entered the cost
  double rms = 0.0;        // sqrt(mean((ŷ − y)²)), channel unit
  double fit_percent = 0.0;  // NRMSE fit: 100·(1 − ‖y − ŷ‖/‖y − mean(y)‖)
  double max_error = 0.0;  // max |ŷ − y|
  double mae = 0.0;        // mean |ŷ − y| (MeanAbsError), channel unit
  double relative_error_percent = 0.0;  // 100·‖ŷ − y‖/‖y‖ (EMPS measure)
  double ljung_box_q = 0.0;   // Ljung–Box statistic of the residual
  int ljung_box_lags = 20;
  double ljung_box_p = 0.0;   // p-value, χ² with ljung_box_lags dof
  double input_xcorr_peak = 0.0;  // max |normalised cross-correlation| with u
  int input_xcorr_lag = 0;        // its lag in samples (residual lags input if > 0)
  std::vector<double> measured;   // y, per sample
  std::vector<double> simulated;  // ŷ, per sample
};

// One experiment of the job, fitted or only validated.
struct ExperimentFit {
  std::string name;
  std::string role;  // "fit" or "validate"
  std::vector<double> t;  // s, sample times of measured/simulated
  std::vector<ChannelFit> channels;
};

// Wall time and model evaluations spent in one phase of FitParameters
// (accumulated when a phase runs more than once).
struct FitPhase {
  std::string name;     // "starts", "optimum check", "local restarts",
                        // "covariance", "intervals", "evaluation"
  double seconds = 0.0;  // wall-clock time (std::chrono::steady_clock)
  int simulations = 0;   // residual-only evaluations in the phase
  int jacobians = 0;     // evaluations with derivatives in the phase
};

struct FitResult {
  std::vector<ParameterEstimate> parameters;  // free first (job order), then fixed
  std::vector<std::string> free_names;        // order of the correlation matrix
  Eigen::MatrixXd correlation;                // n×n for the free parameters
  std::vector<std::string> undetermined;      // names with determined == false
  std::vector<ExperimentFit> experiments;
  double initial_cost = 0.0;   // Ceres cost ½Σr² at the initial point
  double final_cost = 0.0;     // at the estimate
  bool converged = false;
  // Final cost of every start (initial point first); NaN for a start not
  // continued to the whole record (solver.finalists), +inf for an abandoned one.
  std::vector<double> start_costs;
  // Each start's cost at the end of the longest shorter horizon
  // (screen_horizon, s) that ranked them; NaN without continuation stages.
  std::vector<double> start_screen_costs;
  // Per start: the earlier start whose path it joined (its point after a
  // shorter horizon within that stage's parameter tolerance of the earlier
  // start's; it went no further) and that horizon (s); −1 and 0 for a start
  // that went its own way.
  std::vector<int> start_joined;
  std::vector<double> start_joined_horizon;
  double screen_horizon = 0.0;
  int num_residuals = 0;
  // s² = Σr²/(m − n) and its degrees of freedom m − n, n the fitted entries
  // of θ (free parameters and estimated initial states); for a fit with a
  // kept force map (discovery/force_map.h) the data's Σr² (without the roughness
  // penalty) over m − edf.
  double residual_variance = 0.0;
  double residual_dof = 0.0;
  double aic = 0.0;   // Σr² + 2n (Gaussian, σ known up to the weights)
  double bic = 0.0;   // Σr² + n·ln(m)
  // (y0 m, y1 m/s) of each of the job's `experiments` (its order) at the
  // estimate: fitted for an experiment with `initial_state: estimate`, the
  // declared state otherwise (MODEL.md §1). Empty for a fit that ended
  // without an estimate. ApplyEstimates (estimation/at_estimate.h) writes the fitted
  // ones back into a job.
  std::vector<std::array<double, 2>> initial_states;
  // A fit stopped by control.abandon_above_bic (estimation/fit.h FitParameters):
  // the horizon (s) of the stage where its BIC's lower bound passed that
  // level; 0 for a fit that ran to the whole record. Then `bic` is that
  // lower bound, `parameters` hold the values at the stop (standard errors
  // NaN), `experiments` is empty and the other figures are NaN.
  double abandoned_horizon = 0.0;
  // With control.stop_after_horizon: the stages every start ran, for a fit
  // of the same job to go on from (FitControl::resume); null otherwise.
  std::shared_ptr<const HorizonCheckpoint> checkpoint;
  int iterations = 0;
  int simulations = 0;            // residual-only evaluations
  int jacobian_evaluations = 0;   // evaluations with derivatives
  std::string termination;        // Ceres' message
  // Why the end point may depend on the path (FitParameters): set when the
  // solver stopped on its step size (Ceres' parameter tolerance: the trust
  // region collapsed, not a small gradient or cost change) on a model whose
  // controller quantises the position feedback (sim/controller.h
  // load_quantum, counts_per_rev), whose cost is then piecewise constant at
  // the quantum. Empty otherwise.
  std::string stop_note;
  // Where the fitting model's approximation may bias an estimate by a
  // sizeable fraction of its standard error (FitParameters): a sensor delay
  // tau_d.<channel> fitted with the quasi-steady current loop, whose
  // neglected time constant τ_i = L/(K_a/K_i + R) (MODEL.md eq. 3) is at
  // least half the delay's standard error. Empty otherwise.
  std::string model_note;
  // Set when the job's start alone ended above kAutoStartsAbove and
  // SolverSettings::auto_starts random starts were added (estimation/solver_settings.h): what
  // s² it ended with and which start won. Empty otherwise.
  std::string auto_starts_note;
  // Set when the instant accelerometer's samples at a backlash contact were
  // weighted by σ_k (estimation/internal/instant_sample_sigma.h): how many, the
  // largest σ_k/σ and the re-solves. Empty otherwise.
  std::string sample_sigma_note;
  // Σ log(σ_k²/σ²) over the per-sample σ_k of the final cost (0 without
  // them): what −2·log-likelihood adds to 2·final_cost (Deviance).
  double sample_sigma_log_term = 0.0;
  // Set when the fit ends with s² = residual_variance above
  // kAutoStartsAbove (estimation/solver_settings.h): the residual RMS more than twice the
  // declared σ, i.e. a local minimum the starts did not leave, an effect
  // the model lacks, or σ understated. Empty otherwise.
  std::string residual_note;
  // Set when s² is above kMisspecifiedS2 (estimation/fit_notes.h) and a
  // fitted channel's residual is structured (Ljung–Box p below
  // kStructuredResidualP): the intervals are conditional on the model, and
  // the sandwich standard errors (ParameterEstimate::std_error_sandwich)
  // that allow for the misfit, in words. Empty otherwise.
  std::string misspecification_note;
  // How the model was integrated (FitParameters): RK4's step(s) and, with
  // an analog_velocity_loop, the current loop (sim/axis_params.h
  // CurrentLoop), e.g. "RK4, step 5e-05 s; current loop quasi_steady".
  std::string integration;
  // Optimum check after the solver stopped (FitParameters): the cost probed
  // at the estimate ± {0.01, 0.3, 1, 3, 10} standard deviations along every
  // parameter, every principal axis of the covariance and the last stage's
  // step; a lower cost restarts the solver from there.
  bool optimum_verified = false;
  std::string optimum_check;     // "optimum verified: …" or why not
  int probe_rounds = 0;          // probe rounds run
  double probe_decrease = 0.0;   // cost decrease found by probing + restarts
  int local_starts = 0;           // local restarts run (solver.local_starts)
  double local_decrease = 0.0;    // cost decrease they found
  // Uncertainty (estimation/uncertainty.h): "cost_curvature" or "gauss_newton" (the
  // method behind std_error), and what it did, in words.
  std::string uncertainty_method;
  std::string uncertainty_note;
  int bootstrap_replicates = 0;  // refits that converged (0: no bootstrap)
  // Where the time went, in the order the phases first ran.
  std::vector<FitPhase> phases;
};

// 2·final_cost + sample_sigma_log_term: −2·log-likelihood of `result` up to
// the constant every fit of the same records shares, so that fits under
// different per-sample σ_k (estimation/internal/instant_sample_sigma.h) compare as
// χ² do. Never throws.
inline double Deviance(const FitResult& result) {
  return 2.0 * result.final_cost + result.sample_sigma_log_term;
}

}  // namespace axis

#endif  // ESTIMATION_FIT_RESULT_H_
