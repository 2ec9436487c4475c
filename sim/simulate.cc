#include "sim/simulate.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace axis {
namespace {

// n such that period ≈ n·step, or throws.
long WholeSteps(double period, double step, const char* what) {
  const double ratio = period / step;
  const long n = std::lround(ratio);
  if (n < 1 || std::abs(ratio - n) > 1e-6 * ratio) {
    std::ostringstream msg;
    msg << "expected the " << what << " to be a whole number (≥ 1) of "
        << "integration steps of " << step << " s, got " << period << " s ("
        << ratio << " steps)";
    throw std::invalid_argument(msg.str());
  }
  return n;
}

}  // namespace

SimulationGrid MakeGrid(const SimulationOptions& options, const Drive& drive) {
  if (!(options.duration > 0.0) || !std::isfinite(options.duration)) {
    throw std::invalid_argument("expected a positive duration, got " +
                                std::to_string(options.duration));
  }
  if (!(options.step > 0.0) || !std::isfinite(options.step)) {
    throw std::invalid_argument("expected a positive integration step, got " +
                                std::to_string(options.step));
  }
  SimulationGrid g;
  g.step = options.step;
  g.num_steps = std::lround(options.duration / options.step);
  g.steps_per_output =
      WholeSteps(options.output_period, options.step, "output period");
  if (drive.closed_loop) {
    g.steps_per_control =
        WholeSteps(drive.controller.T_s, options.step, "control period T_s");
  }
  g.num_outputs = g.num_steps / g.steps_per_output + 1;
  return g;
}

}  // namespace axis
