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

std::shared_ptr<const StageInputs> MakeStageInputs(const Drive& drive,
                                                   const SimulationGrid& grid) {
  if (drive.closed_loop || IsHeldInput(drive.input)) return nullptr;
  auto out = std::make_shared<StageInputs>();
  const double h = grid.step;
  out->step = h;
  const size_t n_entries = static_cast<size_t>(grid.num_steps) + 1;
  out->at_start.resize(n_entries);
  out->at_half.resize(n_entries);
  out->at_end.resize(n_entries);
  size_t cursor = 0;
  for (long n = 0; n <= grid.num_steps; ++n) {
    // The times as Simulate and Rk4Step form them (t = n·h; t + half_h with
    // half_h = 0.5·h; t + h).
    const double t = n * h;
    out->at_start[n] = drive.input.Evaluate(t, &cursor);
    out->at_half[n] = drive.input.Evaluate(t + 0.5 * h, &cursor);
    out->at_end[n] = drive.input.Evaluate(t + h, &cursor);
  }
  return out;
}

// The instances sim/simulate.h declares extern.
AXIS_SIMULATE_INSTANCES(, double)
AXIS_SIMULATE_INSTANCES(, EventTimeJet)

}  // namespace axis
