// Estimating the free parameters of a problem (estimation/estimation_problem.h) with Ceres Solver:
// Levenberg–Marquardt on the σ-weighted output error of all experiments,
// multi-start, within the parameters' bounds by an active set
// (internal/active_bounds.h), covariance as ceres::Covariance's DENSE_SVD
// forms it (estimation/covariance.h) scaled by the residual variance, and
// goodness of fit per channel.
#ifndef ESTIMATION_FIT_H_
#define ESTIMATION_FIT_H_

#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "estimation/fit_control.h"
#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"

namespace axis {

// Fits the job (estimation/internal/fitter.h: the steps in order). Prints one line
// per iteration to `progress` if non-null and job.solver.progress.
//
// Starts: the job's initial point, then job.solver.starts points drawn
// (seeded by job.solver.seed) log-uniformly within the bounds of positive
// parameters and uniformly otherwise, each through the horizon continuation
// (solver.first_horizon, doubled per stage); the solver.finalists lowest on
// the longest shorter horizon fit the whole record and the lowest final
// cost wins. A start that meets an earlier start's point after a shorter
// horizon (within its parameter tolerance) stops (FitResult::start_joined).
// With solver.starts 0 and the job's start ending at s² above
// kAutoStartsAbove, random starts are added (FitResult::auto_starts_note):
// kMisfitProbeStarts first, the rest of solver.auto_starts only unless all
// of those end at the job's cost (a misfit of the model, not a wrong
// minimum: estimation/internal/start_agreement.h). With the instant accelerometer
// the samples of `a` whose window holds a backlash contact are then
// weighted by σ_k and the fit re-solved under them
// (estimation/internal/instant_sample_sigma.h, FitResult::sample_sigma_note; a fit
// of the whole record alone starts under the weights at its start). Then
// the optimum check
// (solver.probe_rounds; on a cost rough below the standard-error scale
// lower points count only past χ² = s², estimation/internal/rough_optimum.h), the
// covariance, the local restarts (solver.local_starts) and the intervals
// (uncertainty.method), any of which restarts the solver at a lower cost it
// meets. Intervals that are artifacts of roughness are replaced by the
// covariance at the smooth scale (estimation/internal/smooth_scale.h;
// ParameterEstimate::interval_method); s² above 2 with structured
// residuals adds sandwich standard errors (FitResult::misspecification_note).
//
// `control` (estimation/fit_control.h) steers the fit from inside the tool:
// with a finite control.abandon_above_bic (the discovery loop's refits), a
// start whose BIC can no longer end below it stops on a shorter horizon (a
// stage's cost is a prefix of the whole record's, so 2·(its minimum) +
// n·ln(m) bounds the final BIC from below; the minimum taken as the lower
// of the stage's end point and the start); if every start stops, the result
// says where (FitResult::abandoned_horizon). control.stop_after_horizon > 0
// stops every start so after that horizon (a screen), and the result
// carries the stages every start ran (FitResult::checkpoint); a fit of the
// same job given that as control.resume takes those stages as run and goes
// on after them, with the same end as running them again (bit for bit on
// the same number of threads; estimation/horizon_checkpoint.h);
// control.stop_before_whole_record stops every start so after the last
// shorter horizon. With
// control.publish_level the fit publishes its BIC there when it ends (also
// when it throws: +inf); with control.pending_level it stops as under
// abandon_above_bic at that level once another fit publishes it, and may
// block until then (estimation/shared_level.h).
//
// Throws std::invalid_argument for an inconsistent job (LoadFitJob has
// checked), for a control.resume that is not a checkpoint of this job, for
// a pending_level with solver.starts > 0, a stop_after_horizon or
// stop_before_whole_record, and for stop_after_horizon with
// stop_before_whole_record; the solver itself never throws.
FitResult FitParameters(const EstimationProblem& job, std::ostream* progress = nullptr,
                        const FitControl& control = {});

// Turns `job` into a warm refit: a fit that starts next to its optimum (the
// residual bootstrap's refits of resampled data at the estimate) and only
// needs that optimum and its Gauss–Newton covariance. One start, no optimum
// check (solver.probe_rounds 0), the whole record at once
// (solver.first_horizon 0: the horizon continuation exists to bring a far
// start through the gear resonance's phase minima), Gauss–Newton
// intervals, and no line search along the solver's steps
// (EstimationProblem::no_line_search: one Jacobian per iteration, not
// two). The discovery loop's refits use these settings but restore
// first_horizon: with an effect added at its score step or removed, the
// start is not near enough (issue 11: on EMPS the whole record at once
// ended the Stribeck refit in a minimum 100 BIC higher).
void AsWarmRefit(EstimationProblem* job);

// Fits jobs[k] (FitParameters, no progress, with controls[k] if `controls`
// is not empty) for every k, up to `threads`
// fits at once on their own std::threads; each fit's Ceres evaluation gets
// twice its fair share, 2·threads / (fits at once) threads, at least 1 and
// at most `threads` (its job.solver.threads is overridden), so that the
// fits still running when others have ended use the freed cores (the
// force map's forms on the friction patch case, two runs each on 2 cores:
// 52.4 and 50.4 s with the fair share, 46.0 and 49.8 s so); taken in index
// order. The fits are independent (each builds
// its own problems), so the results are those of fitting one after the
// other, except that a fit with a control's pending_level waits for its level:
// its publisher must come at a lower index (it then always runs first or
// beside it; estimation/shared_level.h SharedLevel). `seconds`, if
// non-null, receives each fit's wall time (s). Rethrows the exception of
// the lowest-indexed fit that threw (std::invalid_argument for an
// inconsistent job), after every fit has run (common/concurrency.h
// ForEachConcurrently); std::invalid_argument at once if `controls` is
// neither empty nor of jobs' size. threads < 1 counts as 1. `on_done`, if
// set, is called after each fit ends with the number ended so far and
// n (for a progress line), one call at a time (under a lock) on the thread
// that ran the fit.
std::vector<FitResult> FitConcurrently(
    const std::vector<EstimationProblem>& jobs, int threads,
    std::vector<double>* seconds = nullptr, const std::vector<FitControl>& controls = {},
    const std::function<void(size_t done, size_t total)>& on_done = {});

}  // namespace axis

#endif  // ESTIMATION_FIT_H_
