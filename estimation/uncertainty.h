// Uncertainty of a fit's estimate beyond the Gauss–Newton covariance
// (issue 9): the curvature of the cost measured at the scale of the
// confidence interval, and the residual bootstrap that cross-checks it.
//
// Why: the cost of the model as specified (MODEL.md §3) is piecewise smooth.
// Near a grazing backlash contact (the gear only just reaches the edge of
// the backlash) the event time is hypersensitive to the parameters — the
// saltation term divides by the guard's rate, which goes to zero — so JᵀJ at
// the estimate describes the cost only within a tiny neighbourhood and can
// overstate the information by orders of magnitude. Measured on the PRBS
// campaign (scripts/optimum-campaign): T_p estimates 3–8 Gauss–Newton
// standard errors from the truth while their cost lay within 1 of the
// truth's.
#ifndef ESTIMATION_UNCERTAINTY_H_
#define ESTIMATION_UNCERTAINTY_H_

#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include "estimation/fit_result.h"
#include "job/fit_job.h"

namespace axis {

// The cost ½Σr² of `problem` at `point` (internal coordinates, written into
// its single parameter block `theta`, whose size equals point.size()), or +∞
// where the simulation fails or the cost is not finite. The residual blocks
// (one per experiment) are evaluated on `threads` threads (≥ 1), as the
// solver evaluates them (ceres::Problem::EvaluateOptions::num_threads).
double CostAt(ceres::Problem* problem, const std::vector<double>& point, int threads,
              std::vector<double>* theta);

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

// Likelihood-ratio 95 % intervals along the profile directions, measured on
// the cost itself. For free parameter k the direction is d_k = C·e_k/√C_kk,
// C the Gauss–Newton covariance of θ (`cov_theta`, n×n, n = theta->size(),
// already scaled by the residual variance s²): moving θ_k by one standard
// deviation while the others follow their regression on θ_k, the path along
// which a quadratic cost's profile is traced. The cost is evaluated at
// θ* ± s·d_k for s in `steps` (standard deviations, increasing), and each
// end of the interval is the furthest s at which cost − cost(θ*) is still
// ≤ ½·t²·s² (t = `t975`), interpolated linearly to the next step above the
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
RatioScan LikelihoodRatioIntervals(ceres::Problem* problem,
                                   const std::vector<double>& lower,
                                   const std::vector<double>& upper,
                                   const Eigen::MatrixXd& cov_theta, int n_free,
                                   double t975, double residual_variance,
                                   const std::vector<double>& steps, int threads,
                                   std::vector<double>* theta);

// What ProfileLikelihoodIntervals found.
struct ProfileScan {
  std::vector<RatioInterval> intervals;  // one per free parameter; empty on
                                         // failure or on an early stop
  int solves = 0;                        // constrained refits
  int iterations = 0;                    // their solver iterations in all
  double lowest_cost = 0.0;              // lowest cost met (the estimate's
  std::vector<double> lowest_point;      // if nothing is lower) and where
};

// Profile-likelihood 95 % intervals: for free parameter k the profile cost
// P(x) = min over the other entries of θ of cost(θ) with θ_k = x, each
// interval end the x where P has risen by ½·t²·s² above the estimate's
// cost (t = `t975`, s² = `residual_variance`), i.e. the likelihood-ratio
// test of θ_k = x at 95 % with the others re-estimated (Wilks; with an
// F/t threshold for the estimated σ²). Unlike a scan along a fixed line
// this holds where the cost is not quadratic and the others' best values
// move non-linearly with θ_k (on PRBS records the line scan and JᵀJ
// understated T_p's interval; README, issue 9 campaign).
// Each P(x) is one Levenberg–Marquardt run of `options` on `problem` (its
// single parameter block `theta`, n = theta->size() entries, bounds as set
// on the problem) with entry k held constant (ceres::SubsetManifold),
// started from a solved point moved along the Gauss–Newton profile
// direction C·e_k/C_kk (`cov_theta`, n×n, already scaled by s²). Per side,
// P is evaluated at θ*_k ± {1, 2, 4, 8}·t·√C_kk (clipped to the bound
// [lower_k, upper_k]), each refit warm-started from the previous point and,
// where it ends above the threshold, also from θ*; a refit ending above but
// within 3 times the threshold is retried from the solved point outside it
// (the lowest result counts): the cost is piecewise smooth with small jumps,
// and one local refit can stop in a local minimum above the profile. The
// profile can cross a bump between minima, so the end is placed past the
// furthest point still below the threshold (the hull of the confidence
// set), refined by regula falsi on √(P − cost*) (linear in x near a smooth
// minimum; refits from the bracket's inner end, retried as above) until P
// is within 5 % of the threshold or 4 refinements are spent. A side that does not rise past the threshold is marked
// unbounded, its end at the last point reached. If a refit ends below
// `lowest_allowed` (the estimate is not the optimum) and `stop_at_lower`,
// the search stops at once with no intervals, so that the caller can
// restart the solver at lowest_point. Leaves *theta at its entry value and
// the parameter block without a manifold. Returns no intervals if
// cov_theta is not finite or the cost cannot be evaluated at θ*.
// `on_parameter`, if set, is called with k before the search of parameter
// k begins (progress, common/progress.h). Source:
// Venzon & Moolgavkar, "A method for computing profile-likelihood-based
// confidence intervals", Appl. Statist. 37 (1988); Bates & Watts (1988)
// §6.1.
ProfileScan ProfileLikelihoodIntervals(ceres::Problem* problem,
                                       const ceres::Solver::Options& options,
                                       const std::vector<double>& lower,
                                       const std::vector<double>& upper,
                                       const Eigen::MatrixXd& cov_theta, int n_free,
                                       double t975, double residual_variance,
                                       double lowest_allowed, bool stop_at_lower,
                                       std::vector<double>* theta,
                                       const std::function<void(int)>& on_parameter = {});

// Residual bootstrap (Efron & Tibshirani, "An Introduction to the
// Bootstrap", 1993, §9.5; moving blocks, Künsch 1989): `settings.bootstrap`
// replicate data sets, each the fitted trace of `fit` plus its residuals
// (measured − simulated, per fitted channel of every fitted experiment)
// resampled in blocks of `settings.block` consecutive samples (random
// starts, seeded by settings.seed; blocks keep the residuals' correlation
// over shorter lags). Each replicate is refitted from the estimate (one
// start, whole record at once, no optimum check, Gauss–Newton covariance).
// Writes into fit->parameters (free ones) the replicates' standard deviation
// (std_error_bootstrap) and their 2.5 / 97.5 % percentiles (bootstrap_low /
// bootstrap_high), and the number of converged refits into
// fit->bootstrap_replicates. `fit` must come from FitParameters(job);
// throws std::invalid_argument if it does not match the job's experiments
// and channels. Refits start where the estimate is, so on a cost with local
// minima (estimation/fit.h, optimum check) they measure the local spread.
void ResidualBootstrap(const FitJob& job, FitResult* fit, std::ostream* progress);

}  // namespace axis

#endif  // ESTIMATION_UNCERTAINTY_H_
