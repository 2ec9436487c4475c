#include "estimation/internal/fit_problem.h"

#include <algorithm>
#include <cmath>

#include "estimation/experiment_cost.h"
#include "estimation/horizon_checkpoint.h"
#include "estimation/roughness_cost.h"
#include "estimation/cost_at.h"
#include "estimation/estimation_problem.h"

namespace axis {

void BuildStage(const EstimationProblem& job, const ParameterMap& map,
                const std::vector<int>& state_index,
                const std::vector<double>& lower,
                const std::vector<double>& upper, double* theta,
                EvaluationCounter* counter, HorizonStage* stage) {
  const int theta_size = static_cast<int>(lower.size());
  stage->problem = std::make_unique<ceres::Problem>();
  stage->sample_sigma.assign(stage->experiments.size(), SampleSigmas{});
  for (size_t j = 0; j < stage->experiments.size(); ++j) {
    stage->sample_sigma[j].assign(stage->experiments[j].fitted.size(), {});
    ceres::CostFunction* cost =
        ExperimentCost::Create(job.model.structure, map, stage->experiments[j], theta_size,
                               state_index[j], counter, &stage->sample_sigma[j]);
    stage->num_residuals += cost->num_residuals();
    stage->problem->AddResidualBlock(cost, nullptr, theta);
  }
  // A force map's roughness penalty (discovery/force_map.h): in the cost, not in
  // the residual count (it is a prior on the map, not data).
  if (ceres::CostFunction* roughness = RoughnessCost::Create(
          job.model.structure.force_map, map, theta_size, job.roughness.lambda,
          job.roughness.anchor)) {
    stage->problem->AddResidualBlock(roughness, nullptr, theta);
  }
  for (int k = 0; k < theta_size; ++k) {
    if (std::isfinite(lower[k])) stage->problem->SetParameterLowerBound(theta, k, lower[k]);
    if (std::isfinite(upper[k])) stage->problem->SetParameterUpperBound(theta, k, upper[k]);
  }
}

std::string CheckpointMismatch(const HorizonCheckpoint& checkpoint,
                               const std::vector<HorizonStage>& stages,
                               const std::vector<std::vector<double>>& starts, int threads,
                               std::vector<double>* theta) {
  if (checkpoint.starts.size() != starts.size()) {
    return std::to_string(checkpoint.starts.size()) + " start(s) where the job has " +
           std::to_string(starts.size());
  }
  std::vector<double> horizons;
  for (size_t i = 0; i + 1 < stages.size(); ++i) horizons.push_back(stages[i].horizon);
  if (checkpoint.horizons != horizons) return "other horizons";
  for (size_t s = 0; s < starts.size(); ++s) {
    const HorizonCheckpoint::Start& start = checkpoint.starts[s];
    if (start.point != starts[s]) return "start " + std::to_string(s) + " elsewhere";
    if (start.stages.size() >= stages.size()) return "too many stages";
    for (const HorizonCheckpoint::StageEnd& done : start.stages) {
      if (done.theta.size() != theta->size()) return "points of another size";
    }
  }
  const std::vector<HorizonCheckpoint::StageEnd>& first = checkpoint.starts[0].stages;
  if (!first.empty() && first[0].usable) {
    const double cost = CostAt(stages[0].problem.get(), starts[0], threads, theta);
    if (!(std::abs(cost - first[0].start_cost) <= 1e-9 * std::abs(first[0].start_cost))) {
      return "another cost on the first horizon (other data or model)";
    }
  }
  return "";
}

}  // namespace axis
