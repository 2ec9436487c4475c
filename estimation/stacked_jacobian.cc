#include "estimation/stacked_jacobian.h"

#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include <ceres/ceres.h>

#include "common/concurrency.h"
#include "estimation/experiment_cost.h"
#include "estimation/estimation_problem.h"

namespace axis {

void StackedJacobian(const EstimationProblem& job, Eigen::VectorXd* r, Eigen::MatrixXd* jac) {
  const ParameterMap map(job.model.params, job.free, job.ties);
  const int n = map.num_free();
  std::vector<double> theta(n);
  for (int k = 0; k < n; ++k) theta[k] = map.ToInternal(k, job.free[k].initial);
  EvaluationCounter counter;
  const size_t count = job.experiments.size();
  std::vector<Eigen::VectorXd> rs(count);
  std::vector<Eigen::MatrixXd> js(count);
  ForEachConcurrently(count, job.solver.threads, [&](size_t k) {
    const FitExperiment& e = job.experiments[k];
    std::unique_ptr<ceres::CostFunction> cost(ExperimentCost::Create(
        job.model.structure, map, e, n, -1, &counter));
    const int me = cost->num_residuals();
    Eigen::VectorXd re(me);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> je(me, n);
    const double* params[] = {theta.data()};
    double* jacobians[] = {je.data()};
    if (!cost->Evaluate(params, re.data(), jacobians)) {
      throw std::runtime_error("experiment '" + e.name +
                               "': the simulation at the fitted parameters "
                               "failed; no score test possible");
    }
    rs[k] = std::move(re);
    js[k] = je;
  });
  int m = 0;
  for (const Eigen::VectorXd& re : rs) m += static_cast<int>(re.size());
  r->resize(m);
  jac->resize(m, n);
  int row = 0;
  for (size_t j = 0; j < rs.size(); ++j) {
    r->segment(row, rs[j].size()) = rs[j];
    jac->middleRows(row, rs[j].size()) = js[j];
    row += static_cast<int>(rs[j].size());
  }
}

}  // namespace axis
