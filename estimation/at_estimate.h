// The model at a fit's estimate: a job's free parameters and estimated
// initial states set to the values a FitResult holds — for the residual
// diagnostics, the score tests, warm refits and the next fit's start.
#ifndef ESTIMATION_AT_ESTIMATE_H_
#define ESTIMATION_AT_ESTIMATE_H_

#include <array>

#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"

namespace axis {

// Sets `e`'s initial arm position y0 = y[0] (m) and velocity y1 = y[1]
// (m/s), with the motor's y2 = y0/r_g (rad), y3 = y1/r_g (rad/s): the gear
// undeflected, as `initial_state: estimate` fits them (configs/README.md;
// MODEL.md §1). r_g in m/rad, > 0.
void SetArmState(const std::array<double, 2>& y, double r_g, FitExperiment* e);

// Writes the free parameters' estimates of `result` into `job` as model
// values and as initial values (clamped to their bounds), the tied
// parameters their sources' values (EstimationProblem::ties), and the fitted
// initial states (FitResult::initial_states) into its experiments with
// `initial_state: estimate`: the model at the estimate, for the score test
// and the diagnostics, and the warm start of the next fit. Never throws
// (the loader has checked the ties' names).
void ApplyEstimates(const FitResult& result, EstimationProblem* job);

// A copy of `job` with ApplyEstimates(result) applied: the model at the
// estimate (for its residual diagnostics, or warm refits). Never throws.
EstimationProblem AtEstimate(const EstimationProblem& job, const FitResult& result);

}  // namespace axis

#endif  // ESTIMATION_AT_ESTIMATE_H_
