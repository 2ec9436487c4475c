// The parameter rows of a FitResult (estimation/fit_result.h
// ParameterEstimate) that carry no interval: the fixed parameters, and the
// free ones of a fit stopped before the whole record; and the progress line
// of a continuation stage that failed. Internal to estimation/.
#ifndef ESTIMATION_INTERNAL_FIT_ESTIMATES_H_
#define ESTIMATION_INTERNAL_FIT_ESTIMATES_H_

#include <ostream>
#include <string>
#include <vector>

#include "estimation/experiment_cost.h"
#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"

namespace axis {

// Appends the fixed parameters (those not in result->free_names) at their
// values in `fitted`, standard errors and intervals NaN; only those the model
// configuration uses (no per-channel sensor parameters); units those of an
// axis moving as `motion` (ParamUnit, sim/axis_params.h). A parameter tied
// to another (`ties`, estimation/parameter_tie.h) names it in
// ParameterEstimate::tied_to and, where the source is free and already in
// result->parameters, carries its standard errors and interval (the same
// value; CopyTiedUncertainty, estimation/parameter_tie.h).
void AppendFixedEstimates(AxisParams<double> fitted, Motion motion,
                          const std::vector<ParameterTie>& ties, FitResult* result);


// The parameters of a fit stopped before the whole record (FitResult::
// abandoned_horizon): every one at its value at θ (internal coordinates),
// no standard errors.
void AppendEstimates(const EstimationProblem& job, const ParameterMap& map,
                     const std::vector<double>& theta, FitResult* result);

// One progress line for a continuation stage that failed, with the free
// parameters where it failed.
void ReportStageFailure(const EstimationProblem& job, const ParameterMap& map,
                        const std::vector<double>& theta, size_t start,
                        double horizon, const std::string& message,
                        const std::string& action, std::ostream* progress);

}  // namespace axis

#endif  // ESTIMATION_INTERNAL_FIT_ESTIMATES_H_
