// Taking an effect back out of a model the discovery loop built: the refit
// without it (warm-started at the optimum with the effect off), the report's
// bookkeeping when it goes, and the rule that drops every effect that is
// not significantly different from off (issue 10).
#ifndef DISCOVERY_REMOVAL_H_
#define DISCOVERY_REMOVAL_H_

#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "discovery/candidates.h"
#include "discovery/discovery_report.h"
#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"

namespace axis {

// One refit of RefitsWithout: the removal step, the refit and its job.
struct Removal {
  DiscoveryStep record;
  FitResult refit;
  EstimationProblem without;  // the job refitted
};

// Refits `job` without each of `candidates` (its parameters
// EffectParameters fixed), warm-started at the optimum `result` with the
// effect switched off (ApplyEstimates writes `result` into `job` first).
// Each removal step records BIC with and without (bic_before, bic_after)
// and the refit's own wall time; kept = BIC improved. A refit that can no
// longer fall below the BIC with the effect stops early
// (DiscoveryStep::stopped, not kept). Up to job->solver.threads refits run
// at once (FitConcurrently, estimation/fit.h), with what the refits one
// after the other would give, up to the last bits of a cost summed on
// another number of threads (one candidate: one refit on all the threads);
// in `candidates`' order. Throws as FitParameters does (the lowest-indexed
// refit's exception, after every refit has run).
std::vector<Removal> RefitsWithout(const std::vector<Candidate>& candidates,
                                   EstimationProblem* job, const FitResult& result);

// Drops `name` (which must be in report->selected) from the selected
// effects (to report->removed) and adopts the model without it (`without`,
// fitted as `refit`) as `job` and `result`.
void DropEffect(const std::string& name, EstimationProblem&& without, FitResult&& refit, EstimationProblem* job,
                FitResult* result, DiscoveryReport* report);

// The stand-in rule of Discover (issue 10), on its own: each effect of
// report->selected (Candidate names, the last first; the accelerometer's
// convention step, discovery/accelerometer_convention.h, skipped; Coulomb skipped while
// Stribeck is in) whose EffectWald p-value at the fit `result` is not below
// `level` is refitted away (warm-started at the optimum with the effect
// off, its parameters fixed) and dropped whatever BIC says, unless the
// likelihood ratio of that refit, 2·(cost without − cost with)/max(1, s²),
// is significant at `level` (χ² with as many dof as the effect's
// parameters) or the refit stopped on its BIC bound or failed: then the
// effect stays (a removal step with
// `insignificant` saying so, kept false). A dropped one: a removal step
// with `insignificant` set is appended, the name moves to report->removed,
// and `job`/`result` become the model without it. Sets report->level and
// report->significance (the effects left); a level above 1 keeps every
// effect. Throws std::invalid_argument for a level ≤ 0 or an unknown effect
// name.
void DropInsignificant(double level, EstimationProblem* job, FitResult* result,
                       DiscoveryReport* report, std::ostream* progress);

}  // namespace axis

#endif  // DISCOVERY_REMOVAL_H_
