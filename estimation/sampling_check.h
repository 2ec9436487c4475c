// Whether the accelerometer's records fit the other sampling convention of
// MODEL.md §6 better than the declared one at a fit's estimate: a record
// sampled at the instant read as period means (or the reverse) leaves a
// misfit that no plant effect explains and that random starts cannot
// lower (issue 42: s² = 9.6, eight random starts and 703 s for nothing,
// the warning naming everything but the cause). The fit's parameters
// absorb part of such a misfit, so the other convention is judged after a
// warm refit of its own (estimation/fit.h AsWarmRefit), not at the
// declared fit's estimate: on the committed misfit records
// (configs/jobs/misfit/period_mean.yaml) the other convention's χ² at that
// estimate was higher than the declared one's.
#ifndef ESTIMATION_SAMPLING_CHECK_H_
#define ESTIMATION_SAMPLING_CHECK_H_

#include <string>

#include "estimation/fit_result.h"
#include "job/fit_job.h"

namespace axis {

// The other convention's refit must lower the fit's Σ(r/σ)² by at least
// this fraction to be reported: both have the same parameters, so this is
// a BIC difference of a quarter of χ², far past any selection threshold on
// records of hundreds of samples, and at the noise (s² ≈ 1, the declared
// convention right) the other one fits worse, not better.
constexpr double kSamplingDropNote = 0.25;

struct SamplingCheck {
  bool ran = false;            // some fitted experiment fits channel `a`
  std::string declared;        // "period_mean" or "instant"
  std::string other;           // the other one
  double chi2_declared = 0.0;  // Σ(r/σ)² of the fit (2·FitResult::final_cost)
  double chi2_other = 0.0;     // the same after the refit under the other one
  int samples = 0;             // the samples of `a` the job fits
  std::string note;            // set when chi2_other < (1 − kSamplingDropNote)·chi2_declared
  // The refit under the other convention (Gauss–Newton intervals, no
  // optimum check): the discovery loop's base fit when it adopts that
  // convention (discovery/accelerometer_convention.h).
  FitResult refit;
};

// Refits `job` from the estimate of `result` (AtEstimate, AsWarmRefit:
// one Levenberg–Marquardt run on the whole record, Gauss–Newton
// covariance, no checks) with the other accelerometer convention
// (AxisStructure::accelerometer) and compares the two fits' Σ(r/σ)². `ran`
// is false when no fitted experiment fits `a`; a refit that ends without a
// finite cost leaves chi2_other NaN and no note. `result` must be a fit of
// `job`. Throws std::runtime_error if the model does not simulate at the
// estimate.
SamplingCheck CheckAccelerometerSampling(const FitJob& job, const FitResult& result);

}  // namespace axis

#endif  // ESTIMATION_SAMPLING_CHECK_H_
