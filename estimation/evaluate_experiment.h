// The goodness of fit of one experiment at given parameters: the simulated
// channels beside the measured ones, RMS, fit %, whiteness and the
// cross-correlation with the input (estimation/fit_result.h ExperimentFit).
#ifndef ESTIMATION_EVALUATE_EXPERIMENT_H_
#define ESTIMATION_EVALUATE_EXPERIMENT_H_

#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"
#include "sim/axis_params.h"

namespace axis {

// Simulates `experiment` with `params` and fills its goodness of fit: every
// measured channel compared (fitted ones flagged with their σ), residual
// whiteness and cross-correlation with the simulated input u.
ExperimentFit EvaluateExperiment(const AxisStructure& structure,
                                 const AxisParams<double>& params,
                                 const FitExperiment& experiment);

}  // namespace axis

#endif  // ESTIMATION_EVALUATE_EXPERIMENT_H_
