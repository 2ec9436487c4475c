#include "estimation/record_prefix.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "sim/channels.h"

namespace axis {

FitExperiment Truncate(const FitExperiment& e, double horizon, double lookahead) {
  FitExperiment out = e;
  size_t n = 0;
  while (n < e.t.size() && e.t[n] <= horizon * (1 + 1e-9)) ++n;
  n = std::max<size_t>(n, 3);
  if (n >= e.t.size()) return out;
  out.t.resize(n);
  for (auto& m : out.measured) m.resize(n);
  // Whole output periods past the last sample kept, within the record.
  const size_t ahead =
      lookahead > 0.0
          ? static_cast<size_t>(std::ceil(lookahead / e.options.output_period - 1e-9))
          : 0;
  out.options.duration = e.t[std::min(n - 1 + ahead, e.t.size() - 1)];
  return out;
}

double Lookahead(const EstimationProblem& problem) {
  double ahead = 0.0;
  for (int k = 0; k < kNumChannels; ++k) {
    if (!problem.model.structure.sensors.delay[k]) continue;
    double lowest = problem.model.params.tau_d[k];
    const std::string name = std::string("tau_d.") + ChannelName(static_cast<Channel>(k));
    for (const FreeParameter& f : problem.free) {
      if (f.name == name) lowest = std::min(lowest, f.lower);
    }
    ahead = std::max(ahead, -lowest);
  }
  return ahead;
}

}  // namespace axis
