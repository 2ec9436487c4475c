#include "estimation/sampling_check.h"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "estimation/at_estimate.h"
#include "estimation/fit.h"

namespace axis {
namespace {

const char* ConventionName(AccelerometerSampling s) {
  return s == AccelerometerSampling::kInstant ? "instant" : "period_mean";
}

// The samples of channel `a` the job fits.
int SamplesOfA(const FitJob& job) {
  int samples = 0;
  for (const FitExperiment& e : job.experiments) {
    for (const FittedChannel& f : e.fitted) {
      if (f.channel == Channel::kA) samples += static_cast<int>(e.t.size());
    }
  }
  return samples;
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
  const AccelerometerSampling other =
      at.model.structure.accelerometer == AccelerometerSampling::kInstant
          ? AccelerometerSampling::kPeriodMean
          : AccelerometerSampling::kInstant;
  check.declared = ConventionName(at.model.structure.accelerometer);
  check.other = ConventionName(other);
  check.samples = SamplesOfA(at);
  check.chi2_declared = 2.0 * result.final_cost;
  FitJob refit = at;
  refit.model.structure.accelerometer = other;
  AsWarmRefit(&refit);
  refit.solver.progress = false;
  check.refit = FitParameters(refit, nullptr);
  check.chi2_other = 2.0 * check.refit.final_cost;
  if (!std::isfinite(check.chi2_other) || !std::isfinite(check.chi2_declared)) {
    check.chi2_other = std::numeric_limits<double>::quiet_NaN();
    return check;
  }
  if (check.chi2_other < (1.0 - kSamplingDropNote) * check.chi2_declared) {
    std::ostringstream note;
    note << std::setprecision(4) << "the accelerometer's records fit 'accelerometer: "
         << check.other << "' better than the declared '" << check.declared
         << "' (the fit's sum of (r/sigma)^2 " << check.chi2_declared << " -> "
         << check.chi2_other << " refitted under '" << check.other << "'; " << check.samples
         << " samples of a): the misfit is the sampling convention's, not a wrong minimum; declare "
            "it in the model config (MODEL.md section 6) or the job's configuration, and fit "
            "again";
    check.note = note.str();
  }
  return check;
}

}  // namespace axis
