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
#include "job/fit_job.h"

namespace axis {

// Score test of one candidate at the current fit.
struct Score {
  std::string name;
  double chi2 = 0.0;   // rᵀJ⊥(J⊥ᵀJ⊥)⁻¹J⊥ᵀr / s², s² the residual variance
  int dof = 0;         // number of columns
  double p_value = 1.0;
  double log_p_value = 0.0;  // natural log; finite where p_value is 0
  std::vector<double> step;  // Gauss–Newton step of the columns' parameters
  // The step of each column alone (−gₖ/Iₖₖ: the others held at zero), a
  // start for a refit from one column's shape (Stribeck: one per v_st of
  // the grid, where the joint step of nearly parallel columns can be far
  // larger than any of them).
  std::vector<double> single_step;
};

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
Ranking RankCandidates(const FitJob& job, const std::vector<Candidate>& candidates,
                       double alpha = 1e-3);

// Orthonormal basis (m × rank) of the columns of `a` (Eigen's
// ColPivHouseholderQR, rank threshold 1e-10; no columns if a is zero).
Eigen::MatrixXd Basis(const Eigen::MatrixXd& a);

}  // namespace axis

#endif  // DISCOVERY_SCORE_TEST_H_
