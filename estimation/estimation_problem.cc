#include "estimation/estimation_problem.h"

#include <algorithm>
#include <stdexcept>

#include "sim/channels.h"

namespace axis {

const std::vector<double>& FitExperiment::Measured(Channel c) const {
  for (size_t k = 0; k < measured_channels.size(); ++k) {
    if (measured_channels[k] == c) return measured[k];
  }
  throw std::invalid_argument("experiment '" + name + "': expected channel '" +
                              ChannelName(c) + "' to be measured, got none");
}

double FittedPeriod(const EstimationProblem& problem, Channel c) {
  double period = 0.0;
  for (const FitExperiment& e : problem.experiments) {
    for (const FittedChannel& f : e.fitted) {
      if (f.channel == c) period = std::max(period, e.options.output_period);
    }
  }
  return period;
}

const FitExperiment* FindExperiment(const std::vector<FitExperiment>& list,
                                    const std::string& name) {
  for (const FitExperiment& e : list) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

int EstimatedStateCount(const EstimationProblem& problem) {
  int n = 0;
  for (const FitExperiment& e : problem.experiments) n += e.estimate_initial_state ? 2 : 0;
  return n;
}

std::vector<ParameterRange> FreeParameterRanges(const EstimationProblem& problem) {
  std::vector<ParameterRange> ranges;
  for (const FreeParameter& f : problem.free) {
    ranges.push_back({f.name, f.lower, f.upper});
    for (const ParameterTie& tie : problem.ties) {
      if (tie.source == f.name) ranges.push_back({tie.parameter, f.lower, f.upper});
    }
  }
  return ranges;
}

}  // namespace axis
