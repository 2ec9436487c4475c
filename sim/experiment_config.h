// Experiment files (configs/experiments/*.yaml): the model with its
// overrides, what drives it, the time grid, the recorded channels, noise
// and seed; one strict loader (configs/README.md). Errors are
// std::invalid_argument naming file, line and key.
#ifndef SIM_EXPERIMENT_CONFIG_H_
#define SIM_EXPERIMENT_CONFIG_H_

#include <array>
#include <cstdint>
#include <string>

#include <yaml-cpp/yaml.h>

#include "sim/axis_config.h"
#include "sim/axis_model.h"
#include "sim/simulate.h"

namespace axis {

// The largest noise seed of an experiment (its `seed` key, simulate-axis
// --seed): 2^62.
constexpr long kMaxExperimentSeed = 1L << 62;

// An experiment file: the model (with overrides), what drives it, the time
// grid, recorded channels, noise and seed.
struct ExperimentConfig {
  std::string path;
  std::string description;
  AxisConfig model;
  Drive drive;
  SimulationOptions options;
  std::array<double, kNumChannels> noise_sigma{};  // Gaussian σ per channel
  std::uint64_t seed = 0;  // 0..kMaxExperimentSeed
  AxisState<double> initial_state = AxisState<double>::Zero();
};

// Loads an experiment file. Throws std::invalid_argument.
ExperimentConfig LoadExperiment(const std::string& path);

// As LoadExperiment, from a parsed YAML document; `path` names it in
// messages and relative file names (model, data columns) are resolved
// against `base_dir`.
ExperimentConfig ParseExperiment(const YAML::Node& document, const std::string& path,
                                 const std::string& base_dir);

}  // namespace axis

#endif  // SIM_EXPERIMENT_CONFIG_H_
