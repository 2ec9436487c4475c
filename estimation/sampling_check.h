// Whether the accelerometer's records fit the other sampling convention of
// MODEL.md §6 better than the declared one at a fit's estimate: a record
// sampled at the instant read as period means (or the reverse) leaves a
// misfit that no plant effect explains and that random starts cannot
// lower (issue 42: s² = 9.6, eight random starts and 703 s for nothing,
// the warning naming everything but the cause). One simulation of each
// experiment that fits channel `a` under the other convention tells.
#ifndef ESTIMATION_SAMPLING_CHECK_H_
#define ESTIMATION_SAMPLING_CHECK_H_

#include <string>

#include "estimation/fit_result.h"
#include "job/fit_job.h"

namespace axis {

// The other convention must lower Σ(r/σ)² of channel `a` by at least this
// fraction to be reported: at the noise (s² ≈ 1) the two conventions differ
// by a fraction of that (they agree to O(T_o²·y1''') on smooth motion), so a
// drop of a quarter is the sampling's and not chance.
constexpr double kSamplingDropNote = 0.25;

struct SamplingCheck {
  bool ran = false;            // some fitted experiment fits channel `a`
  std::string declared;        // "period_mean" or "instant"
  std::string other;           // the other one
  double chi2_declared = 0.0;  // Σ(r/σ)² of `a` over the fitted experiments
  double chi2_other = 0.0;     // the same at the same parameters, other convention
  int samples = 0;             // the samples of `a` in those sums
  std::string note;            // set when chi2_other < (1 − kSamplingDropNote)·chi2_declared
};

// Evaluates channel `a` of the job's fitted experiments at the estimate of
// `result` (AtEstimate) under the declared and the other accelerometer
// convention (AxisStructure::accelerometer). `ran` is false when no fitted
// experiment fits `a`; a simulation that fails leaves chi2_other NaN and no
// note. Never throws for a job FitParameters accepted.
SamplingCheck CheckAccelerometerSampling(const FitJob& job, const FitResult& result);

}  // namespace axis

#endif  // ESTIMATION_SAMPLING_CHECK_H_
