#include "estimation/internal/phase_timer.h"

#include <algorithm>

#include "estimation/fit_result.h"

namespace axis {

void AddPhase(const FitPhase& phase, FitResult* result) {
  auto it = std::find_if(result->phases.begin(), result->phases.end(),
                         [&](const FitPhase& f) { return f.name == phase.name; });
  if (it == result->phases.end()) {
    result->phases.push_back(phase);
    return;
  }
  it->seconds += phase.seconds;
  it->simulations += phase.simulations;
  it->jacobians += phase.jacobians;
}

}  // namespace axis
