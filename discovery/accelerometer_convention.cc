#include "discovery/accelerometer_convention.h"

#include <cmath>

#include "discovery/channel_changes.h"

namespace axis {

std::optional<DiscoveryStep> AdoptAccelerometerConvention(const SamplingCheck& check,
                                                          FitJob* job, FitResult* result) {
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

}  // namespace axis
