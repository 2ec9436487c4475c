// Running an experiment file end to end: simulate, add measurement noise,
// write the trace. The library side of `simulate-axis`.
#ifndef SIM_EXPERIMENT_H_
#define SIM_EXPERIMENT_H_

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sim/config.h"
#include "sim/simulate.h"

namespace axis {

// Simulates the experiment (noise-free). `progress` as in Simulate().
// Throws std::invalid_argument if the grid is inconsistent (MakeGrid).
Trace<double> RunExperiment(const ExperimentConfig& experiment,
                            const std::function<void(double)>& progress = nullptr);

// Adds independent Gaussian noise N(0, σ_c²) to every recorded channel c with
// σ_c = sigma[c] > 0, drawn by StandardNormal (sim/random.h) from a
// RandomEngine seeded with `seed` (channels in Channel order, samples in time
// order: fixed seeds give identical files on every platform).
void AddNoise(const std::array<double, kNumChannels>& sigma, std::uint64_t seed,
              Trace<double>* trace);

// Writes t and the recorded channels (in `channels` order) as CSV with the
// canonical channel names of MODEL.md §6 as header, atomically (temporary
// file, then rename). Throws std::runtime_error if it cannot write.
void WriteTraceCsv(const std::string& path, const Trace<double>& trace,
                   const std::vector<Channel>& channels);

// Options of the simulate-axis command.
struct SimulateAxisOptions {
  std::string experiment_path;
  std::string out_path;
  bool has_seed = false;
  std::uint64_t seed = 0;           // overrides the experiment's seed
  std::vector<std::string> sets;    // NAME=VALUE parameter overrides
  bool no_noise = false;            // write the noise-free trace
  bool show_progress = false;       // progress bar on stderr
};

// The trace simulate-axis writes for the loaded experiment `e`: the
// options' `sets` applied (ApplySetArgument, in order), the initial state
// made consistent (ConsistentInitialState), simulated (RunExperiment; a
// progress bar on stderr if show_progress) and, unless no_noise, the
// experiment's noise added with its seed (or options.seed if has_seed).
// The paths of `options` are not used. Throws std::invalid_argument for a
// bad set or grid and std::runtime_error "<e.path>: the simulation left the
// finite numbers …" if it diverges.
Trace<double> SimulateExperiment(ExperimentConfig e, const SimulateAxisOptions& options);

// Loads the experiment, checks the output path (CheckOutputFile, before
// simulating), applies the overrides, simulates, adds noise and writes the
// CSV (SimulateExperiment, WriteTraceCsv). Throws std::invalid_argument on
// bad input, an output path that is a folder or in a folder that is missing
// or cannot be written into (nothing is written then), and
// std::runtime_error if the output cannot be written after all or the
// simulation leaves the finite numbers.
void SimulateAxis(const SimulateAxisOptions& options);

}  // namespace axis

#endif  // SIM_EXPERIMENT_H_
