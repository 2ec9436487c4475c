// Intervals at the scale where the cost is smooth (issue 42). On records
// whose sampled signals jump with the parameters (accelerometer samples
// taken at the instant across backlash contacts, MODEL.md §6) the cost is
// rough below the standard-error scale: autodiff's Jacobian at the point
// sees only the local slope between jumps, and the profile likelihood's
// refits stop in the jumps, so that the estimate can sit at one end of its
// own interval and the intervals come out 10–15 times too narrow. A
// Jacobian by central differences at about one standard error averages over
// the jumps; its Gauss–Newton covariance is the interval at that scale.
#ifndef ESTIMATION_INTERNAL_SMOOTH_SCALE_H_
#define ESTIMATION_INTERNAL_SMOOTH_SCALE_H_

#include <vector>

#include <Eigen/Core>
#include <ceres/problem.h>

#include "estimation/experiment_cost.h"

namespace axis {

// An estimate within this fraction of its interval's width from one end is
// an artifact of roughness: on a smooth profile likelihood the cost would
// have to rise (19)² = 361 times faster on one side than on the other.
constexpr double kEndFraction = 0.05;

// True if `value` lies within kEndFraction·(high − low) of `low` or `high`
// (or outside [low, high]); false for a non-finite or empty interval.
// Never throws.
bool EstimateAtIntervalEnd(double value, double low, double high);

// The σ-weighted residuals of `problem` at `point` (written into its single
// parameter block `theta`), in the order of its residual blocks, into *r;
// false if they cannot be evaluated or one is not finite. `threads` ≥ 1.
bool ResidualsAt(ceres::Problem* problem, const std::vector<double>& point, int threads,
                 std::vector<double>* theta, Eigen::VectorXd* r);

// Jacobian (m×n, n = centre.size()) of the residuals by central
// differences: column k = (r(θ⁺) − r(θ⁻))/(θ⁺_k − θ⁻_k), θ^± = centre ±
// steps[k]·e_k clipped to [lower_k, upper_k]. Simulates in double (the
// guard of `counter` off, restored on return). False if an evaluation fails
// or a step is not positive. Leaves *theta at `centre`.
bool CentralDifferenceJacobian(ceres::Problem* problem, const std::vector<double>& centre,
                               const std::vector<double>& steps,
                               const std::vector<double>& lower,
                               const std::vector<double>& upper, EvaluationCounter* counter,
                               int threads, std::vector<double>* theta, Eigen::MatrixXd* j);

struct SmoothScale {
  bool ok = false;
  Eigen::MatrixXd cov;       // n×n covariance of θ, s²·(JᵀJ)⁺
  Eigen::MatrixXd jacobian;  // m×n, the last pass's
  Eigen::VectorXd residuals;  // m, at the centre
  std::vector<double> steps;  // the last pass's steps (θ units)
  int passes = 0;
};

// The covariance at the smooth scale: steps of one standard deviation of
// `cov0` (n×n, θ units, scaled by s²; a step that is not finite and
// positive is 1e-6·(1 + |θ_k|)), the Jacobian by CentralDifferenceJacobian,
// cov = s2·(JᵀJ)⁺ (eigenvalues below 1e-14 of the largest dropped), and
// again with each step that is below half its new standard deviation
// raised to it (steps never shrink), until no step is, at most 4 passes
// (the scale of the differences reaches the scale of the interval).
// ok false if an evaluation fails. Leaves *theta at `centre`.
SmoothScale SmoothScaleCovariance(ceres::Problem* problem, const std::vector<double>& centre,
                                  const Eigen::MatrixXd& cov0, const std::vector<double>& lower,
                                  const std::vector<double>& upper, double s2,
                                  EvaluationCounter* counter, int threads,
                                  std::vector<double>* theta);

}  // namespace axis

#endif  // ESTIMATION_INTERNAL_SMOOTH_SCALE_H_
