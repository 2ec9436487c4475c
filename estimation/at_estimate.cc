#include "estimation/at_estimate.h"

#include <algorithm>

#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"

namespace axis {

void SetArmState(const std::array<double, 2>& y, double r_g, FitExperiment* e) {
  e->initial_state[0] = y[0];
  e->initial_state[1] = y[1];
  e->initial_state[2] = y[0] / r_g;
  e->initial_state[3] = y[1] / r_g;
}

void ApplyEstimates(const FitResult& result, EstimationProblem* job) {
  for (FreeParameter& f : job->free) {
    for (const ParameterEstimate& e : result.parameters) {
      if (e.free && e.name == f.name) {
        f.initial = std::clamp(e.value, f.lower, f.upper);
        *FindParam(&job->model.params, f.name) = e.value;
      }
    }
  }
  ApplyTies(TieIndices(job->ties), &job->model.params);
  if (result.initial_states.size() != job->experiments.size()) return;  // no estimate
  for (size_t j = 0; j < job->experiments.size(); ++j) {
    FitExperiment& e = job->experiments[j];
    if (e.estimate_initial_state) SetArmState(result.initial_states[j], job->model.params.r_g, &e);
  }
}

EstimationProblem AtEstimate(const EstimationProblem& job, const FitResult& result) {
  EstimationProblem out = job;
  ApplyEstimates(result, &out);
  return out;
}

}  // namespace axis
