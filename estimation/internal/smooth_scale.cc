#include "estimation/internal/smooth_scale.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "estimation/cost_at.h"
#include "sim/dense_decompositions.h"

namespace axis {
namespace {

constexpr int kMaxPasses = 4;
constexpr double kScaleAgreement = 2.0;

}  // namespace

bool EstimateAtIntervalEnd(double value, double low, double high) {
  if (!(std::isfinite(value) && std::isfinite(low) && std::isfinite(high) && high > low)) {
    return false;
  }
  const double margin = kEndFraction * (high - low);
  return value - low <= margin || high - value <= margin;
}

bool ResidualsAt(ceres::Problem* problem, const std::vector<double>& point, int threads,
                 std::vector<double>* theta, Eigen::VectorXd* r) {
  std::copy(point.begin(), point.end(), theta->begin());
  double cost = 0.0;
  std::vector<double> residuals;
  if (!problem->Evaluate(EvaluateOn(threads), &cost, &residuals, nullptr, nullptr)) return false;
  *r = Eigen::Map<const Eigen::VectorXd>(residuals.data(),
                                         static_cast<Eigen::Index>(residuals.size()));
  return r->allFinite();
}

bool CentralDifferenceJacobian(ceres::Problem* problem, const std::vector<double>& centre,
                               const std::vector<double>& steps,
                               const std::vector<double>& lower,
                               const std::vector<double>& upper, EvaluationCounter* counter,
                               int threads, std::vector<double>* theta, Eigen::MatrixXd* j) {
  const int n = static_cast<int>(centre.size());
  const bool guard = counter->guard;
  counter->guard = false;
  bool ok = true;
  for (int k = 0; k < n && ok; ++k) {
    if (!(steps[k] > 0.0)) {
      ok = false;
      break;
    }
    std::vector<double> plus = centre, minus = centre;
    plus[k] = std::min(centre[k] + steps[k], upper[k]);
    minus[k] = std::max(centre[k] - steps[k], lower[k]);
    Eigen::VectorXd r_plus, r_minus;
    ok = plus[k] > minus[k] && ResidualsAt(problem, plus, threads, theta, &r_plus) &&
         ResidualsAt(problem, minus, threads, theta, &r_minus);
    if (!ok) break;
    if (k == 0) *j = Eigen::MatrixXd(r_plus.size(), n);
    j->col(k) = (r_plus - r_minus) / (plus[k] - minus[k]);
  }
  counter->guard = guard;
  std::copy(centre.begin(), centre.end(), theta->begin());
  return ok;
}

SmoothScale SmoothScaleCovariance(ceres::Problem* problem, const std::vector<double>& centre,
                                  const Eigen::MatrixXd& cov0, const std::vector<double>& lower,
                                  const std::vector<double>& upper, double s2,
                                  EvaluationCounter* counter, int threads,
                                  std::vector<double>* theta) {
  SmoothScale out;
  const int n = static_cast<int>(centre.size());
  const auto sd_steps = [&](const Eigen::MatrixXd& cov) {
    std::vector<double> steps(n);
    for (int k = 0; k < n; ++k) {
      const double sd = std::sqrt(cov(k, k));
      steps[k] = std::isfinite(sd) && sd > 0.0 ? sd : 1e-6 * (1.0 + std::abs(centre[k]));
    }
    return steps;
  };
  out.steps = sd_steps(cov0);
  const bool guard = counter->guard;
  counter->guard = false;
  const bool centre_ok = ResidualsAt(problem, centre, threads, theta, &out.residuals);
  counter->guard = guard;
  if (!centre_ok) return out;
  for (out.passes = 1; out.passes <= kMaxPasses; ++out.passes) {
    if (!CentralDifferenceJacobian(problem, centre, out.steps, lower, upper, counter, threads,
                                   theta, &out.jacobian)) {
      return out;
    }
    const Eigen::MatrixXd jtj = out.jacobian.transpose() * out.jacobian;
    out.cov = s2 * PseudoInverseOf(SymmetricEigenOf(jtj), 1e-14);
    const std::vector<double> next = sd_steps(out.cov);
    // Steps only grow: a standard deviation below half the step says the
    // cost is smooth at that step already (a central difference is exact
    // on a quadratic at any step), while shrinking the step towards a
    // smaller one walks back into the roughness (on the issue 42 records a
    // shrinking iteration ended at a sixth of the Gauss–Newton standard
    // error).
    bool agree = true;
    for (int k = 0; k < n; ++k) {
      if (next[k] > kScaleAgreement * out.steps[k]) {
        agree = false;
        out.steps[k] = next[k];
      }
    }
    out.ok = out.cov.allFinite();
    if (agree || out.passes == kMaxPasses) break;
  }
  return out;
}

}  // namespace axis
