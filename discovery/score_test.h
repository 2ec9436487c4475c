// The score test of the discovery loop's candidates (discovery/discovery.h):
// a Lagrange-multiplier test that needs no refit per candidate. It projects
// the candidate's Jacobian column(s), taken at the value that switches the
// effect off, off the span of the free parameters' Jacobian and tests the
// residual against them (Breusch & Pagan 1980; Engle 1984, "Wald,
// likelihood ratio and Lagrange multiplier tests in econometrics", §5).
#ifndef DISCOVERY_SCORE_TEST_H_
#define DISCOVERY_SCORE_TEST_H_

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "discovery/candidates.h"
#include "discovery/score.h"
#include "estimation/estimation_problem.h"

namespace axis {

// Two candidates whose projected columns are nearly parallel (largest
// canonical cosine > 0.95). The residual may still prefer one: the
// conditional score statistic of a given b, chi2(a, b together) − chi2(b),
// tests what a explains beyond b (and vice versa); both below the critical
// value means this data cannot tell them apart.
struct ParallelPair {
  std::string a, b;
  double cosine = 0.0;
  double chi2_a_given_b = 0.0;  // dof of a
  double chi2_b_given_a = 0.0;  // dof of b
  bool separated = false;       // one of the two conditionals is significant
};

struct Ranking {
  std::vector<Score> scores;  // most significant first
  std::vector<ParallelPair> parallel;
  // The nearly parallel pairs that the residual does not separate.
  std::vector<std::pair<std::string, std::string>> indistinguishable;
};

// Ranks `candidates` by their score-test p-value at the job's current
// parameter values (job.model.params must hold the fitted values); where
// p-values underflow (chi2 beyond ~1400) by the logarithm of the p-value
// (LogChiSquaredSurvival), so that such candidates are still ordered.
// Pairs are checked for indistinguishability when one of them is
// significant at `alpha` / number of candidates. Throws std::runtime_error
// if a simulation at the current point fails.
Ranking RankCandidates(const EstimationProblem& job, const std::vector<Candidate>& candidates,
                       double alpha = 1e-3);

// Orthonormal basis (m × rank) of the columns of `a` (Eigen's
// ColPivHouseholderQR, rank threshold 1e-10; no columns if a is zero).
Eigen::MatrixXd Basis(const Eigen::MatrixXd& a);

}  // namespace axis

#endif  // DISCOVERY_SCORE_TEST_H_
