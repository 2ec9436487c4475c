// Profile-likelihood intervals of a fit's free parameters (issue 9; why the
// cost and not JᵀJ: estimation/uncertainty.h): the public search
// (ProfileLikelihoodIntervals, what it found: ProfileScan) and the class
// that runs it, one method per step (ProfileLikelihood, internal to
// estimation/).
#ifndef ESTIMATION_PROFILE_LIKELIHOOD_H_
#define ESTIMATION_PROFILE_LIKELIHOOD_H_

#include <cstddef>
#include <functional>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include "estimation/likelihood_ratio.h"

namespace axis {

struct EvaluationCounter;  // estimation/experiment_cost.h

// What ProfileLikelihoodIntervals found.
struct ProfileScan {
  std::vector<RatioInterval> intervals;  // one per free parameter; empty on
                                         // failure or on an early stop
  int solves = 0;                        // constrained refits
  int repeated = 0;                      // refits answered from memory (their
                                         // start refitted before)
  int iterations = 0;                    // their solver iterations in all
  double lowest_cost = 0.0;              // lowest cost met (the estimate's
  std::vector<double> lowest_point;      // if nothing is lower) and where
};

// What ProfileLikelihoodIntervals works on beside the problem and how.
struct ProfileOptions {
  // θ's bounds, the covariance and the threshold's terms; the entries of θ
  // past basis.n_free (the estimated initial states) are refitted with the
  // others.
  IntervalBasis basis;
  // The refits: one Levenberg–Marquardt run each.
  ceres::Solver::Options solver;
  // The counter of the problem's ExperimentCosts (estimation/experiment_cost.h),
  // or null: each refit then evaluates its trial points in double and runs
  // again with the sensitivity guard only if it fails
  // (estimation/internal/optimistic_solve.h). Must outlive the search.
  EvaluationCounter* counter = nullptr;
  // A refit ending below this cost means the estimate is not the optimum;
  // with stop_at_lower the search then stops at once (ProfileScan::
  // lowest_point, the caller restarts there).
  double lowest_allowed = -std::numeric_limits<double>::infinity();
  bool stop_at_lower = false;
  // Called with k before the search of parameter k begins (progress,
  // common/progress.h); may be empty.
  std::function<void(int)> on_parameter;
};

// Profile-likelihood 95 % intervals: for free parameter k the profile cost
// P(x) = min over the other entries of θ of cost(θ) with θ_k = x, each
// interval end the x where P has risen by ½·t²·s² above the estimate's
// cost (t = options.basis.t975, s² = options.basis.residual_variance), i.e. the likelihood-ratio
// test of θ_k = x at 95 % with the others re-estimated (Wilks; with an
// F/t threshold for the estimated σ²). Unlike a scan along a fixed line
// this holds where the cost is not quadratic and the others' best values
// move non-linearly with θ_k (on PRBS records the line scan and JᵀJ
// understated T_p's interval; README, issue 9 campaign).
// Each P(x) is one Levenberg–Marquardt run of options.solver on `problem` (its
// single parameter block `theta`, n = theta->size() entries, bounds as set
// on the problem) with entry k held constant (ceres::SubsetManifold),
// started from a solved point moved along the Gauss–Newton profile
// direction C·e_k/C_kk (options.basis.cov_theta). Per side,
// P is evaluated at θ*_k ± {1, 2, 4, 8}·t·√C_kk (clipped to the bound
// θ's bounds), each refit warm-started from the previous point; a refit
// that fails, or ends above the threshold but within 3 times it, is retried
// from θ* and (if still near) from the solved point outside it (the lowest
// result counts): the cost is piecewise smooth with small jumps, and one
// local refit can stop in a local minimum up to about half the threshold
// above the profile, too little to matter further out. The
// profile can cross a bump between minima, so the end is placed past the
// furthest point still below the threshold (the hull of the confidence
// set), refined by regula falsi on √(P − cost*) (linear in x near a smooth
// minimum; refits from the bracket's inner end, retried as above) until P
// is within 5 % of the threshold or 4 refinements are spent. A side that
// does not rise past the threshold is marked unbounded, its end at the last
// point reached. If a refit ends below
// options.lowest_allowed (the estimate is not the optimum) and options.stop_at_lower,
// the search stops at once with no intervals, so that the caller can
// restart the solver at lowest_point. Leaves *theta at its entry value and
// the parameter block without a manifold. Returns no intervals if
// cov_theta is not finite or the cost cannot be evaluated at θ*.
// Source:
// Venzon & Moolgavkar, "A method for computing profile-likelihood-based
// confidence intervals", Appl. Statist. 37 (1988); Bates & Watts (1988)
// §6.1.
ProfileScan ProfileLikelihoodIntervals(ceres::Problem* problem, const ProfileOptions& options,
                                       std::vector<double>* theta);

// The search of ProfileLikelihoodIntervals as a sequence of named steps, its
// state in members (as estimation/internal/fitter.h): per free parameter the two
// sides, each walked out along the profile, its points near the threshold
// retried inward, and its end bracketed and refined by regula falsi; under
// them the refit at a point and the bookkeeping of the lowest cost met,
// which stops the search when the caller wants to restart there. Internal
// to estimation/; ProfileLikelihoodIntervals is the entry.
class ProfileLikelihood {
 public:
  // The arguments of ProfileLikelihoodIntervals; every one must outlive the
  // search.
  ProfileLikelihood(ceres::Problem* problem, const ProfileOptions& options,
                    std::vector<double>* theta);
  ProfileLikelihood(const ProfileLikelihood&) = delete;
  ProfileLikelihood& operator=(const ProfileLikelihood&) = delete;

