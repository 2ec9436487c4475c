#include "estimation/optimum_check.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

#include <Eigen/Dense>

#include "estimation/cost_at.h"
#include "estimation/experiment_cost.h"
#include "sim/dense_decompositions.h"

namespace axis {

bool EvaluateDenseJacobian(ceres::Problem* problem, int n, int threads, DenseJacobian* j) {
  ceres::CRSMatrix crs;
  double cost = 0.0;
  if (!problem->Evaluate(EvaluateOn(threads), &cost, nullptr, nullptr, &crs)) {
    return false;
  }
  *j = DenseJacobian::Zero(crs.num_rows, n);
  for (int row = 0; row < crs.num_rows; ++row) {
    for (int a = crs.rows[row]; a < crs.rows[row + 1]; ++a) {
      if (crs.cols[a] < n) (*j)(row, crs.cols[a]) = crs.values[a];
    }
  }
  return true;
}

Eigen::MatrixXd GaussNewtonOf(const DenseJacobian& j) {
  const Eigen::Index n = j.cols();
  Eigen::MatrixXd jtj = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index row = 0; row < j.rows(); ++row) {
    for (Eigen::Index a = 0; a < n; ++a) {
      for (Eigen::Index b = 0; b < n; ++b) jtj(a, b) += j(row, a) * j(row, b);
    }
  }
  return jtj;
}

bool GaussNewtonMatrix(ceres::Problem* problem, int n, int threads, Eigen::MatrixXd* jtj) {
  DenseJacobian j;
  if (!EvaluateDenseJacobian(problem, n, threads, &j)) return false;
  *jtj = GaussNewtonOf(j);
  return true;
}

double CostResolution(double cost, double function_tolerance) {
  return std::max(kLowerRelative, function_tolerance) * std::abs(cost) + kLowerAbsolute;
}

double LowerThan(double cost, double relative) {
  return cost - CostResolution(cost, relative);
}

ProbeRoundResult ProbeRound(ceres::Problem* problem, const std::vector<double>& lower,
                            const std::vector<double>& upper,
                            const std::vector<double>& last_step, double cost,
                            EvaluationCounter* counter, int threads,
                            std::vector<double>* theta) {
  const int n = static_cast<int>(theta->size());
  const std::vector<double> centre = *theta;
  ProbeRoundResult result;
  result.best = centre;
  result.best_cost = cost;
  Eigen::MatrixXd jtj;
  if (!GaussNewtonMatrix(problem, n, threads, &jtj)) return result;
  std::vector<Eigen::VectorXd> directions;
  const SymmetricEigen eig = SymmetricEigenOf(jtj);
  const double largest = eig.values.maxCoeff();
  const Eigen::MatrixXd cov = PseudoInverseOf(eig, 1e-14);
  for (int k = 0; k < n; ++k) {
    if (cov(k, k) <= 0.0) continue;
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    d[k] = std::sqrt(cov(k, k));
    directions.push_back(d);
  }
  const size_t first_principal = directions.size();
  for (int e = 0; e < n; ++e) {
    const double l = eig.values[e];
    if (l > 1e-14 * largest) directions.push_back(eig.vectors.col(e) / std::sqrt(l));
  }
  const size_t end_principal = directions.size();
  Eigen::VectorXd step = Eigen::Map<const Eigen::VectorXd>(last_step.data(), n);
  const double curvature = step.dot(jtj * step);
  if (curvature > 0.0) directions.push_back(step / std::sqrt(curvature));
  struct LowerPoint {
    double cost;
    double scale;
    std::vector<double> point;
  };
  std::vector<LowerPoint> lower_points;
  // The largest scale (from 1 up) at which every principal-axis probe so far
  // agreed with the quadratic; the scales are visited in increasing order.
  constexpr double kScales[] = {0.01, 0.3, 1.0, 3.0, 10.0};
  double reach = kScales[std::size(kScales) - 1];
  {
    const ScopedGuardOff off(counter);  // the probes in double
    for (size_t i = 0; i < directions.size(); ++i) {
      const Eigen::VectorXd& d = directions[i];
      const bool principal = i >= first_principal && i < end_principal;
      for (size_t j = 0; j < std::size(kScales); ++j) {
        const double s = kScales[j];
        for (double sign : {-1.0, 1.0}) {
          std::vector<double> point = centre;
          bool clipped = false;
          for (int k = 0; k < n; ++k) {
            const double x = centre[k] + sign * s * d[k];
            point[k] = std::clamp(x, lower[k], upper[k]);
            clipped = clipped || point[k] != x;
          }
          const double c = CostAt(problem, point, threads, theta);
          ++result.probes;
          if (c < cost) lower_points.push_back({c, s, point});
          const double expected = 0.5 * s * s;
          if (principal && s >= 1.0 && s <= reach &&
              (clipped || !(std::abs(c - cost - expected) <= kQuadraticAgreement * expected))) {
            reach = j > 0 && kScales[j - 1] >= 1.0 ? kScales[j - 1] : 0.0;
          }
        }
      }
    }
  }
  // The lowest point that passes the guard (the same cost, by the same
  // arithmetic, when it passes).
  // By cost, ties by the point (as the pairs were sorted before the scale
  // was kept).
  std::sort(lower_points.begin(), lower_points.end(),
            [](const LowerPoint& a, const LowerPoint& b) {
              return a.cost != b.cost ? a.cost < b.cost : a.point < b.point;
            });
  for (const LowerPoint& p : lower_points) {
    if (std::isfinite(CostAt(problem, p.point, threads, theta))) {
      result.best_cost = p.cost;
      result.best = p.point;
      result.lowest_scale = p.scale;
      break;
    }
  }
  result.quadratic_reach = end_principal > first_principal ? reach : 0.0;
  std::copy(centre.begin(), centre.end(), theta->begin());
  return result;
}

}  // namespace axis
