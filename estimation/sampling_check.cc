#include "estimation/sampling_check.h"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "estimation/at_estimate.h"
#include "estimation/evaluate_experiment.h"

namespace axis {
namespace {

const char* ConventionName(AccelerometerSampling s) {
  return s == AccelerometerSampling::kInstant ? "instant" : "period_mean";
}

// Σ(r/σ)² of the fitted channel `a` over the job's fitted experiments under
// `structure`; adds the samples to *samples.
double ChiSquaredOfA(const FitJob& job, const AxisStructure& structure, int* samples) {
  double chi2 = 0.0;
  for (const FitExperiment& e : job.experiments) {
    const ExperimentFit fit = EvaluateExperiment(structure, job.model.params, e);
    for (const ChannelFit& c : fit.channels) {
      if (c.channel != "a" || !c.fitted || !(c.sigma > 0.0)) continue;
      const double n = static_cast<double>(c.measured.size());
      chi2 += n * (c.rms / c.sigma) * (c.rms / c.sigma);
      if (samples != nullptr) *samples += static_cast<int>(c.measured.size());
    }
  }
  return chi2;
}

}  // namespace

SamplingCheck CheckAccelerometerSampling(const FitJob& job, const FitResult& result) {
  SamplingCheck check;
  bool fits_a = false;
  for (const FitExperiment& e : job.experiments) {
    for (const FittedChannel& f : e.fitted) fits_a = fits_a || f.channel == Channel::kA;
  }
  if (!fits_a) return check;
  check.ran = true;
  const FitJob at = AtEstimate(job, result);
  AxisStructure other = at.model.structure;
  other.accelerometer = other.accelerometer == AccelerometerSampling::kInstant
                            ? AccelerometerSampling::kPeriodMean
                            : AccelerometerSampling::kInstant;
  check.declared = ConventionName(at.model.structure.accelerometer);
  check.other = ConventionName(other.accelerometer);
  check.chi2_declared = ChiSquaredOfA(at, at.model.structure, &check.samples);
  check.chi2_other = ChiSquaredOfA(at, other, nullptr);
  if (!std::isfinite(check.chi2_other)) {
    check.chi2_other = std::numeric_limits<double>::quiet_NaN();
    return check;
  }
  if (check.chi2_other < (1.0 - kSamplingDropNote) * check.chi2_declared) {
    std::ostringstream note;
    note << std::setprecision(4) << "the accelerometer's records fit 'accelerometer: "
         << check.other << "' better than the declared '" << check.declared
         << "' at this estimate (sum of (r/sigma)^2 on a: " << check.chi2_declared << " -> "
         << check.chi2_other << " over " << check.samples
         << " samples): the misfit is the sampling convention's, not a wrong minimum; declare "
            "it in the model config (MODEL.md section 6) or the job's configuration, and fit "
            "again";
    check.note = note.str();
  }
  return check;
}

}  // namespace axis
