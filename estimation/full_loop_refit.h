// The refit of a quasi-steady fit with the paper's full current loop (MODEL.md
// eq. 3), for when the current-loop check (estimation/current_loop_check.h)
// finds the quasi-steady approximation shifting the estimate by more than
// simulation.full_loop_refit_above standard errors (run/job_run.h RunJob).
//
// The full loop costs about ten times as much per simulation (10 µs instead
// of 100 µs). Running the job's whole optimum check and profile intervals
// on it took 250 s of a 260 s job (issue 42, the accelerometer sampled at
// the instant: 892 probe simulations, 440 in local restarts, 1640 in the
// profiles). The two models differ by a shift of a few standard errors,
// not in the shape of the cost, so by default (FullLoopRefitSettings::
// Intervals::kCarried) the refit is a local Levenberg–Marquardt solve from the
// bias-corrected estimate θ_qs − shift (the check's first-order bias), with
// the Gauss–Newton covariance of the full loop, and the intervals are the
// quasi-steady fit's (its optimum check, its profile or smooth-scale
// intervals) carried over: CarryQuasiSteadyIntervals. kRefitted runs the
// job's own checks and interval method on the full loop instead.
#ifndef ESTIMATION_FULL_LOOP_REFIT_H_
#define ESTIMATION_FULL_LOOP_REFIT_H_

#include "estimation/current_loop_check.h"
#include "estimation/estimation_problem.h"
#include "estimation/fit_result.h"
#include "io/yaml_util.h"

namespace axis {

// When and how a quasi-steady fit is refitted with the full loop, and
// whether a full-loop job is screened with the quasi-steady loop first (job
// keys simulation.full_loop_refit_above, simulation.full_loop_intervals and
// simulation.quasi_steady_screen).
struct FullLoopRefitSettings {
  // The shift of the estimate against the full loop, in standard errors,
  // past which fit-params refits with the full loop (run/job_run.h RunJob,
  // estimation/current_loop_check.h); > 0, +inf never refits.
  double refit_above = 1.0;
  // How the refit gets its optimum check and intervals: kCarried, a local
  // solve from the bias-corrected estimate whose intervals are the
  // quasi-steady fit's carried over (widened by the ratio of the two
  // models' Gauss–Newton standard errors where the full loop's is larger);
  // kRefitted, the job's own optimum check and uncertainty method run
  // again on the full loop (ten times the cost per simulation).
  enum class Intervals { kCarried, kRefitted };
  Intervals intervals = Intervals::kCarried;
  // Whether a job declared with the full current loop is fitted on its
  // quasi-steady screen first (estimation/quasi_steady_screen.h) and then
  // refitted with the full loop at its own step, whatever the shift:
  // kAuto where the model has the screen (an analog velocity loop) and the
  // screen's step is coarser than the job's; kOff fits the full loop
  // throughout.
  enum class Screen { kAuto, kOff };
  Screen screen = Screen::kAuto;

  // The keys of `simulation:` these settings own (io/settings_reader.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("full_loop_refit_above", &refit_above, YamlMap::Range::kPositiveOrInfinite);
    a->Visit("full_loop_intervals", &intervals,
             {{"carried", Intervals::kCarried}, {"refitted", Intervals::kRefitted}});
    a->Visit("quasi_steady_screen", &screen, {{"auto", Screen::kAuto}, {"off", Screen::kOff}});
  }
};

// The step, in standard errors, below which the full-loop refit with
// carried intervals stops (FullLoopRefitProblem): a twentieth of the
// interval's half-width, below what the carried intervals resolve.
constexpr double kFullLoopRefitStepSe = 0.05;

// The problem of the refit: WithFullLoop of `problem` at the estimate of
// `quasi` (AtEstimate), one start next to the minimum
// (EstimationProblem::start_near_minimum), no random starts, no horizon
// continuation; its free parameters start at value − check.shift (clamped
// to their bounds; a NaN shift leaves the value). With `intervals`
// kCarried also no probe rounds, no local restarts, Gauss–Newton intervals
// and a function tolerance that stops once a step lowers the cost by less
// than a step of kFullLoopRefitStepSe standard errors would. *step, if not null, receives the full loop's step (s). Throws
// std::runtime_error as WithFullLoop.
EstimationProblem FullLoopRefitProblem(const EstimationProblem& problem, const FitResult& quasi,
                                       const CurrentLoopCheck& check,
                                       FullLoopRefitSettings::Intervals intervals,
                                       double* step = nullptr);

// Gives every free parameter of `full` (the refit) the interval of the same
// parameter in `quasi`, moved to the refit's value and scaled by
// r = max(1, (full's Gauss–Newton standard error) / (quasi's)), or 1 where
// either is not a finite positive number (never narrower: a rough
// full-loop cost makes its Gauss–Newton scale an artifact): for a positive value and interval the ends
// scale in ratio, value·(end/value_qs)^r (which keeps them positive, as a
// log-scaled parameter's are); otherwise they move by r·(end − value_qs). std_error becomes r·(quasi's), the interval method
// "<quasi's>, carried from the quasi-steady fit", and the optimum check,
// its verdict and the uncertainty method and note are the quasi-steady
// fit's, named as such. Never throws.
void CarryQuasiSteadyIntervals(const FitResult& quasi, FitResult* full);

// After an effect is dropped from the full-loop refit (discovery's
// significance rule applied again, run/job_run.h), the model without it is
// again a local Gauss–Newton solve on the same rough cost, so its own
// intervals are the artifact CarryQuasiSteadyIntervals avoids (an
// independent square-wave and sweep record: T_p's 14 times narrower than
// the carried one, the truth 9 of those off). Gives every free parameter of
// `refit` that is also in `carried` (the full-loop fit with the effect, its
// intervals carried) `carried`'s interval moved to the refit's value, and
// widened by the ratio of the two Gauss–Newton standard errors where the
// refit's is larger, never narrowed (as CarryQuasiSteadyIntervals; the
// dropped effect's correlation can only have widened them). The interval
// method, optimum check and uncertainty method and note are `carried`'s.
// Never throws.
void CarryIntervalsAcrossRemoval(const FitResult& carried, FitResult* refit);

}  // namespace axis

#endif  // ESTIMATION_FULL_LOOP_REFIT_H_
