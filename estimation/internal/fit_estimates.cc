#include "estimation/internal/fit_estimates.h"

#include <algorithm>
#include <iomanip>
#include <limits>

#include "estimation/experiment_cost.h"
#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"
#include "estimation/parameter_tie.h"

namespace axis {

void AppendFixedEstimates(AxisParams<double> fitted, Motion motion,
                          const std::vector<ParameterTie>& ties, FitResult* result) {
  for (const ParamInfo& info : ListParams()) {
    if (std::find(result->free_names.begin(), result->free_names.end(),
                  info.name) != result->free_names.end()) {
      continue;
    }
    if (info.name.find('.') != std::string::npos) continue;
    ParameterEstimate e;
    e.name = info.name;
    e.unit = ParamUnit(info.name, motion);
    e.value = *FindParam(&fitted, info.name);
    e.initial = e.value;
    e.free = false;
    e.std_error = e.ci95_low = e.ci95_high = e.std_error_gauss_newton =
        e.std_error_bootstrap = e.bootstrap_low = e.bootstrap_high =
            std::numeric_limits<double>::quiet_NaN();
    e.tied_to = TiedTo(ties, info.name);
    result->parameters.push_back(e);
  }
  CopyTiedUncertainty(result);
}

void AppendEstimates(const EstimationProblem& job, const ParameterMap& map,
                     const std::vector<double>& theta, FitResult* result) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k < map.num_free(); ++k) {
    ParameterEstimate e;
    e.name = job.free[k].name;
    e.unit = job.free[k].unit;
    e.value = map.FromInternal(k, theta[k]);
    e.initial = job.free[k].initial;
    e.free = true;
    e.std_error = e.std_error_gauss_newton = e.std_error_bootstrap = e.bootstrap_low =
        e.bootstrap_high = e.ci95_low = e.ci95_high = nan;
    e.determined = false;
    result->free_names.push_back(e.name);
    result->parameters.push_back(e);
  }
  AppendFixedEstimates(map.Apply(theta.data()), job.model.structure.motion, job.ties, result);
}

void ReportStageFailure(const EstimationProblem& job, const ParameterMap& map,
                        const std::vector<double>& theta, size_t start,
                        double horizon, const std::string& message,
                        const std::string& action, std::ostream* progress) {
  if (!job.solver.progress || progress == nullptr) return;
  *progress << "start " << std::setw(2) << start << "  horizon " << std::fixed
            << std::setprecision(3) << horizon << std::defaultfloat
            << " s  failed (" << message << ") at";
  for (int k = 0; k < map.num_free(); ++k) {
    *progress << " " << job.free[k].name << " = " << map.FromInternal(k, theta[k]);
  }
  *progress << "; " << action << "\n";
}

}  // namespace axis
