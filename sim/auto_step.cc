#include "sim/auto_step.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "sim/preflight.h"

namespace axis {

double AutoStepLimit(const AxisStructure& structure, const AxisParams<double>& params,
                     const std::vector<ParameterRange>& ranges) {
  const double start = Rk4StabilityLimitOf(structure, params).max_step;
  if (std::isnan(start)) {
    throw std::invalid_argument(
        "expected a model whose linearisation at rest is finite at the start values (to "
        "choose the integration step), got a non-finite Jacobian; set simulation.step");
  }
  double limit = start;
  for (const ParameterRange& r : ranges) {
    for (double value : {r.lower, r.upper}) {
      if (!std::isfinite(value)) continue;
      AxisParams<double> moved = params;
      double* field = FindParam(&moved, r.name);
      if (field == nullptr) continue;
      *field = value;
      const double at = Rk4StabilityLimitOf(structure, moved).max_step;
      if (std::isfinite(at)) limit = std::min(limit, at);
    }
  }
  return kAutoStepFraction * limit;
}

namespace {

// Whether `step` divides `period` into whole steps (within 10⁻⁶ of a step);
// a period of 0 (open loop) is divided by any step.
bool Divides(double step, double period) {
  if (!(period > 0.0)) return true;
  const double n = period / step;
  return std::abs(n - std::round(n)) <= 1e-6;
}

}  // namespace

double AutoStep(double limit, double output_period, double control_period) {
  if (!(output_period > 0.0) || !std::isfinite(output_period)) {
    throw std::invalid_argument("expected an output period > 0, got " +
                                std::to_string(output_period));
  }
  const bool bounded = std::isfinite(limit) && limit > 0.0;
  if ((!bounded || output_period <= limit) && Divides(output_period, control_period)) {
    return output_period;
  }
  // A round step (1, 2, 2.5 or 5 times a power of ten) below the period.
  const double top = bounded ? std::min(limit, output_period) : output_period;
  const int highest = static_cast<int>(std::floor(std::log10(top)));
  for (int e = highest; e >= highest - 2; --e) {  // down to a 1000th of the bound
    for (double m : {5.0, 2.5, 2.0, 1.0}) {
      const double h = m * std::pow(10.0, e);
      if (h <= top * (1 + 1e-12) && Divides(h, output_period) && Divides(h, control_period)) {
        return h;
      }
    }
  }
  // A period no round step divides (e.g. 1/3 ms): T_o/n.
  const long first =
      bounded ? std::max(1L, static_cast<long>(std::ceil(output_period / limit - 1e-9))) : 1L;
  for (long n = first; n <= 10000; ++n) {
    const double h = output_period / static_cast<double>(n);
    if (Divides(h, control_period)) return h;
  }
  std::ostringstream msg;
  msg << "expected a control period T_s = " << control_period
      << " s that is a whole number of some step T_o/n of the output period T_o = "
      << output_period << " s, got none for n up to 10^4; set simulation.step";
  throw std::invalid_argument(msg.str());
}

std::string AutoStepNote(double limit) {
  std::ostringstream out;
  out << "step chosen from the model (simulation.step absent): each record's period, or "
         "the largest round step (1, 2, 2.5 or 5 times a power of ten) dividing it at most "
      << kAutoStepFraction << " of the RK4 stability limit of the linearised model";
  if (std::isfinite(limit)) {
    out << " (" << limit / kAutoStepFraction << " s, over the free parameters' ranges)";
  } else {
    out << " (none: no mode limits the step)";
  }
  out << " and dividing the control period (sim/auto_step.h)";
  return out.str();
}

}  // namespace axis
