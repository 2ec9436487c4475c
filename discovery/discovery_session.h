// Discovery as a run does it after the declared model's fit (run/job_run.h
// RunJob): the accelerometer's sampling convention first, then the loop of
// discovery/discovery.h, then the convention judged again on the model it
// discovered, then the force map; and, after a refit with another model of
// the current loop, the selected effects judged again. The policy between
// the steps (when the convention is judged again, which rule decides) lives
// here, beside the steps; the run only calls it and prints its own tables.
#ifndef DISCOVERY_DISCOVERY_SESSION_H_
#define DISCOVERY_DISCOVERY_SESSION_H_

#include <functional>
#include <ostream>

#include "discovery/discovery_report.h"
#include "discovery/discovery_settings.h"
#include "discovery/force_map_report.h"
#include "estimation/estimation_problem.h"
#include "estimation/fit_result.h"
#include "estimation/sampling_check.h"

namespace axis {

// What RunDiscovery found.
struct DiscoveryOutcome {
  // The loop's report, the convention's steps among its own; its
  // base_fit_seconds is the one given.
  DiscoveryReport report;
  // The force-map step, with settings.force_map (force_map.ran otherwise
  // false).
  ForceMapReport force_map;
  // The accelerometer check that stands: the one given, or the one on the
  // discovered model where that adopted the other convention.
  SamplingCheck sampling_check;
};

// Runs discovery on `problem` from its fit `result` (both changed to the
// discovered model and its fit):
// 1. the convention `check` (estimation/sampling_check.h, on the declared
//    model) recommends is adopted first where its refit has the lower BIC
//    (discovery/accelerometer_convention.h): the loop's delays and filters
//    would stand in for it. Not where the model or job declares the
//    convention (AxisConfig::declared) and settings.revisit_declared is
//    off: a declaration is kept, and the check's evidence against it is a
//    note of the report (steps 1 and 3 skipped);
// 2. the loop (Discover);
// 3. if none was adopted in 1 and the check ran: where the loop's verdict
//    is not `explained`, or it kept a filter or a delay on `a` (to first
//    order stand-ins for the convention: a period mean is a box filter and
//    a half-period delay of instant samples), the convention is judged
//    again on the discovered model (kMisfit when unexplained, kBestBic when
//    a stand-in was kept); if the other wins, it is adopted, the first
//    run's effects meet the significance rule (DropInsignificant: a
//    stand-in goes there), the loop runs again with the effects left to
//    add, every selected effect meets the rule again, and the final model
//    is judged;
// 4. with settings.force_map, the force map (discovery/force_map.h).
// Prints the convention's adoption, the final diagnostics, the loop's
// table and the force map's to `out`. `stage`, if set, is told each step
// that starts (a progress line). Throws as Discover.
DiscoveryOutcome RunDiscovery(const DiscoverySettings& settings, const SamplingCheck& check,
                              double base_fit_seconds, EstimationProblem* problem,
                              FitResult* result, std::ostream& out,
                              const std::function<void(const char*)>& stage = {});

// After `problem` was refitted with the paper's full current loop (its fit
// `result`; estimation/full_loop_refit.h): the loop's significance rule
// (DropInsignificant at report->level) on the selected effects, its steps
// marked "with the full loop: …", then the final diagnostics and verdict
// at `alpha`, printed to `out` ("Final model with the full current loop:
// …"). An effect that was significant only against the quasi-steady
// approximation's error goes (a payload of 0.17 kg, 4.3 standard errors,
// on independent-data square-wave records: 0.08 ± 0.04 kg with the full
// loop). Returns the effects it dropped (also in report->removed).
// Throws as DropInsignificant; a model that does not simulate at its
// estimate keeps the loop's verdict.
std::vector<std::string> JudgeEffectsAgain(double alpha, EstimationProblem* problem,
                                           FitResult* result, DiscoveryReport* report,
                                           std::ostream& out);

}  // namespace axis

#endif  // DISCOVERY_DISCOVERY_SESSION_H_
