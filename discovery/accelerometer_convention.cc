#include "discovery/accelerometer_convention.h"

#include <cmath>

#include "discovery/channel_changes.h"

namespace axis {

std::optional<DiscoveryStep> AdoptAccelerometerConvention(const SamplingCheck& check,
                                                          EstimationProblem* job, FitResult* result) {
  if (check.note.empty() || !std::isfinite(check.refit.final_cost) ||
      !(check.refit.bic < result->bic)) {
    return std::nullopt;
  }
  DiscoveryStep step;
  step.effect = "accelerometer." + check.other;
  step.chi2 = check.chi2_declared - check.chi2_other;
  step.dof = 0;
  step.p_value = 0.0;
  step.bic_before = result->bic;
  step.bic_after = check.refit.bic;
  step.kept = true;
  step.rule = "the sampling check's refit under '" + check.other +
              "' (the same parameters: the BIC falls by the drop in chi2; MODEL.md section 6)";
  step.channels = ChannelChanges(*result, check.refit);
  for (const FitPhase& f : check.refit.phases) step.seconds += f.seconds;
  job->model.structure.accelerometer = check.other == "instant"
                                           ? AccelerometerSampling::kInstant
                                           : AccelerometerSampling::kPeriodMean;
  *result = check.refit;
  return step;
}

bool IsConventionStep(const std::string& name) { return name.rfind("accelerometer.", 0) == 0; }

void PrependConventionStep(const DiscoveryStep& step, DiscoveryReport* report) {
  report->steps.insert(report->steps.begin(), step);
  report->selected.insert(report->selected.begin(), step.effect);
}

DiscoveryReport JoinSecondPass(DiscoveryReport first, const DiscoveryStep& convention,
                               DiscoveryReport second,
                               const std::vector<DiscoveryStep>& between) {
  DiscoveryReport out = std::move(second);
  first.steps.push_back(convention);
  first.steps.insert(first.steps.end(), between.begin(), between.end());
  out.steps.insert(out.steps.begin(), first.steps.begin(), first.steps.end());
  first.selected.push_back(convention.effect);
  out.selected.insert(out.selected.begin(), first.selected.begin(), first.selected.end());
  out.removed.insert(out.removed.begin(), first.removed.begin(), first.removed.end());
  out.base_fit_seconds += first.base_fit_seconds;
  out.score_seconds += first.score_seconds;
  out.score_rankings += first.score_rankings;
  return out;
}

}  // namespace axis
