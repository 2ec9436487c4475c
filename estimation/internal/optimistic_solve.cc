#include "estimation/internal/optimistic_solve.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "estimation/experiment_cost.h"

namespace axis {

void SolveOptimistically(const ceres::Solver::Options& options, ceres::Problem* problem,
                         double* theta, int n, EvaluationCounter* counter,
                         ceres::Solver::Summary* summary,
                         const std::function<void()>& before_rerun) {
  if (counter == nullptr || !counter->guard) {
    ceres::Solve(options, problem, summary);
    return;
  }
  const std::vector<double> start(theta, theta + n);
  ceres::Solver::Summary first;
  {
    const ScopedGuardOff off(counter);
    ceres::Solve(options, problem, &first);
  }
  if (first.IsSolutionUsable()) {
    *summary = std::move(first);
    return;
  }
  std::copy(start.begin(), start.end(), theta);
  if (before_rerun) before_rerun();
  ceres::Solve(options, problem, summary);
  summary->num_residual_evaluations += first.num_residual_evaluations;
  summary->num_jacobian_evaluations += first.num_jacobian_evaluations;
  summary->minimizer_time_in_seconds += first.minimizer_time_in_seconds;
  summary->total_time_in_seconds += first.total_time_in_seconds;
}

}  // namespace axis
