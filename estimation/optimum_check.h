// The optimum check of a fit (estimation/internal/fitter.h): the Gauss–Newton
// matrix JᵀJ, the cost resolution below which two fits ended at the same
// optimum, and one round of probing the cost around the estimate.
#ifndef ESTIMATION_OPTIMUM_CHECK_H_
#define ESTIMATION_OPTIMUM_CHECK_H_

#include <vector>

#include <Eigen/Core>
#include <ceres/ceres.h>

#include "estimation/experiment_cost.h"

namespace axis {

// A dense Jacobian in Ceres' own storage order (ceres/internal/eigen.h
// `Matrix`, row-major), as ceres::Covariance's DENSE_SVD builds it.
using DenseJacobian = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The Jacobian of the weighted residuals over the first n entries of θ at
// the current θ (m × n; θ is the problem's single parameter block), or
// false if it cannot be evaluated there. The residual blocks (the
// experiments', a roughness penalty's) are evaluated on up to `threads` threads
// (ceres::Problem::EvaluateOptions::num_threads; < 1 counts as 1); each
// block's rows are the same whatever the number.
bool EvaluateDenseJacobian(ceres::Problem* problem, int n, int threads, DenseJacobian* j);

// JᵀJ of `j` (the Gauss–Newton approximation of the cost's Hessian),
// summed row by row in column order. Never throws but std::bad_alloc.
Eigen::MatrixXd GaussNewtonOf(const DenseJacobian& j);

// GaussNewtonOf the Jacobian at the current θ (EvaluateDenseJacobian on
// `threads` threads), or false if it cannot be evaluated there.
bool GaussNewtonMatrix(ceres::Problem* problem, int n, int threads, Eigen::MatrixXd* jtj);

// The relative function and parameter tolerance of the continuation's
// shorter horizons (at least; the job's if larger): they only deliver a warm
// start for the next.
constexpr double kStageParameterTolerance = 1e-4;

// A point counts as lower than the estimate if its cost (½Σr² of σ-weighted
// residuals, i.e. half a χ²) is below by more than `relative` (the solver's
// function_tolerance, at least 1e-9) times the cost plus 1e-6 absolute. The
// solver itself stops once an iteration gains less than function_tolerance
// relative, so a smaller difference is within its accuracy and restarting
// it there moves the estimate by a few thousandths of a standard deviation
// (the paper job: three probe rounds and two local-restart passes, 9 s,
// for a decrease of 4.6e-5 in a cost of 4070, where 4.1e-5 is the solver's
// own stop); a χ² difference of 2e-6 means nothing statistically, and on
// noise-free records (cost ~1e-8 at the optimum) smaller differences are
// round-off that would otherwise restart the solver again and again
// (CostResolution, below).
constexpr double kLowerRelative = 1e-9;
constexpr double kLowerAbsolute = 1e-6;

// The smallest change of a cost (½Σr² of σ-weighted residuals) that the
// solver resolves: `function_tolerance` (Ceres' relative stop, at least
// kLowerRelative) times |cost|, plus kLowerAbsolute. Two fits whose costs
// differ by less ended at the same optimum as far as the solver can tell
// (the optimum check's "lower" point; the force map's removal ties,
// discovery/force_map.cc). Never throws.
double CostResolution(double cost, double function_tolerance);

// The cost a point must be below to count as lower than `cost` (see above).
double LowerThan(double cost, double relative);

// The relative tolerance of QuadraticReach: a probe along a principal axis
// agrees with the quadratic the covariance describes if its rise is within
// this fraction of ½s².
constexpr double kQuadraticAgreement = 0.1;

// What one round of the optimum check found (ProbeRound).
struct ProbeRoundResult {
  std::vector<double> best;  // the lowest point found (θ* if nothing is lower)
  double best_cost = 0.0;    // its cost (`cost` if nothing is lower)
  int probes = 0;            // cost evaluations made
  // The s of the point in `best` (standard deviations; 0 if nothing is
  // lower): lower points at 0.01 mean a cost rough below the standard-error
  // scale.
  double lowest_scale = 0.0;
  // The largest probe scale s ≥ 1 such that along every principal axis, on
  // both sides and at every probe scale from 1 up to s, the cost rose by
  // ½s² within kQuadraticAgreement (a rise of ½ per standard deviation
  // squared is what the covariance describes); a probe clipped to a bound
  // counts as disagreeing, so the reach ends at the scale before it; 0 if
  // even the probes at 1 disagree or there is no principal axis. Out to
  // that many standard deviations the probes saw the quadratic bowl of the
  // Gauss–Newton model along those lines (sampled at 1, 3 and 10: a kink
  // between the scales can go unseen).
  double quadratic_reach = 0.0;
};

// One round of the optimum check: the cost at θ* + s·d for the probe
// directions d (every coordinate and every principal axis of (JᵀJ)⁻¹, scaled
// to one standard deviation — a change of ½ in cost on a quadratic — and the
// last step, scaled alike) and s = ±{0.01, 0.3, 1, 3, 10}, clipped to the
// bounds. The lowest point found is ProbeRoundResult::best. The probes
// simulate in double (the guard of `counter` off); a point lower than θ* is
// kept only if it also passes the sensitivity guard (ExperimentCost), as the
// solver will start from it. The cost and JᵀJ are evaluated on `threads`
// threads (CostAt, GaussNewtonMatrix). *theta holds θ* on entry (`cost` its
// cost) and is left there. If JᵀJ cannot be evaluated, no probe is made
// (best = θ*, quadratic_reach 0). Never throws but std::bad_alloc.
ProbeRoundResult ProbeRound(ceres::Problem* problem, const std::vector<double>& lower,
                            const std::vector<double>& upper,
                            const std::vector<double>& last_step, double cost,
                            EvaluationCounter* counter, int threads,
                            std::vector<double>* theta);

}  // namespace axis

#endif  // ESTIMATION_OPTIMUM_CHECK_H_
