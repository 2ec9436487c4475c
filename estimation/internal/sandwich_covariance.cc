#include "estimation/internal/sandwich_covariance.h"

#include <stdexcept>
#include <string>

#include <Eigen/Dense>

#include "sim/dense_decompositions.h"

namespace axis {

Eigen::MatrixXd NeweyWestCovariance(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& r,
                                    const std::vector<int>& series, int lags) {
  const Eigen::Index m = jacobian.rows();
  if (r.size() != m) {
    throw std::invalid_argument("NeweyWestCovariance: expected " + std::to_string(m) +
                                " residuals (the Jacobian's rows), got " +
                                std::to_string(r.size()));
  }
  if (lags < 0) {
    throw std::invalid_argument("NeweyWestCovariance: expected lags >= 0, got " +
                                std::to_string(lags));
  }
  long total = 0;
  for (int len : series) {
    if (len < 0) {
      throw std::invalid_argument("NeweyWestCovariance: expected series lengths >= 0, got " +
                                  std::to_string(len));
    }
    total += len;
  }
  if (total != m) {
    throw std::invalid_argument("NeweyWestCovariance: expected series lengths summing to " +
                                std::to_string(m) + ", got " + std::to_string(total));
  }
  // g_t as the columns of G (n×m).
  const Eigen::MatrixXd g = (jacobian.array().colwise() * r.array()).matrix().transpose();
  Eigen::MatrixXd s = g * g.transpose();
  Eigen::Index begin = 0;
  for (int len : series) {
    for (int l = 1; l <= lags && l < len; ++l) {
      const double w = 1.0 - static_cast<double>(l) / (lags + 1);
      const Eigen::MatrixXd cross =
          g.middleCols(begin + l, len - l) * g.middleCols(begin, len - l).transpose();
      s += w * (cross + cross.transpose());
    }
    begin += len;
  }
  const Eigen::MatrixXd jtj = jacobian.transpose() * jacobian;
  const Eigen::MatrixXd bread = PseudoInverseOf(SymmetricEigenOf(jtj), 1e-14);
  return bread * s * bread;
}

}  // namespace axis
