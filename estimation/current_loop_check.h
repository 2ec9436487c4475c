// What fitting the quasi-steady current loop (sim/axis_params.h
// CurrentLoop::kQuasiSteady) instead of the paper's full loop (MODEL.md
// eq. 3) costs the estimate on the job's own records: the shift of every
// free parameter, in its standard errors. Its model error was measured on
// the X axis's steps (tests/axis_model_test.cc: at most 0.022 σ RMS); on
// other axes and inputs it can be many standard errors (a wrist axis at
// 2 kHz, a PRBS on the Y axis with a quieter tachometer: shifts up to 13
// standard errors), so each fit with the option checks it.
#ifndef ESTIMATION_CURRENT_LOOP_CHECK_H_
#define ESTIMATION_CURRENT_LOOP_CHECK_H_

#include <string>
#include <vector>

#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"

namespace axis {

// A shift of more than this many standard errors is reported
// (CurrentLoopCheck::note): at half a standard error a 95 % interval still
// holds the truth 92 % of the time, at one 83 % (the normal law).
constexpr double kLoopShiftNote = 0.5;

// The full loop's RK4 step at most: the paper's (MODEL.md §5), stable to
// 19.5 µs on the X axis (tests/axis_model_test.cc).
constexpr double kFullLoopStep = 1e-5;

// The full loop's step at most this fraction of its RK4 stability limit
// (the paper's 10 µs is 0.51 of the X axis's 19.5 µs).
constexpr double kFullLoopStabilityMargin = 0.6;

// The smallest full-loop step WithFullLoop accepts (s): below it a fit of
// a few seconds of records takes millions of steps per simulation.
constexpr double kMinFullLoopStep = 1e-6;

struct CurrentLoopCheck {
  bool ran = false;                // the job fits the quasi-steady loop
  std::vector<std::string> names;  // the free parameters, job order
  // Estimate of the quasi-steady model on the full model's noise-free
  // trace at the estimate, minus the estimate (parameter units), and that
  // over the parameter's std_error (NaN where it has none).
  std::vector<double> shift;
  std::vector<double> shift_in_se;
  double largest = 0.0;            // max |shift_in_se| (0 if none finite)
  bool measured = false;           // some shift_in_se is finite
  double full_step = 0.0;          // s, the full loop's step (WithFullLoop)
  std::string note;                // set when largest > kLoopShiftNote
  // Set by fit-params (run/job_run.h RunJob) when largest passed the job's
  // simulation.full_loop_refit_above and the job was refitted with the
  // full loop at kFullLoopStep.
  bool refitted = false;
  // Set by fit-params when the job declares the full loop and was fitted on
  // its quasi-steady screen first (estimation/quasi_steady_screen.h): the
  // screen's smallest step (s).
  bool screened = false;
  double screen_step = 0.0;
};

// A copy of `job` with the paper's full current loop (CurrentLoop::kFull)
// at its model's parameters (for a fit's estimate: AtEstimate first), every
// experiment (fitted and validated) integrated at the largest whole
// fraction of its own step (which divides its sample period and, in closed
// loop, T_s) that is at most kFullLoopStep and kFullLoopStabilityMargin of
// the full loop's RK4 stability limit there (sim/preflight.h Rk4StabilityLimitOf;
// 19.5 µs on the X axis, so 10 µs at 1 kHz). *step, if not null, receives
// the smallest step used. Throws std::runtime_error naming the limit if
// that step would be below kMinFullLoopStep or the limit is not finite.
EstimationProblem WithFullLoop(const EstimationProblem& job, double* step = nullptr);

// For a job whose model has an analog_velocity_loop fitted with
// `current_loop: quasi_steady` (else ran = false, nothing computed):
// simulates every fitted experiment with the full loop (WithFullLoop) at
// the estimate `result`, refits the job's
// quasi-steady model to those noise-free traces from the estimate (one
// warm Levenberg–Marquardt run, estimation/fit.h AsWarmRefit, from Ceres'
// default trust region: EstimationProblem::start_near_minimum) and reports how far
// each free parameter moved: to first order the bias the approximation
// puts into the estimate (the Gauss–Newton step (JᵀJ)⁻¹Jᵀe of the model
// error e). `result` must be a fit of `job` with an estimate (its
// parameters and, for estimated states, initial_states). If the full loop
// cannot be integrated (WithFullLoop), its trace leaves the finite
// numbers, or the refit fails, ran is true, the shifts NaN, measured false
// and the note says why. Never throws (except std::bad_alloc).
CurrentLoopCheck CheckCurrentLoop(const EstimationProblem& job, const FitResult& result);

}  // namespace axis

#endif  // ESTIMATION_CURRENT_LOOP_CHECK_H_
