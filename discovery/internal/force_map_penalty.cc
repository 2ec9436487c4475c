#include "discovery/internal/force_map_penalty.h"

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "estimation/roughness_cost.h"
#include "estimation/stacked_jacobian.h"
#include "sim/dense_decompositions.h"
#include "sim/force_map.h"

namespace axis {

Eigen::MatrixXd PenaltyMatrix(const EstimationProblem& job, int n) {
  const ForceMap& f = job.model.structure.force_map;
  const int k = static_cast<int>(f.knots.size());
  std::vector<std::string> names;
  for (const FreeParameter& p : job.free) names.push_back(p.name);
  const Eigen::MatrixXd d = SecondDifferences(f.knots);
  const Eigen::MatrixXd c = ConfoundedComponents(f, names);
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(n, n);
  p.bottomRightCorner(k, k) =
      job.roughness.lambda * d.transpose() * d + job.roughness.anchor * c.transpose() * c;
  return p;
}

Penalised AtPenalty(const Eigen::VectorXd& r, const Eigen::MatrixXd& j, const Eigen::MatrixXd& p,
                    const Eigen::VectorXd& theta, bool step) {
  const Eigen::MatrixXd jtj = j.transpose() * j;
  Penalised out;
  out.inverse = CodPseudoInverse(jtj + p);
  out.edf = (out.inverse * jtj).trace();
  Eigen::VectorXd predicted = r;
  if (step) predicted -= j * (out.inverse * (j.transpose() * r + p * theta));
  out.chi2 = predicted.squaredNorm();
  return out;
}

Eigen::VectorXd ThetaOf(const EstimationProblem& job) {
  const ParameterMap map(job.model.params, job.free, job.ties);
  Eigen::VectorXd theta(map.num_free());
  for (int k = 0; k < map.num_free(); ++k) theta[k] = map.ToInternal(k, job.free[k].initial);
  return theta;
}

Assessment Assess(const EstimationProblem& job) {
  Eigen::VectorXd r;
  Eigen::MatrixXd j;
  StackedJacobian(job, &r, &j);
  const Penalised at =
      AtPenalty(r, j, PenaltyMatrix(job, static_cast<int>(j.cols())), ThetaOf(job), false);
  Assessment out;
  const double m = static_cast<double>(r.size());
  out.chi2 = at.chi2;
  out.edf = at.edf;
  out.bic = at.chi2 + at.edf * std::log(m);
  out.s2 = at.chi2 / std::max(1.0, m - at.edf);
  out.inverse = at.inverse;
  return out;
}

}  // namespace axis
