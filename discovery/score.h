// The score test's figures for one candidate effect (discovery/score_test.h
// RankCandidates): its statistic, degrees of freedom and p-value, and the
// Gauss–Newton steps of its parameters that start its refit
// (discovery/candidates.h AddEffect).
#ifndef DISCOVERY_SCORE_H_
#define DISCOVERY_SCORE_H_

#include <string>
#include <vector>

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

}  // namespace axis

#endif  // DISCOVERY_SCORE_H_
