#include "estimation/internal/instant_sample_sigma.h"

#include <algorithm>
#include <cmath>

#include "sim/simulate.h"

namespace axis {

namespace {

// Below this share of σ no Δ_k is worth a weight (σ_k within 0.5 % of σ).
constexpr double kMaterialSpread = 0.1;

}  // namespace

std::vector<double> InstantSampleSigmas(const AxisStructure& structure,
                                        const AxisParams<double>& params,
                                        const AxisState<double>& y0,
                                        const FitExperiment& experiment) {
  if (structure.accelerometer != AccelerometerSampling::kInstant) return {};
  const FittedChannel* a = nullptr;
  for (const FittedChannel& f : experiment.fitted) {
    if (f.channel == Channel::kA) a = &f;
  }
  if (a == nullptr) return {};
  SimulationOptions options = experiment.options;
  options.channels = {Channel::kA};
  options.point_acceleration = true;
  const SimulationGrid grid = MakeGrid(options, experiment.drive);
  const Trace<double> trace = Simulate(structure, params, y0, experiment.drive, options, grid);
  const std::vector<double>& mean = trace[Channel::kA];
  const size_t n = experiment.t.size();
  if (!trace.finite || mean.size() < n || trace.a_point.size() < n) return {};
  std::vector<double> sigma(n);
  double largest = 0.0;
  for (size_t k = 0; k < n; ++k) {
    const double spread = std::abs(mean[k] - trace.a_point[k]);
    largest = std::max(largest, spread);
    sigma[k] = std::hypot(a->sigma, spread);
  }
  if (!(largest >= kMaterialSpread * a->sigma)) return {};
  return sigma;
}

double SampleSigmaLogTerm(const std::vector<FitExperiment>& experiments,
                          const std::vector<SampleSigmas>& sample_sigma) {
  double sum = 0.0;
  for (size_t j = 0; j < experiments.size() && j < sample_sigma.size(); ++j) {
    const std::vector<FittedChannel>& fitted = experiments[j].fitted;
    for (size_t i = 0; i < fitted.size() && i < sample_sigma[j].size(); ++i) {
      for (double s : sample_sigma[j][i]) sum += 2.0 * std::log(s / fitted[i].sigma);
    }
  }
  return sum;
}

}  // namespace axis
