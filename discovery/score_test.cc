#include "discovery/score_test.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "common/statistics.h"
#include "estimation/stacked_jacobian.h"
#include "sim/dense_decompositions.h"

namespace axis {

Eigen::MatrixXd Basis(const Eigen::MatrixXd& a) {
  return ColumnSpaceBasis(a, 1e-10);
}

Ranking RankCandidates(const EstimationProblem& job, const std::vector<Candidate>& candidates,
                       double alpha) {
  Eigen::VectorXd r;
  Eigen::MatrixXd jf;
  StackedJacobian(job, &r, &jf);
  const int m = static_cast<int>(r.size());
  const int n = static_cast<int>(jf.cols());
  const Eigen::MatrixXd q = Basis(jf);
  // Residuals are divided by the declared σ: under the null hypothesis (the
  // model without the candidate, right noise levels) they have unit
  // variance, so the statistic uses s² = 1, not the residual variance, which
  // a misfit inflates and which would deflate every candidate alike.
  const double s2 = 1.0;
  (void)n;
  Ranking ranking;
  std::vector<Eigen::MatrixXd> bases;
  for (const Candidate& c : candidates) {
    Eigen::MatrixXd jc = CandidateColumns(job, c, m);
    jc -= q * (q.transpose() * jc);  // off the span of the free parameters
    Score s;
    s.name = c.name;
    s.dof = static_cast<int>(jc.cols());
    const Eigen::MatrixXd info = jc.transpose() * jc;
    const Eigen::VectorXd g = jc.transpose() * r;
    const Eigen::VectorXd solved = SvdSolve(info, g, 1e-12);
    s.chi2 = g.dot(solved) / s2;
    s.p_value = ChiSquaredSurvival(s.chi2, s.dof);
    s.step.resize(s.dof);
    for (int k = 0; k < s.dof; ++k) s.step[k] = -solved[k];
    s.single_step.resize(s.dof);
    for (int k = 0; k < s.dof; ++k) {
      s.single_step[k] = info(k, k) > 0.0 ? -g[k] / info(k, k) : 0.0;
    }
    ranking.scores.push_back(s);
    bases.push_back(Basis(jc));
  }
  const double threshold = alpha / std::max<size_t>(1, candidates.size());
  const auto projected_chi2 = [&](const Eigen::MatrixXd& basis) {
    return (basis.transpose() * r).squaredNorm() / s2;
  };
  for (size_t a = 0; a < candidates.size(); ++a) {
    for (size_t b = a + 1; b < candidates.size(); ++b) {
      if (bases[a].cols() == 0 || bases[b].cols() == 0) continue;
      if (ranking.scores[a].p_value >= threshold && ranking.scores[b].p_value >= threshold) continue;
      const Eigen::MatrixXd cross = bases[a].transpose() * bases[b];
      const double cosine = SvdOf(cross, false, false).singular_values[0];
      if (!(cosine > 0.95)) continue;
      Eigen::MatrixXd both(m, bases[a].cols() + bases[b].cols());
      both << bases[a], bases[b];
      const double joint = projected_chi2(Basis(both));
      ParallelPair pair;
      pair.a = candidates[a].name;
      pair.b = candidates[b].name;
      pair.cosine = cosine;
      pair.chi2_a_given_b = std::max(0.0, joint - projected_chi2(bases[b]));
      pair.chi2_b_given_a = std::max(0.0, joint - projected_chi2(bases[a]));
      pair.separated =
          ChiSquaredSurvival(pair.chi2_a_given_b, ranking.scores[a].dof) < threshold ||
          ChiSquaredSurvival(pair.chi2_b_given_a, ranking.scores[b].dof) < threshold;
      ranking.parallel.push_back(pair);
      if (!pair.separated) ranking.indistinguishable.emplace_back(pair.a, pair.b);
    }
  }
  for (Score& x : ranking.scores) x.log_p_value = LogChiSquaredSurvival(x.chi2, x.dof);
  std::stable_sort(ranking.scores.begin(), ranking.scores.end(),
                   [](const Score& x, const Score& y) {
                     if (x.log_p_value != y.log_p_value) return x.log_p_value < y.log_p_value;
                     return x.chi2 / x.dof > y.chi2 / y.dof;
                   });
  return ranking;
}

}  // namespace axis
