// The roughness penalty of a free force map (MODEL.md §7 `force_map`) as a
// Ceres cost: ½λ‖D·f‖² on the second differences of the map's values, and
// the anchor rows that hold at zero the components a free parameter
// produces exactly (a P-spline: Eilers & Marx 1996, "Flexible smoothing
// with B-splines and penalties", Statistical Science 11(2)). Part of the
// fit's cost (estimation/fit.h) when the force-map step of the discovery
// loop (discovery/force_map.h) sets EstimationProblem::force_map_lambda.
#ifndef ESTIMATION_ROUGHNESS_COST_H_
#define ESTIMATION_ROUGHNESS_COST_H_

#include <string>
#include <vector>

#include <Eigen/Core>
#include <ceres/ceres.h>

#include "estimation/experiment_cost.h"
#include "sim/force_map.h"

namespace axis {

// The roughness matrix D ((K−2) × K, K = knots.size() ≥ 3): row j − 1 is
// twice the divided second difference f[t_{j−1}, t_j, t_{j+1}] times the
// mean knot spacing squared, i.e. f_{j−1} − 2·f_j + f_{j+1} on uniform
// knots. Knots as
// ForceMapKnotsProblem accepts; never throws.
Eigen::MatrixXd SecondDifferences(const std::vector<double>& knots);

// The components of a map that a free parameter of the model produces
// exactly, as unit rows (c × K) in the space of the map's K values: the
// constant (1/√K per knot) of f(v) or f(x) when F_0 is free (or x_0 with
// f(x)), the slope ((t_k − t̄)/‖t − t̄‖) of f(v) when B_a is free and of f(x)
// when k_x is free, the constant of f(x)·sgn_ε(v) when F_c is free. The
// data cannot tell the map's share from the parameter's, so the fit holds
// these components at zero (the anchor rows of RoughnessCost) and the
// parameter carries them. Never throws.
Eigen::MatrixXd ConfoundedComponents(const ForceMap& f, const std::vector<std::string>& free_names);

// The Ceres cost of the roughness penalty and the anchor: residuals
// [√λ·D; √α·C]·f (dimensionless: λ, α in 1/N², f in N), C the
// ConfoundedComponents of the map's free parameters, f the map's values —
// free ones from θ through the ParameterMap, fixed ones from its base
// parameters. Its Jacobian is analytic (the penalty is linear in f).
class RoughnessCost : public ceres::CostFunction {
 public:
  // The cost over a parameter block of `theta_size` entries, or nullptr if
  // `f` is not enabled, both `lambda` and `anchor` are ≤ 0 or none of
  // f_map.<k> (k < K) is free in `map`. `map` must outlive the cost. Never
  // throws.
  static ceres::CostFunction* Create(const ForceMap& f, const ParameterMap& map, int theta_size,
                                     double lambda, double anchor);

  RoughnessCost(const Eigen::MatrixXd& scaled_d, std::vector<int> theta_index,
                std::vector<double> fixed, const ParameterMap& map, int theta_size);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  Eigen::MatrixXd d_;             // [√λ·D; √α·C], (K − 2 + c) × K
  std::vector<int> theta_index_;  // per knot: index in θ, −1 if fixed
  std::vector<double> fixed_;     // per knot: the value when fixed (N)
  const ParameterMap& map_;
  int theta_size_;
};

}  // namespace axis

#endif  // ESTIMATION_ROUGHNESS_COST_H_
