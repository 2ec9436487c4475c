#include "estimation/roughness_cost.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "estimation/experiment_cost.h"
#include "estimation/estimation_problem.h"

namespace axis {

Eigen::MatrixXd SecondDifferences(const std::vector<double>& knots) {
  const int n = static_cast<int>(knots.size());
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(std::max(0, n - 2), n);
  if (n < 3) return d;
  const double mean_h = (knots.back() - knots.front()) / (n - 1);
  for (int j = 1; j + 1 < n; ++j) {
    const double h0 = knots[j] - knots[j - 1];
    const double h1 = knots[j + 1] - knots[j];
    const double scale = 2.0 * mean_h * mean_h / (h0 + h1);
    d(j - 1, j - 1) = scale / h0;
    d(j - 1, j) = -scale * (1.0 / h0 + 1.0 / h1);
    d(j - 1, j + 1) = scale / h1;
  }
  return d;
}

Eigen::MatrixXd ConfoundedComponents(const ForceMap& f, const std::vector<std::string>& free_names) {
  const auto is_free = [&](const char* name) {
    return std::find(free_names.begin(), free_names.end(), name) != free_names.end();
  };
  const int n = static_cast<int>(f.knots.size());
  bool constant = false, slope = false;
  if (f.variable == ForceMapVariable::kV) {
    constant = is_free("F_0");
    slope = is_free("B_a");
  } else if (f.friction) {
    constant = is_free("F_c");
  } else {
    constant = is_free("F_0") || is_free("x_0");
    slope = is_free("k_x");
  }
  Eigen::MatrixXd c(int(constant) + int(slope), n);
  int row = 0;
  if (constant) c.row(row++).setConstant(1.0 / std::sqrt(static_cast<double>(n)));
  if (slope && n > 0) {
    const Eigen::Map<const Eigen::VectorXd> t(f.knots.data(), n);
    const Eigen::VectorXd centred = t.array() - t.mean();
    c.row(row++) = centred.transpose() / centred.norm();
  }
  return c;
}

ceres::CostFunction* RoughnessCost::Create(const ForceMap& f, const ParameterMap& map,
                                           int theta_size, double lambda, double anchor) {
  if (!f.enabled || !(lambda > 0.0 || anchor > 0.0) || f.knots.size() < 3) return nullptr;
  const int n = static_cast<int>(f.knots.size());
  std::vector<int> index(n, -1);
  std::vector<double> fixed(n, 0.0);
  bool any = false;
  for (int k = 0; k < n; ++k) {
    fixed[k] = map.base().f_map[k];
    const std::string name = "f_map." + std::to_string(k);
    for (int j = 0; j < map.num_free(); ++j) {
      if (map.free()[j].name == name) {
        index[k] = j;
        any = true;
      }
    }
  }
  if (!any) return nullptr;
  std::vector<std::string> names;
  for (const FreeParameter& p : map.free()) names.push_back(p.name);
  const Eigen::MatrixXd d = SecondDifferences(f.knots);
  const Eigen::MatrixXd c = ConfoundedComponents(f, names);
  Eigen::MatrixXd rows(d.rows() + c.rows(), n);
  rows << std::sqrt(std::max(0.0, lambda)) * d, std::sqrt(std::max(0.0, anchor)) * c;
  return new RoughnessCost(rows, index, fixed, map, theta_size);
}

RoughnessCost::RoughnessCost(const Eigen::MatrixXd& scaled_d, std::vector<int> theta_index,
                             std::vector<double> fixed, const ParameterMap& map, int theta_size)
    : d_(scaled_d),
      theta_index_(std::move(theta_index)),
      fixed_(std::move(fixed)),
      map_(map),
      theta_size_(theta_size) {
  set_num_residuals(static_cast<int>(d_.rows()));
  mutable_parameter_block_sizes()->push_back(theta_size);
}

bool RoughnessCost::Evaluate(double const* const* parameters, double* residuals,
                             double** jacobians) const {
  const double* theta = parameters[0];
  const int n = static_cast<int>(theta_index_.size());
  Eigen::VectorXd f(n);
  for (int k = 0; k < n; ++k) {
    f[k] = theta_index_[k] >= 0 ? map_.FromInternal(theta_index_[k], theta[theta_index_[k]])
                                : fixed_[k];
  }
  Eigen::Map<Eigen::VectorXd>(residuals, d_.rows()) = d_ * f;
  if (jacobians != nullptr && jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> jac(
        jacobians[0], d_.rows(), theta_size_);
    jac.setZero();
    for (int k = 0; k < n; ++k) {
      const int j = theta_index_[k];
      if (j >= 0) jac.col(j) = d_.col(k) * map_.Derivative(j, theta[j]);
    }
  }
  return residuals == nullptr || Eigen::Map<Eigen::VectorXd>(residuals, d_.rows()).allFinite();
}

}  // namespace axis
