#include "estimation/covariance.h"

#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Dense>

#include "estimation/optimum_check.h"

namespace axis {

Eigen::MatrixXd CovarianceOfTheta(ceres::Problem* problem, double* theta, int n,
                                  int threads, Eigen::MatrixXd* jtj_out) {
  Eigen::MatrixXd out =
      Eigen::MatrixXd::Constant(n, n, std::numeric_limits<double>::quiet_NaN());
  // A Jacobian with non-finite entries (a hypersensitive full-loop record
  // whose sensitivities overflow only in some entries) crashed Eigen's SVD
  // inside ceres::Covariance (SIGSEGV in JacobiSVD::compute, a probe's Y
  // axis chirp at 500 Hz): no covariance then.
  Eigen::MatrixXd jtj;
  const bool evaluated = GaussNewtonMatrix(problem, n, &jtj);
  if (jtj_out != nullptr) *jtj_out = evaluated ? jtj : Eigen::MatrixXd();
  if (!evaluated || !jtj.allFinite()) return out;
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  co.num_threads = threads;
  co.null_space_rank = 0;
  co.min_reciprocal_condition_number = 1e-14;
  const std::vector<std::pair<const double*, const double*>> pairs = {{theta, theta}};
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> c(n, n);
  ceres::Covariance covariance(co);
  if (covariance.Compute(pairs, problem)) {
    covariance.GetCovarianceBlock(theta, theta, c.data());
    out = c;
    return out;
  }
  // Rank deficient: the pseudo-inverse, with the null space dropped.
  co.null_space_rank = -1;
  ceres::Covariance pseudo(co);
  if (pseudo.Compute(pairs, problem)) {
    pseudo.GetCovarianceBlock(theta, theta, c.data());
    out = c;
  }
  return out;
}

std::vector<bool> NullSpaceMembersOf(const Eigen::MatrixXd& jtj, int n_free) {
  std::vector<bool> out(n_free, false);
  Eigen::VectorXd scale(n_free);
  for (int k = 0; k < n_free; ++k) {
    scale[k] = jtj(k, k) > 0.0 ? 1.0 / std::sqrt(jtj(k, k)) : 0.0;
    if (jtj(k, k) <= 0.0) out[k] = true;
  }
  const Eigen::MatrixXd scaled = scale.asDiagonal() * jtj * scale.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scaled);
  const double largest = eig.eigenvalues().maxCoeff();
  for (int e = 0; e < n_free; ++e) {
    if (eig.eigenvalues()[e] > 1e-10 * largest) continue;
    for (int k = 0; k < n_free; ++k) {
      if (std::abs(eig.eigenvectors()(k, e)) > 0.1) out[k] = true;
    }
  }
  return out;
}

std::vector<bool> NullSpaceMembers(ceres::Problem* problem, int n_free) {
  Eigen::MatrixXd jtj;
  if (!GaussNewtonMatrix(problem, n_free, &jtj)) {
    return std::vector<bool>(n_free, true);
  }
  return NullSpaceMembersOf(jtj, n_free);
}

}  // namespace axis
