#include "estimation/cost_at.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace axis {

double CostAt(ceres::Problem* problem, const std::vector<double>& point, int threads,
              std::vector<double>* theta) {
  std::copy(point.begin(), point.end(), theta->begin());
  double cost = 0.0;
  if (!problem->Evaluate(EvaluateOn(threads), &cost, nullptr, nullptr, nullptr) ||
      !std::isfinite(cost)) {
    return std::numeric_limits<double>::infinity();
  }
  return cost;
}

ceres::Problem::EvaluateOptions EvaluateOn(int threads) {
  ceres::Problem::EvaluateOptions options;
  options.num_threads = std::max(1, threads);
  return options;
}

}  // namespace axis
