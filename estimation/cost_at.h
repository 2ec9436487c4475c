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

// ceres::Problem::Evaluate's options for an evaluation of the residual
// blocks on up to `threads` threads (< 1 counts as 1): CostAt's, and those
// of the dense Jacobians and residuals taken outside the solver
// (estimation/optimum_check.h EvaluateDenseJacobian, the misspecification
// and smooth-scale checks). Never throws.
ceres::Problem::EvaluateOptions EvaluateOn(int threads);

}  // namespace axis

#endif  // ESTIMATION_COST_AT_H_
