#include "estimation/quasi_steady_screen.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "sim/auto_step.h"

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
  const double control_period = job.model.has_controller ? job.model.controller.T_s : 0.0;
  for (std::vector<FitExperiment>* list : {&screen.experiments, &screen.validate}) {
    for (FitExperiment& e : *list) {
      const double period = e.options.output_period;
      const double step = AutoStep(limit, period, control_period);
      const double n = std::round(period / step);
      if (!(n >= 1.0) || std::abs(n * step - period) > 1e-6 * step) {
        throw std::invalid_argument("no quasi-steady step divides the output period of " +
                                    e.name);
      }
      e.options.step = std::max(e.options.step, period / n);
    }
  }
  return screen;
}

double UseDeclaredSteps(const EstimationProblem& declared, EstimationProblem* full) {
  for (std::vector<FitExperiment>* list : {&full->experiments, &full->validate}) {
    for (FitExperiment& e : *list) {
      const std::vector<FitExperiment>& from =
          list == &full->experiments ? declared.experiments : declared.validate;
      if (const FitExperiment* d = FindExperiment(from, e.name)) e.options.step = d->options.step;
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
