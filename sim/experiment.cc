#include "sim/experiment.h"

#include <cstdio>
#include <stdexcept>
#include <utility>

#include "io/csv.h"
#include "io/interrupt.h"
#include "sim/random.h"

namespace axis {

Trace<double> RunExperiment(const ExperimentConfig& e,
                            const std::function<void(double)>& progress) {
  const SimulationGrid grid = MakeGrid(e.options, e.drive);
  return Simulate(e.model.structure, e.model.params, e.initial_state, e.drive,
                  e.options, grid, progress);
}

void AddNoise(const std::array<double, kNumChannels>& sigma, std::uint64_t seed,
              Trace<double>* trace) {
  RandomEngine rng(seed);
  for (int c = 0; c < kNumChannels; ++c) {
    if (!(sigma[c] > 0.0)) continue;
    for (double& value : trace->values[c]) value += sigma[c] * StandardNormal(rng);
  }
}

void WriteTraceCsv(const std::string& path, const Trace<double>& trace,
                   const std::vector<Channel>& channels) {
  std::vector<std::string> names = {"t"};
  std::vector<std::vector<double>> columns = {trace.t};
  for (Channel c : channels) {
    names.push_back(ChannelName(c));
    columns.push_back(trace[c]);
  }
  WriteCsvAtomic(path, names, columns, 12);
}

Trace<double> SimulateExperiment(ExperimentConfig e, const SimulateAxisOptions& options) {
  for (const std::string& set : options.sets) ApplySetArgument(&e.model, set);
  e.initial_state = ConsistentInitialState(e.model, e.initial_state);
  if (options.has_seed) {
    if (options.seed > static_cast<std::uint64_t>(kMaxExperimentSeed)) {
      throw std::invalid_argument("--seed: expected an integer in 0.." +
                                  std::to_string(kMaxExperimentSeed) +
                                  " (the range of the experiment's seed key), got " +
                                  std::to_string(options.seed));
    }
    e.seed = options.seed;
  }
  std::function<void(double)> progress;
  if (options.show_progress) {
    progress = [](double fraction) {
      std::fprintf(stderr, "\rsimulating %3d %%", static_cast<int>(100 * fraction));
    };
  }
  Trace<double> trace = RunExperiment(e, progress);
  if (options.show_progress) std::fprintf(stderr, "\rsimulating 100 %%\n");
  if (!trace.finite) {
    throw std::runtime_error(
        e.path +
        ": the simulation left the finite numbers (unstable: try a smaller "
        "step or check the parameters); nothing written");
  }
  if (!options.no_noise) AddNoise(e.noise_sigma, e.seed, &trace);
  return trace;
}

void SimulateAxis(const SimulateAxisOptions& options) {
  SetInterruptTarget(options.out_path);
  ExperimentConfig e = LoadExperiment(options.experiment_path);
  CheckOutputFile(options.out_path);  // before the simulation, not after it
  const std::vector<Channel> channels = e.options.channels;
  const Trace<double> trace = SimulateExperiment(std::move(e), options);
  DeferInterrupts defer;  // no temporary file left behind (io/interrupt.h)
  WriteTraceCsv(options.out_path, trace, channels);
  defer.Committed();
}

}  // namespace axis
