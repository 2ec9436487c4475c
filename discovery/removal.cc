#include "discovery/removal.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "common/format.h"
#include "common/progress.h"
#include "common/statistics.h"
#include "discovery/accelerometer_convention.h"
#include "discovery/candidates.h"
#include "discovery/channel_changes.h"
#include "discovery/internal/screen.h"
#include "discovery/significance.h"
#include "estimation/at_estimate.h"
#include "estimation/fit.h"
#include "estimation/fit_control.h"

namespace axis {
namespace {

// `job` without `c` (its parameters `params` fixed), as a warm refit.
// Without a large effect the optimum can be far from this start: the
// removal keeps the horizon continuation (there is no bound on its cost
// to check a warm refit against, as there is for an added effect).
EstimationProblem WithoutJob(const Candidate& c, const std::vector<std::string>& params,
                             const EstimationProblem& job) {
  EstimationProblem without = job;
  RemoveEffect(c, params, &without);
  const double first_horizon = without.solver.first_horizon;
  AsWarmRefit(&without);
  without.solver.first_horizon = first_horizon;
  return without;
}

// Removed only if BIC falls: a refit that can no longer fall below the
// BIC with the effect stops early (FitControl::abandon_above_bic).
FitControl RemovalControl(const FitResult& result) {
  FitControl control;
  control.abandon_above_bic = kStopFactor * result.bic;
  return control;
}

DiscoveryStep RemovalRecord(const Candidate& c, const FitResult& result, const FitResult& refit,
                            double seconds) {
  DiscoveryStep record;
  record.seconds = seconds;
  record.effect = c.name;
  record.removal = true;
  record.bic_before = result.bic;
  record.bic_after = refit.bic;
  record.stopped = StoppedText(refit, result.bic, "the BIC with the effect");
  record.kept = refit.bic < result.bic && record.stopped.empty();
  record.channels = ChannelChanges(result, refit);
  return record;
}

}  // namespace

std::vector<Removal> RefitsWithout(const std::vector<Candidate>& candidates,
                                   EstimationProblem* job, const FitResult& result) {
  ApplyEstimates(result, job);
  std::vector<EstimationProblem> jobs;
  for (const Candidate& c : candidates) jobs.push_back(WithoutJob(c, EffectParameters(c), *job));
  std::vector<double> seconds;
  std::vector<FitResult> refits =
      FitConcurrently(jobs, job->solver.threads, &seconds,
                      std::vector<FitControl>(jobs.size(), RemovalControl(result)));
  std::vector<Removal> out;
  for (size_t k = 0; k < candidates.size(); ++k) {
    DiscoveryStep record = RemovalRecord(candidates[k], result, refits[k], seconds[k]);
    out.push_back({std::move(record), std::move(refits[k]), std::move(jobs[k])});
  }
  return out;
}

void DropEffect(const std::string& name, EstimationProblem&& without, FitResult&& refit, EstimationProblem* job,
                FitResult* result, DiscoveryReport* report) {
  report->removed.push_back(name);
  report->selected.erase(std::find(report->selected.begin(), report->selected.end(), name));
  *job = std::move(without);
  *result = std::move(refit);
}

void DropInsignificant(double level, EstimationProblem* job, FitResult* result,
                       DiscoveryReport* report, std::ostream* progress) {
  if (!(level > 0.0)) {
    throw std::invalid_argument("DropInsignificant: expected a level > 0, got " +
                                std::to_string(level));
  }
  report->level = level;
  // The last added first (Stribeck before the Coulomb it refines).
  const std::vector<std::string> effects = report->selected;
  for (size_t k = effects.size(); k-- > 0;) {
    if (IsConventionStep(effects[k])) continue;  // no parameter to test
    const Candidate candidate = CandidateNamed(effects[k]);
    if (RefinedInModel(candidate.effect, job->model.structure)) continue;
    ApplyEstimates(*result, job);
    const EffectSignificance w = EffectWald(candidate.name, *result);
    if (w.p_value < level) continue;
    if (ProgressStream* status = AsProgressStream(progress)) {
      status->Status("discovery significance: refit without " + candidate.name +
                         " (not significant)",
                     std::numeric_limits<double>::quiet_NaN());
    }
    Removal removal = std::move(RefitsWithout({candidate}, job, *result)[0]);
    DiscoveryStep& record = removal.record;
    const FitResult& refit = removal.refit;
    // The likelihood ratio of the same refit must agree: a Wald test is not
    // invariant to the parametrisation (a second-order filter's (τ, ζ)
    // ridge, where removing the effect raised BIC from 8.0e3 past 2.0e4 on
    // an independent-data PRBS record, had a Wald p above the level), and a
    // refit stopped on its BIC bound has no estimate to adopt.
    // χ² of the refit's fixed parameters, scaled by s² as the Wald test is.
    const double ratio = (Deviance(refit) - Deviance(*result)) /
                         std::max(1.0, result->residual_variance);
    const int fixed = std::max(1, static_cast<int>(EffectParameters(candidate).size()));
    const bool failed = record.stopped.empty() && !std::isfinite(ratio);
    const double ratio_p =
        record.stopped.empty() && !failed ? ChiSquaredSurvival(std::max(ratio, 0.0), fixed) : 0.0;
    std::ostringstream why;
    why << "Wald chi2 " << w.chi2 << " (dof " << w.dof << "), p " << w.p_value
        << " not below " << level;
    if (ratio_p < level) {
      why << (failed ? ", but the refit without it failed: kept"
                     : ", but the likelihood ratio of the refit without it is significant (" +
                           (record.stopped.empty() ? "p " + FormatNumber(ratio_p, 4)
                                                   : std::string("stopped on its bound")) +
                           "): kept");
      record.insignificant = why.str();
      record.kept = false;
      report->steps.push_back(record);
      if (progress) *progress << "  refit without " << candidate.name << ": " << why.str() << "\n";
      continue;
    }
    why << ", likelihood ratio p " << ratio_p << ": not distinguishable from off";
    record.insignificant = why.str();
    record.kept = true;  // removed whatever BIC says
    report->steps.push_back(record);
    if (progress) {
      *progress << "  refit without " << candidate.name << ": " << record.insignificant
                << "; BIC " << record.bic_before << " -> " << record.bic_after
                << " (removed)\n";
    }
    DropEffect(candidate.name, std::move(removal.without), std::move(removal.refit), job, result,
               report);
  }
  ApplyEstimates(*result, job);
  report->significance.clear();
  for (const std::string& name : report->selected) {
    if (!IsConventionStep(name)) report->significance.push_back(EffectWald(name, *result));
  }
}

}  // namespace axis
