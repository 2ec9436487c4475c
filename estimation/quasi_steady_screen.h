// The quasi-steady screen of a job declared with the paper's full current
// loop (issue 57: screen coarse, confirm fine once). The full loop's
// electrical mode limits RK4 to about 19.5 µs on the X axis, so the paper's
// model is integrated at 10 µs; its quasi-steady limit (sim/axis_params.h
// CurrentLoop::kQuasiSteady, MODEL.md §2: K_a "sufficiently large") has no
// such mode and is stable to about 139 µs, five to ten times fewer steps for
// a trace that differs by a small fraction of the noise on the paper's
// records (tests/axis_model_test.cc). fit-params (run/job_run.h RunJob) fits
// the screen — the starts, the horizon continuation, the checks and the
// discovery loop — and then refits the declared full loop at the job's own
// step from the screen's estimate less its first-order shift
// (estimation/full_loop_refit.h), so the values reported are the declared
// model's.
#ifndef ESTIMATION_QUASI_STEADY_SCREEN_H_
#define ESTIMATION_QUASI_STEADY_SCREEN_H_

#include "estimation/estimation_problem.h"

namespace axis {

// Whether fit-params screens `job` with the quasi-steady current loop: an
// analog velocity loop (MODEL.md §3) declared with the full current loop.
// Never throws.
bool HasQuasiSteadyScreen(const EstimationProblem& job);

// The screen's coarser step: a round step at most this fraction of the
// quasi-steady model's RK4 stability limit (over the free parameters'
// ranges) is taken instead of the automatic rule's (0.52 of it) where its
// traces at the job's start differ from the declared model's by at most
// kScreenErrorGrowth times the automatic step's difference plus
// kScreenErrorSlack (RMS in σ, the worst fitted channel): the quasi-steady
// approximation's own error (about 0.02 σ on the paper's records) is the
// screen's, and a step that adds little to it costs half the simulations.
// 0.9 keeps the step clear of the stability edge.
constexpr double kScreenStepFraction = 0.9;
constexpr double kScreenErrorGrowth = 1.25;
constexpr double kScreenErrorSlack = 0.01;

// The screen of `job` (HasQuasiSteadyScreen): the same job with
// `current_loop: quasi_steady`, every experiment (fitted and validated)
// integrated at the automatic step of the quasi-steady model (sim/auto_step.h
// AutoStep: at most 0.52 of its RK4 stability limit over the free
// parameters' ranges, dividing the record's output period and the control
// period T_s — the experiment's own in closed loop, else the model's) or at
// the coarser step above where its traces stay as close to the declared
// model's (each simulated once in double at the job's start, the declared
// one at its own step), never finer than the experiment's own step. Output
// periods, durations and sample times are the job's. Throws
// std::invalid_argument, naming why, where the model has no screen, the
// quasi-steady model's linearisation is not finite, or no automatic step
// divides an experiment's periods (sim/simulate.h MakeGrid); the caller
// then fits the job as declared.
EstimationProblem QuasiSteadyScreen(const EstimationProblem& job);

// Gives every experiment of `full` (fitted and validated) the finer of its
// own integration step and that of the experiment of the same name in
// `declared` (the job before its screen), where there is one: the refit
// runs at the job's step unless the discovered model at its estimate needs
// a finer one (estimation/current_loop_check.h WithFullLoop). Both divide
// the experiment's periods, so the finer does. Returns the smallest step of
// `full`'s experiments afterwards (s). Never throws.
double TakeFinerSteps(const EstimationProblem& declared, EstimationProblem* full);

// The smallest integration step (s) of the experiments of `job`, fitted and
// validated; +inf if it has none. Never throws.
double SmallestStep(const EstimationProblem& job);

}  // namespace axis

#endif  // ESTIMATION_QUASI_STEADY_SCREEN_H_
