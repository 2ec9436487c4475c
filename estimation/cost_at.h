// The cost ½Σr² of a Ceres problem at a given point: the one evaluation the
// fit's start screen, the optimum check and the interval methods share
// (estimation/uncertainty.h).
#ifndef ESTIMATION_COST_AT_H_
#define ESTIMATION_COST_AT_H_

#include <vector>

#include <ceres/problem.h>

namespace axis {

// The cost ½Σr² of `problem` at `point` (internal coordinates, written into
// its single parameter block `theta`, whose size equals point.size()), or +∞
// where the simulation fails or the cost is not finite. The residual blocks
// (one per experiment) are evaluated on `threads` threads (≥ 1), as the
// solver evaluates them (ceres::Problem::EvaluateOptions::num_threads).
double CostAt(ceres::Problem* problem, const std::vector<double>& point, int threads,
              std::vector<double>* theta);

}  // namespace axis

#endif  // ESTIMATION_COST_AT_H_
