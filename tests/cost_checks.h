// The Jet Jacobian of a fit cost (estimation/experiment_cost.h) against central
// differences, shared by the suites that check derivatives.
#ifndef TESTS_COST_CHECKS_H_
#define TESTS_COST_CHECKS_H_

#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include <ceres/ceres.h>

#include "estimation/experiment_cost.h"
#include "run/fit_job.h"

namespace axis {
namespace testing_files {

// Per column k of θ: ‖J_k − D_k‖ and ‖D_k‖ (D_k the central difference of the
// residuals with step h), and the gradient Jᵀr beside the central difference
// of the cost ½Σr². Throws std::runtime_error if an evaluation fails.
struct ColumnCheck {
  double error_norm = 0.0;
  double difference_norm = 0.0;
  double gradient = 0.0;
  double difference_gradient = 0.0;
};

inline std::vector<ColumnCheck> CheckJacobian(const ceres::CostFunction& cost,
                                              const std::vector<double>& theta,
                                              double h) {
  const int n = static_cast<int>(theta.size());
  const int m = cost.num_residuals();
  std::vector<double> r(m), jac(m * n), rp(m), rm(m);
  const double* params[] = {theta.data()};
  double* jacobians[] = {jac.data()};
  if (!cost.Evaluate(params, r.data(), jacobians)) throw std::runtime_error("Jacobian failed");
  std::vector<ColumnCheck> out(n);
  for (int k = 0; k < n; ++k) {
    std::vector<double> tp = theta, tm = theta;
    tp[k] += h;
    tm[k] -= h;
    const double* pp[] = {tp.data()};
    const double* pm[] = {tm.data()};
    if (!cost.Evaluate(pp, rp.data(), nullptr) || !cost.Evaluate(pm, rm.data(), nullptr)) {
      throw std::runtime_error("residuals failed");
    }
    double num = 0.0, den = 0.0, cost_p = 0.0, cost_m = 0.0;
    for (int i = 0; i < m; ++i) {
      const double fd = (rp[i] - rm[i]) / (2 * h);
      num += (jac[i * n + k] - fd) * (jac[i * n + k] - fd);
      den += fd * fd;
      cost_p += 0.5 * rp[i] * rp[i];
      cost_m += 0.5 * rm[i] * rm[i];
      out[k].gradient += r[i] * jac[i * n + k];
    }
    out[k].error_norm = std::sqrt(num);
    out[k].difference_norm = std::sqrt(den);
    out[k].difference_gradient = (cost_p - cost_m) / (2 * h);
  }
  return out;
}

// CheckJacobian for the cost of the job's first experiment at its initial
// values (θ in the optimised coordinates of estimation/experiment_cost.h).
inline std::vector<ColumnCheck> CheckJobJacobian(const FitJob& job, double step) {
  const ParameterMap map(job.problem.model.params, job.problem.free);
  EvaluationCounter counter;
  const int n = static_cast<int>(job.problem.free.size());
  std::unique_ptr<ceres::CostFunction> cost(ExperimentCost::Create(
      job.problem.model.structure, map, job.problem.experiments[0], n, -1, &counter));
  std::vector<double> theta;
  for (int k = 0; k < n; ++k) theta.push_back(map.ToInternal(k, job.problem.free[k].initial));
  return CheckJacobian(*cost, theta, step);
}

}  // namespace testing_files
}  // namespace axis

#endif  // TESTS_COST_CHECKS_H_
