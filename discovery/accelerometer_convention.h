// The accelerometer's sampling convention (MODEL.md §6: instant or period
// mean) as a front-end step of the discovery loop. The convention is not a
// parameter the score test can differentiate, and to first order the
// loop's delay and low-pass on `a` stand in for it (issue 42: a period
// mean read as instant samples is a box filter and a half-period delay):
// on instant records read as period means, `fit-params --discover` kept
// sensor_delay.a and ended "incomplete" at s² = 1.40, b_g 13 standard
// errors off. The sampling check (estimation/sampling_check.h) has already
// refitted the model under the other convention; when that refit lowered
// χ² past its note, the loop starts from it.
#ifndef DISCOVERY_ACCELEROMETER_CONVENTION_H_
#define DISCOVERY_ACCELEROMETER_CONVENTION_H_

#include <optional>
#include <string>
#include <vector>

#include "discovery/discovery_report.h"
#include "estimation/fit_result.h"
#include "estimation/sampling_check.h"
#include "estimation/estimation_problem.h"

namespace axis {

// If `check` carries a note (the other convention's refit lowered Σ(r/σ)²
// past kSamplingBicMargin) and its refit, without the check's delay, has a
// finite cost and a lower BIC than `result`: sets
// job->model.structure.accelerometer to check.other, replaces *result by
// check.refit, and returns the step "accelerometer.<other>" (kept; chi2 =
// the drop in Σ(r/σ)², dof 0: the same parameters, so the BIC falls by
// that much; the channels' RMS before and after). Else changes nothing and
// returns nullopt. Never throws (except std::bad_alloc).
std::optional<DiscoveryStep> AdoptAccelerometerConvention(const SamplingCheck& check,
                                                          EstimationProblem* job, FitResult* result);

// Whether `name` is the step AdoptAccelerometerConvention returns
// ("accelerometer.…"), which has no parameter of its own. Never throws.
bool IsConventionStep(const std::string& name);

// Puts `step` before the loop's own steps in `report`, and its effect
// first among the selected. Never throws (except std::bad_alloc).
void PrependConventionStep(const DiscoveryStep& step, DiscoveryReport* report);

// The report of the loop run a second time, after the convention was
// adopted on the model the first run discovered (run/job_run.cc: a plant
// effect's misfit can hide the convention from the check on the declared
// model, and a delay on `a` then stands in for it): `first`'s steps, then
// `convention`, then `between` (the steps taken after the convention and
// before the second run: the significance rule's removals of the first
// run's stand-ins), then `second`'s; the selected effects of both in that
// order (the convention between them); the removed ones of both; the
// seconds and score rankings summed; the rest (ranking, stop reason,
// significance, final diagnostics, verdict) `second`'s. Never throws
// (except std::bad_alloc).
DiscoveryReport JoinSecondPass(DiscoveryReport first, const DiscoveryStep& convention,
                               DiscoveryReport second,
                               const std::vector<DiscoveryStep>& between = {});

}  // namespace axis

#endif  // DISCOVERY_ACCELEROMETER_CONVENTION_H_
