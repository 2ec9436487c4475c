#include "estimation/covariance.h"

#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Dense>

#include "estimation/optimum_check.h"
#include "sim/dense_decompositions.h"

namespace axis {

Eigen::MatrixXd CovarianceOfTheta(ceres::Problem* problem, int n, int threads,
                                  Eigen::MatrixXd* jtj_out) {
  Eigen::MatrixXd out =
      Eigen::MatrixXd::Constant(n, n, std::numeric_limits<double>::quiet_NaN());
  // One evaluation of the Jacobian serves JᵀJ and the covariance (a
  // ceres::Covariance would evaluate it again: at the full loop's 10 µs a
  // Jacobian costs a second or more).
  DenseJacobian j;
  const bool evaluated = EvaluateDenseJacobian(problem, n, threads, &j);
  const Eigen::MatrixXd jtj = evaluated ? GaussNewtonOf(j) : Eigen::MatrixXd();
  if (jtj_out != nullptr) *jtj_out = jtj;
  // A Jacobian with non-finite entries (a hypersensitive full-loop record
  // whose sensitivities overflow only in some entries) crashed Eigen's SVD
  // inside ceres::Covariance (SIGSEGV in JacobiSVD::compute, a probe's Y
  // axis chirp at 500 Hz): no covariance then.
  if (!evaluated || !jtj.allFinite() || !j.allFinite()) return out;
  // ceres::Covariance's DENSE_SVD (covariance_impl.cc
  // ComputeCovarianceValuesUsingDenseSVD): the covariance V·S⁻²·Vᵀ from
  // J = U·S·Vᵀ; with a singular value below √kMinReciprocalCondition of the
  // largest, the pseudo-inverse over the singular values above it (Ceres:
  // null_space_rank −1 after 0 failed).
  return CovarianceOfJacobian(j);
}

Eigen::MatrixXd CovarianceOfJacobian(const Eigen::MatrixXd& j) {
  const Eigen::Index n = j.cols();
  Eigen::MatrixXd out =
      Eigen::MatrixXd::Constant(n, n, std::numeric_limits<double>::quiet_NaN());
  if (n == 0 || j.rows() == 0 || !j.allFinite()) return out;
  // Scaled to a largest entry of 1 (as Eigen's JacobiSVD does): no
  // underflow in the Householder norms of a uniformly tiny J.
  const double scale = j.cwiseAbs().maxCoeff();
  if (!(scale > 0.0)) return out;
  // The R-SVD: J = Q·R, then R = U_R·S·Vᵀ. Eigen's BDCSVD of the whole
  // row-major J took 36 s to compile in this file alone; a Jacobi SVD of
  // the small R is as accurate (it is Eigen's choice for small matrices).
  Eigen::MatrixXd small;
  if (j.rows() >= n) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(j / scale);
    small = qr.matrixQR().topRows(n).triangularView<Eigen::Upper>();
  } else {
    small = j / scale;
  }
  const Svd svd = SvdOf(small, false, true);
  const Eigen::VectorXd& singular = svd.singular_values;
  if (singular.size() == 0 || !(singular[0] > 0.0)) return out;
  const double min_ratio = std::sqrt(kMinReciprocalCondition);
  Eigen::VectorXd inverse_squared = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < singular.size(); ++i) {
    if (singular[i] / singular[0] < min_ratio) break;
    inverse_squared[i] = 1.0 / (singular[i] * singular[i]);
  }
  out = svd.v * inverse_squared.asDiagonal() * svd.v.transpose() / (scale * scale);
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
  const SymmetricEigen eig = SymmetricEigenOf(scaled);
  const double largest = eig.values.maxCoeff();
  for (int e = 0; e < n_free; ++e) {
    if (eig.values[e] > 1e-10 * largest) continue;
    for (int k = 0; k < n_free; ++k) {
      if (std::abs(eig.vectors(k, e)) > 0.1) out[k] = true;
    }
  }
  return out;
}

std::vector<bool> NullSpaceMembers(ceres::Problem* problem, int n_free, int threads) {
  Eigen::MatrixXd jtj;
  if (!GaussNewtonMatrix(problem, n_free, threads, &jtj)) {
    return std::vector<bool>(n_free, true);
  }
  return NullSpaceMembersOf(jtj, n_free);
}

}  // namespace axis