  // Runs the search once (ProfileLikelihoodIntervals).
  ProfileScan Run();

 private:
  // ---- per parameter
  // The interval of free parameter k; sets stopped_ if a refit met a lower
  // cost the caller restarts from.
  RatioInterval Parameter(int k);
  // The side `sign` (−1 low, +1 high) of parameter k_ into *interval; false
  // (the side left as it was) if the search stops at a lower cost.
  bool Side(double sign, RatioInterval* interval);

  // ---- one side, its solved points in xs_, rises_, points_
  // The profile at t, 2t, 4t and 8t standard deviations out to `bound`.
  void WalkOut(double sign, double bound);
  // Points just above the threshold once more from the point outside them.
  void RetryInward();
  // The furthest point still below the threshold (the hull of the
  // confidence set).
  size_t FurthestBelow() const;
  // Regula falsi between solved points j and j + 1 into *end; false if the
  // search stops at a lower cost.
  bool Refine(size_t j, double* end);

  // ---- a refit at a point
  // P(x) − cost* from `from` (solved at from_x) moved along the profile
  // direction to x; +∞ where the refit fails. The solved point in *solved.
  double RiseAt(double x, double from_x, const std::vector<double>& from,
                std::vector<double>* solved);
  // The constrained refit from `start`: its final cost, +∞ if unusable.
  // A start refitted before for this parameter gives the same end again,
  // from memory: a refit is a function of its start, and a retry's start
  // can be one already refitted (where the refits end where they began,
  // every solved point lies on the Gauss–Newton profile line, and the
  // retries from the estimate and from the outer point start at the same
  // point as the warm refit: on the paper job 8 of 58 refits).
  double Refit(const std::vector<double>& start);
  // P at x from solved point `warm`, retried from the estimate and from
  // solved point `outer` (−1: none), as ProfileLikelihoodIntervals says; the
  // lowest counts.
  double ProfileAt(double x, size_t warm, int outer, std::vector<double>* solved);
  // Refits at x from solved point `from`; keeps it in *rise, *solved if lower.
  void LowerFrom(double x, size_t from, double* rise, std::vector<double>* solved);
  bool NearThreshold(double rise) const;  // above, but within kRetry times it

  // ---- restart bookkeeping
  // A refit met a point the caller wants to restart from.
  bool MetLower() const;

  ceres::Problem* problem_;
  const ceres::Solver::Options& options_;
  EvaluationCounter* const counter_;
  const std::vector<double>& lower_;
  const std::vector<double>& upper_;
  const Eigen::MatrixXd& cov_theta_;
  const int n_free_;
  const double t975_;
  const double residual_variance_;
  const double lowest_allowed_;
  const bool stop_at_lower_;
  std::vector<double>* theta_;
  const std::function<void(int)>& on_parameter_;
  const int n_;                       // theta_->size()
  const std::vector<double> centre_;  // the estimate θ*

  ProfileScan scan_;
  double c0_ = 0.0;         // cost*
  double threshold_ = 0.0;  // ½·t²·s²
  bool stopped_ = false;

  // The parameter being profiled: its index, standard deviation (√C_kk),
  // dθ/dθ_k, and whether there is anything to refit (n > 1).
  int k_ = 0;
  double sd_ = 0.0;
  Eigen::VectorXd slope_;
  bool refit_ = false;
  // Solved profile points of the side being searched, the estimate first.
  std::vector<double> xs_, rises_;
  std::vector<std::vector<double>> points_;
  // The refits of the parameter being profiled (Refit): start, cost, end.
  struct RefitMemory {
    std::vector<double> start;
    double cost;
    std::vector<double> end;
  };
  std::vector<RefitMemory> refits_;
};

}  // namespace axis

#endif  // ESTIMATION_PROFILE_LIKELIHOOD_H_
