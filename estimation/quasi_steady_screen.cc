#include "estimation/quasi_steady_screen.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>
#include <vector>

#include "common/statistics.h"
#include "estimation/evaluate_experiment.h"
#include "estimation/fit_result.h"
#include "sim/auto_step.h"
#include "sim/simulate.h"

namespace axis {

bool HasQuasiSteadyScreen(const EstimationProblem& job) {
  const AxisStructure& s = job.model.structure;
  return s.amplifier == Amplifier::kAnalogVelocityLoop && s.current_loop == CurrentLoop::kFull;
}

namespace {

// `job`'s experiments (fitted and validated) at the steps of the rule under
// `limit` (s): AutoStep for each record's output period and control period
// T_s (the experiment's own in closed loop, else the model's, as the job's
// loader chose its step: run/load_fit_job.cc), never finer than its own.
// Throws std::invalid_argument where a period is not a whole number of
// steps (MakeGrid).
void SetScreenSteps(double limit, EstimationProblem* job) {
  const double model_period = job->model.has_controller ? job->model.controller.T_s : 0.0;
  for (std::vector<FitExperiment>* list : {&job->experiments, &job->validate}) {
    for (FitExperiment& e : *list) {
      const double control_period = e.drive.closed_loop ? e.drive.controller.T_s : model_period;
      e.options.step =
          std::max(e.options.step, AutoStep(limit, e.options.output_period, control_period));
      MakeGrid(e.options, e.drive);
    }
  }
}

// The job's model with its free parameters at their initial values (and
// the parameters tied to them at theirs).
AxisParams<double> StartParams(const EstimationProblem& job) {
  AxisParams<double> params = job.model.params;
  for (const FreeParameter& f : job.free) {
    if (double* field = FindParam(&params, f.name)) *field = f.initial;
  }
  ApplyTies(TieIndices(job.ties), &params);
  return params;
}

// The goodness of fit of `job`'s fitted experiments at `params`: their
// simulated traces. Throws as EvaluateExperiment where a simulation fails.
std::vector<ExperimentFit> FittedTraces(const EstimationProblem& job,
                                        const AxisParams<double>& params) {
  std::vector<ExperimentFit> traces;
  for (const FitExperiment& e : job.experiments) {
    traces.push_back(EvaluateExperiment(job.model.structure, params, e));
  }
  return traces;
}

// The largest RMS, over the fitted channels, of the difference between the
// traces `a` and `reference` of the same experiments, in each channel's σ;
// +inf where a trace leaves the finite numbers.
double TraceDistance(const std::vector<ExperimentFit>& a,
                     const std::vector<ExperimentFit>& reference) {
  double worst = 0.0;
  for (size_t i = 0; i < a.size() && i < reference.size(); ++i) {
    for (size_t c = 0; c < a[i].channels.size() && c < reference[i].channels.size(); ++c) {
      const ChannelFit& x = a[i].channels[c];
      const ChannelFit& y = reference[i].channels[c];
      if (!x.fitted || !(x.sigma > 0.0) || x.simulated.empty() ||
          x.simulated.size() != y.simulated.size()) {
        continue;
      }
      const double rms = Rms(y.simulated, x.simulated) / x.sigma;
      if (!std::isfinite(rms)) return std::numeric_limits<double>::infinity();
      worst = std::max(worst, rms);
    }
  }
  return worst;
}

}  // namespace

EstimationProblem QuasiSteadyScreen(const EstimationProblem& job) {
  if (!HasQuasiSteadyScreen(job)) {
    throw std::invalid_argument(
        "expected an analog velocity loop with the full current loop to screen");
  }
  EstimationProblem screen = job;
  screen.model.structure.current_loop = CurrentLoop::kQuasiSteady;
  const std::vector<ParameterRange> ranges = FreeParameterRanges(job);
  const double limit = AutoStepLimit(screen.model.structure, screen.model.params, ranges);
  if (!(limit > 0.0)) {
    throw std::invalid_argument("expected a positive RK4 step limit of the quasi-steady model");
  }
  EstimationProblem coarse = screen;
  SetScreenSteps(limit, &screen);
  // A coarser step where its traces are as close to the declared model's.
  const double stability = limit / kAutoStepFraction;
  try {
    SetScreenSteps(kScreenStepFraction * stability, &coarse);
  } catch (const std::invalid_argument&) {
    return screen;
  }
  if (!(SmallestStep(coarse) > SmallestStep(screen))) return screen;
  // The declared model simulated once at its own (finest) step.
  const AxisParams<double> start = StartParams(job);
  try {
    const std::vector<ExperimentFit> declared = FittedTraces(job, start);
    const double automatic = TraceDistance(FittedTraces(screen, start), declared);
    const double coarser = TraceDistance(FittedTraces(coarse, start), declared);
    if (std::isfinite(automatic) &&
        coarser <= kScreenErrorGrowth * automatic + kScreenErrorSlack) {
      return coarse;
    }
  } catch (const std::exception&) {
    // A trace that cannot be simulated at the start: the automatic step.
  }
  return screen;
}

double TakeFinerSteps(const EstimationProblem& declared, EstimationProblem* full) {
  for (std::vector<FitExperiment>* list : {&full->experiments, &full->validate}) {
    for (FitExperiment& e : *list) {
      const std::vector<FitExperiment>& from =
          list == &full->experiments ? declared.experiments : declared.validate;
      const FitExperiment* d = FindExperiment(from, e.name);
      if (d != nullptr) e.options.step = std::min(e.options.step, d->options.step);
    }
  }
  return SmallestStep(*full);
}

double SmallestStep(const EstimationProblem& job) {
  double smallest = std::numeric_limits<double>::infinity();
  for (const std::vector<FitExperiment>* list : {&job.experiments, &job.validate}) {
    for (const FitExperiment& e : *list) smallest = std::min(smallest, e.options.step);
  }
  return smallest;
}

}  // namespace axis
