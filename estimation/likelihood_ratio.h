// Likelihood-ratio intervals of a fit's free parameters, measured on the
// cost along fixed lines (the profile directions of the Gauss–Newton
// covariance): the interval of one parameter (RatioInterval, also the
// profile likelihood's, estimation/profile_likelihood.h) and the line scan
// (LikelihoodRatioIntervals). Why the cost itself: estimation/uncertainty.h.
#ifndef ESTIMATION_LIKELIHOOD_RATIO_H_
#define ESTIMATION_LIKELIHOOD_RATIO_H_

#include <vector>

#include <Eigen/Core>
#include <ceres/problem.h>

namespace axis {

// A likelihood-ratio interval of one parameter, in internal coordinates
// (estimation/experiment_cost.h ParameterMap: log(value) for positive parameters).
struct RatioInterval {
  double low = 0.0, high = 0.0;  // θ_k at the interval's ends
  bool bounded_low = true;       // the cost rose past the threshold within
  bool bounded_high = true;      // the largest step on that side
};

// What LikelihoodRatioIntervals found.
struct RatioScan {
  std::vector<RatioInterval> intervals;  // one per free parameter; empty on failure
  int evaluations = 0;                   // cost evaluations
  double lowest_cost = 0.0;              // lowest cost probed (the estimate's
  std::vector<double> lowest_point;      // if nothing is lower) and where
};

// What an interval search starts from (LikelihoodRatioIntervals, and
// ProfileLikelihoodIntervals in estimation/profile_likelihood.h): θ's
// bounds, the estimate's covariance and the threshold's terms.
struct IntervalBasis {
  std::vector<double> lower, upper;  // θ's bounds (internal coordinates)
  // The Gauss–Newton covariance of θ, n×n, already scaled by s².
  Eigen::MatrixXd cov_theta;
  int n_free = 0;                  // intervals for θ_0 … θ_{n_free−1}
  double t975 = 1.96;              // the Student t quantile of the threshold
  double residual_variance = 1.0;  // s²
};

// What LikelihoodRatioIntervals works on beside the problem and how.
struct RatioScanOptions {
  IntervalBasis basis;
  // The points along each direction, in standard deviations, increasing.
  std::vector<double> steps;
  int threads = 1;  // the cost's evaluation threads (CostAt)
};

// Likelihood-ratio 95 % intervals along the profile directions, measured on
// the cost itself. For free parameter k the direction is d_k = C·e_k/√C_kk,
// C the Gauss–Newton covariance of θ (options.basis.cov_theta, n = theta->size()): moving θ_k by one standard
// deviation while the others follow their regression on θ_k, the path along
// which a quadratic cost's profile is traced. The cost is evaluated at
// θ* ± s·d_k for s in options.steps, and each
// end of the interval is the furthest s at which cost − cost(θ*) is still
// ≤ ½·t²·s² (t = options.basis.t975), interpolated linearly to the next step above the
// threshold; if none is above, the end is the largest step and the side is
// marked unbounded. On a quadratic cost the ends are θ*_k ± t·√C_kk, the
// Gauss–Newton interval; where the cost is piecewise smooth with kinks
// (MODEL.md §3, grazing backlash contacts) they follow the cost, which can
// be several times flatter on one side than JᵀJ says. Points are clipped to
// [lower, upper]. Returns one interval per parameter 0..n_free−1 (none if
// cov_theta is not finite or the cost cannot be evaluated at θ*) and the
// lowest cost met — a lower point than θ* means θ* is not the optimum, and
// the caller should restart the solver there. Leaves *theta at its entry
// value. The cost is evaluated on `threads` threads (CostAt). Source:
// Bates & Watts, "Nonlinear Regression Analysis and Its Applications"
// (1988), ch. 6 (likelihood and profile intervals); Venzon & Moolgavkar
// (1988).
RatioScan LikelihoodRatioIntervals(ceres::Problem* problem, const RatioScanOptions& options,
                                   std::vector<double>* theta);

}  // namespace axis

#endif  // ESTIMATION_LIKELIHOOD_RATIO_H_
