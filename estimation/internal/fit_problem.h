// The least-squares problem of a fit: the optimisation vector θ (the free
// parameters in the internal coordinates of estimation/experiment_cost.h
// ParameterMap, then the estimated initial states), its bounds, and one
// Ceres problem per horizon of the continuation (estimation/internal/fitter.h).
// Internal to estimation/.
#ifndef ESTIMATION_INTERNAL_FIT_PROBLEM_H_
#define ESTIMATION_INTERNAL_FIT_PROBLEM_H_

#include <memory>
#include <string>
#include <vector>

#include <ceres/ceres.h>

#include "estimation/experiment_cost.h"
#include "estimation/horizon_checkpoint.h"
#include "estimation/estimation_problem.h"
#include "estimation/record_prefix.h"

namespace axis {

// The optimisation vector θ, its map to parameters and its bounds.
struct FitProblem {
  std::unique_ptr<ParameterMap> map;
  std::vector<double> theta;
  std::vector<double> lower, upper;  // internal bounds
  EvaluationCounter counter;
};

// One least-squares problem over a set of experiments (a horizon stage).
struct HorizonStage {
  double horizon = 0.0;  // s; the last stage covers every sample
  std::vector<FitExperiment> experiments;  // referenced by the costs
  // Per experiment, the per-sample σ_k its cost divides by (referenced by
  // the costs: sized once by BuildStage, its entries set by the fit).
  std::vector<SampleSigmas> sample_sigma;
  std::unique_ptr<ceres::Problem> problem;
  int num_residuals = 0;
};

// Adds the costs of `stage->experiments` (ExperimentCost, one residual block
// each, dividing by stage->sample_sigma, which it sizes with no per-sample
// σ_k; the experiment j's estimated initial state at θ[state_index[j]], −1
// for none), the force map's roughness penalty (estimation/roughness_cost.h)
// and the bounds to a new Ceres problem over `theta`. `counter` counts the
// simulations and Jacobians; `map` and `counter` must outlive the stage.
void BuildStage(const EstimationProblem& job, const ParameterMap& map,
                const std::vector<int>& state_index,
                const std::vector<double>& lower,
                const std::vector<double>& upper, double* theta,
                EvaluationCounter* counter, HorizonStage* stage);

// Why `checkpoint` is not one of the fit with these stages and starts
// (estimation/horizon_checkpoint.h), or "" if it is: the number of starts and
// their points, the shorter stages' horizons, the stages per start (fewer
// than the job's) and their points' size, and the cost at the first start
// on the first horizon (relative tolerance 1e-9: the same cost summed on
// another number of threads). May move *theta to starts[0].
std::string CheckpointMismatch(const HorizonCheckpoint& checkpoint,
                               const std::vector<HorizonStage>& stages,
                               const std::vector<std::vector<double>>& starts, int threads,
                               std::vector<double>* theta);

}  // namespace axis

#endif  // ESTIMATION_INTERNAL_FIT_PROBLEM_H_
