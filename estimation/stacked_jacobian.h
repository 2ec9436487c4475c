// The σ-weighted residuals of a job's fitted experiments and their Jacobian
// in the optimiser's coordinates, stacked: the linearisation the score test
// (discovery/discovery.h), the force map's smoothing choice
// (discovery/force_map.h) and the experiment design (design/) work on.
#ifndef ESTIMATION_STACKED_JACOBIAN_H_
#define ESTIMATION_STACKED_JACOBIAN_H_

#include <Eigen/Core>

#include "estimation/estimation_problem.h"

namespace axis {

// The σ-weighted residuals r (m) of the job's fitted experiments at its
// free parameters' initial values (FreeParameter::initial) and their
// Jacobian (m × n) in the optimiser's coordinates θ (estimation/experiment_cost.h
// ParameterMap), stacked in experiment order. Throws std::runtime_error if
// a simulation fails. The experiments start from their `initial_state`
// (after ApplyEstimates the fitted one) and the Jacobian has no columns for
// estimated initial states: at the estimate the residual is orthogonal to
// those directions, so a candidate column's share along them adds to the
// score test's variance and nothing to its score (the test errs
// conservative). The experiments are simulated on up to job.solver.threads
// threads (common/concurrency.h ForEachConcurrently), each into its own
// rows: the result does not depend on the number. If several simulations
// fail, the error names the first such experiment.
void StackedJacobian(const EstimationProblem& job, Eigen::VectorXd* r, Eigen::MatrixXd* jac);

}  // namespace axis

#endif  // ESTIMATION_STACKED_JACOBIAN_H_
