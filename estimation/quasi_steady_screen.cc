#include "estimation/quasi_steady_screen.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "sim/auto_step.h"
#include "sim/simulate.h"

namespace axis {

bool HasQuasiSteadyScreen(const EstimationProblem& job) {
  const AxisStructure& s = job.model.structure;
  return s.amplifier == Amplifier::kAnalogVelocityLoop && s.current_loop == CurrentLoop::kFull;
}

EstimationProblem QuasiSteadyScreen(const EstimationProblem& job) {
  if (!HasQuasiSteadyScreen(job)) {
    throw std::invalid_argument(
        "expected an analog velocity loop with the full current loop to screen");
  }
  EstimationProblem screen = job;
  screen.model.structure.current_loop = CurrentLoop::kQuasiSteady;
  std::vector<ParameterRange> ranges;
  for (const FreeParameter& f : job.free) ranges.push_back({f.name, f.lower, f.upper});
  const double limit = AutoStepLimit(screen.model.structure, screen.model.params, ranges);
  if (!(limit > 0.0)) {
    throw std::invalid_argument("expected a positive RK4 step limit of the quasi-steady model");
  }
  const double model_period = job.model.has_controller ? job.model.controller.T_s : 0.0;
  for (std::vector<FitExperiment>* list : {&screen.experiments, &screen.validate}) {
    for (FitExperiment& e : *list) {
      // The experiment's own controller period where it runs closed loop
      // (a job's `controller:` may override the model's), and the model's,
      // as the job's loader chose the step (run/load_fit_job.cc).
      const double control_period = e.drive.closed_loop ? e.drive.controller.T_s : model_period;
      const double step = AutoStep(limit, e.options.output_period, control_period);
      e.options.step = std::max(e.options.step, step);
      // Throws std::invalid_argument where the output or control period is
      // not a whole number of steps.
      MakeGrid(e.options, e.drive);
    }
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
