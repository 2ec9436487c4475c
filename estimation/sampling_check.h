// Whether the accelerometer's records fit the other sampling convention of
// MODEL.md §6 better than the declared one at a fit's estimate: a record
// sampled at the instant read as period means (or the reverse) leaves a
// misfit that no plant effect explains and that random starts cannot
// lower (issue 42: s² = 9.6, eight random starts and 703 s for nothing,
// the warning naming everything but the cause). The fit's parameters
// absorb part of such a misfit, so each convention is judged after a warm
// refit of its own (estimation/fit.h AsWarmRefit), not at the declared
// fit's estimate (on the committed misfit records,
// configs/jobs/misfit/period_mean.yaml, the other convention's χ² at that
// estimate was the higher). And a skew of `a` against the other channels
// makes the declared convention look worse than it is (a period mean is
// an instant sample delayed by half a period and averaged: on period-mean
// records with `a` 0.2 ms early the instant convention won without
// delays), and so did a skew of the tachometer against `a` (0.3 ms: a
// delay on `a` alone left most of χ² to it), so both refits free a delay
// on every fitted channel.
#ifndef ESTIMATION_SAMPLING_CHECK_H_
#define ESTIMATION_SAMPLING_CHECK_H_

#include <string>

#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"

namespace axis {

// The other convention's refit must lower Σ(r/σ)² below the declared
// one's (both with a free delay on every fitted channel) by more than this, times
// max(1, s²) of the declared refit, to be reported. Both have the same
// parameters, so Δχ² is their BIC difference, and 10 is the "very strong"
// evidence of Kass & Raftery (1995, J. Am. Stat. Assoc. 90, 773–795:
// 2 ln B > 10); s² widens it under a misfit of another kind. A delay
// absorbs most of the difference between the conventions (a 1 s step:
// 11346 → 2131 for the wrong one, about 2000 for the right one), so a
// relative margin would miss them.
constexpr double kSamplingBicMargin = 10.0;

// ...and by more than this share of the declared refit's excess χ² over its
// degrees of freedom: under a large misfit of another kind the two
// conventions differ by a sliver of it (a friction patch the library
// lacks, s² = 88: Δχ² 1.0e3 of 1.05e6), which is no sampling convention's;
// where the convention is the misfit it removes most of the excess (the
// committed misfit records: 5.6e3 of 6.3e3).
constexpr double kSamplingExcessShare = 0.25;

// How CheckAccelerometerSampling decides for the other convention.
enum class SamplingRule {
  // Its refit with a free delay on every fitted channel lowers Σ(r/σ)²
  // below the declared one's past kSamplingBicMargin·max(1, s²) and
  // kSamplingExcessShare of the excess: the convention as the declared
  // model's misfit (the check after the declared model's fit).
  kMisfit,
  // The lower BIC of its two refits (as the job stands, and with a free
  // delay on every fitted channel) is below the lower of the declared
  // one's (the job's own fit, and its refit with the delays) by more than
  // kSamplingBicMargin·max(1, s²): the convention as a candidate of the
  // discovery loop, judged by BIC against the delays that could stand in
  // for it, for a model whose loop already kept a filter or a delay on `a`
  // (a period mean is a box filter and a half-period delay of instant
  // samples: with a filter kept, the two conventions differ by a sliver of
  // the excess, which kMisfit's share does not see). The job's own fit is
  // `result`, so its BIC is result.bic. Where the job fits a delay on `a`,
  // the other convention's refit without it counts too (one entry fewer):
  // the discovery loop drops that delay after adopting the convention if
  // it is then insignificant.
  kBestBic,
};

struct SamplingCheck {
  bool ran = false;            // some fitted experiment fits channel `a`
  // With kMisfit: the fit as it stands explains the records to their noise
  // (Σ(r/σ)² − dof at most 3·√(2·dof), three standard deviations of χ²):
  // there is no misfit for the other convention to explain, and no refit
  // was run (the delays' and the other convention's χ² are NaN).
  bool explained = false;
  std::string declared;        // "period_mean" or "instant"
  std::string other;           // the other one
  double chi2_declared = 0.0;  // Σ(r/σ)² of the fit (2·FitResult::final_cost)
  // Σ(r/σ)² of the refits under the declared and the other convention, each
  // with a free delay on every fitted channel (sensor_delay.<channel> from
  // 0 within ± the longest output period; the job's own where it has one):
  // what decides. Where the other one wins, the declared one is refitted
  // again from the other's optimum and the lower of its two is kept (a
  // model far off can find a lower minimum under either convention).
  double chi2_declared_delay = 0.0;
  double chi2_other_delay = 0.0;
  // Σ(r/σ)² of the refit under the other convention as the job stands
  // (`refit`); computed only when the note is set (with kBestBic always),
  // else NaN.
  double chi2_other = 0.0;
  // With kBestBic and a fitted delay on `a` in the job: Σ(r/σ)² of the
  // other convention's refit without it (the half-period delay between the
  // conventions is what a kept delay on `a` may stand for, so under the
  // other one it may not be needed); NaN otherwise.
  double chi2_other_without_delay_a = 0.0;
  SamplingRule rule = SamplingRule::kMisfit;  // what decided
  // With kBestBic: the lower BIC of each convention's refits
  // (Σ(r/σ)² + fitted entries·ln(residuals)); NaN with kMisfit.
  double bic_declared = 0.0, bic_other = 0.0;
  int samples = 0;             // the samples of `a` the job fits
  int dof = 0;                 // residuals − free parameters of the refits
  // With kMisfit: set when chi2_declared_delay − chi2_other_delay is above
  // both kSamplingBicMargin·max(1, chi2_declared_delay/dof) and
  // kSamplingExcessShare·(chi2_declared_delay − dof). With kBestBic: set
  // when bic_declared − bic_other is above kSamplingBicMargin·max(1,
  // chi2_declared/(residuals − fitted entries)).
  std::string note;
  // The refit under the other convention (Gauss–Newton intervals, no
  // optimum check): the discovery loop's base fit when it adopts that
  // convention (discovery/accelerometer_convention.h).
  FitResult refit;
};

// Refits `job` from the estimate of `result` (AtEstimate, AsWarmRefit:
// one Levenberg–Marquardt run on the whole record, Gauss–Newton
// covariance, no checks) under each accelerometer convention
// (AxisStructure::accelerometer) with a free delay on every fitted
// channel, compares the two by `rule` (SamplingRule), and where the other
// convention wins refits the job as it stands under it (`refit`; with
// kBestBic before deciding). `ran` is false when no fitted experiment fits
// `a`; a refit that ends without a finite cost leaves no note. `result`
// must be a fit of `job`. The two conventions' refits with the delays run
// side by side, then (kBestBic) the other convention's refits as the job
// stands, two at a time (common/concurrency.h ForEachConcurrently on
// job.solver.threads threads, each refit evaluating on that many too, so
// that it ends as it would alone); an exception comes after both refits
// of its pair have ended. Throws std::runtime_error if the model does not
// simulate at the estimate.
SamplingCheck CheckAccelerometerSampling(const EstimationProblem& job, const FitResult& result,
                                         SamplingRule rule = SamplingRule::kMisfit);

}  // namespace axis

#endif  // ESTIMATION_SAMPLING_CHECK_H_
