#include "sim/experiment_config.h"

#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include "io/yaml_util.h"
#include "sim/channels.h"
#include "sim/drive_config.h"
#include "sim/preflight.h"

namespace axis {

namespace {

using Range = YamlMap::Range;

}  // namespace

namespace {

// The experiment's `channels:` (required): the trace's columns, each once;
// t is always recorded.
void ParseTraceChannels(YamlMap& root, const std::string& path, ExperimentConfig* e) {
  const YAML::Node channels = root.Required("channels");
  if (!channels.IsSequence() || channels.size() == 0) {
    ThrowConfigError(path, channels, "channels",
                     "a list of channel names (" + ChannelNameList() + ")",
                     Describe(channels));
  }
  std::set<Channel> listed;
  for (const YAML::Node& c : channels) {
    const auto channel = c.IsScalar() ? ParseChannel(c.Scalar()) : std::nullopt;
    if (!channel) {
      ThrowConfigError(path, c, "channels",
                       "a channel name (" + ChannelNameList() + ")", Describe(c));
    }
    // Each names a column of the trace; a CSV reader refuses a repeated one.
    if (!listed.insert(*channel).second) {
      ThrowConfigError(path, c, "channels", "each channel once (each names a column)",
                       Describe(c) + " again");
    }
    if (*channel != Channel::kT) e->options.channels.push_back(*channel);
  }
}

// The experiment's `noise:` (optional): σ per channel name, not t.
void ParseNoise(YamlMap& root, const std::string& path, ExperimentConfig* e) {
  const YAML::Node node = root.Optional("noise");
  if (!node) return;
  YamlMap map(node, path, "noise.");
  for (const auto& entry : node) {
    const std::string name = entry.first.Scalar();
    const auto channel = ParseChannel(name);
    if (!channel || *channel == Channel::kT) {
      ThrowConfigError(path, entry.first, "noise." + name,
                       "a channel name (" + ChannelNameList() + ", not t)",
                       "'" + name + "'");
    }
    e->noise_sigma[static_cast<int>(*channel)] =
        map.Number(name, Range::kNonNegative);
  }
  map.Finish();
}

// CheckMemory on the trace of `e`, sampled at `rate` Hz.
void CheckTraceMemory(const ExperimentConfig& e, double rate, const std::string& path) {
  // The trace: one double per output sample and channel (and time); a
  // delayed channel also keeps one value per RK4 step.
  const double outputs = std::floor(e.options.duration / e.options.output_period) + 1.0;
  const double steps = e.options.duration / e.options.step;
  double delayed = 0.0;
  for (int c = 0; c < kNumChannels; ++c) {
    delayed += HasGridFrontEnd(e.model.structure, static_cast<Channel>(c)) ? 1.0 : 0.0;
  }
  const double bytes =
      8.0 * (outputs * (e.options.channels.size() + 1.0) * 2.0 + steps * delayed);
  std::ostringstream advice;
  advice << "shorten 'duration' (" << e.options.duration << " s) or lower 'output_rate' ("
         << rate << " Hz)";
  CheckMemory(bytes, path, "the simulation", advice.str());
}

// `enable:` (MODEL.md §4 drive enable): a signal, on where ≥ 0.5.
void ParseEnable(YamlMap& root, const std::string& path, const std::string& dir,
                 ExperimentConfig* e) {
  const YAML::Node node = root.Optional("enable");
  if (!node) return;
  CheckDriveEnable(e->model.structure, root, node, "enable");
  YamlMap map(node, path, "enable.");
  e->drive.enable = ParseInputSignal(map, dir, e->options.duration);
  e->drive.has_enable = true;
}

// The experiment's drive: `input:` (open loop) or `reference:` with the
// controller and an optional `injection:` (closed loop).
void ParseExperimentDrive(YamlMap& root, const std::string& path, const std::string& dir,
                          ExperimentConfig* e) {
  const bool has_input = root.Has("input");
  const bool has_reference = root.Has("reference");
  if (has_input == has_reference) {
    ThrowConfigError(path, root.node(), has_input ? "reference" : "input",
                     "exactly one of 'input' (open loop) or 'reference' "
                     "(closed loop through the controller)",
                     has_input ? "both" : "neither");
  }
  if (has_input) {
    for (const char* key : {"controller", "injection"}) {
      if (root.Has(key)) {
        ThrowConfigError(path, root.node()[key], key,
                         std::string(key) + " only with a 'reference' (closed loop)",
                         "an open-loop experiment with 'input'");
      }
    }
    if (root.Has("supply")) {
      ThrowConfigError(path, root.node()["supply"], "supply",
                       "supply only with a 'reference' (closed loop: it scales the "
                       "controller's duty cycle)",
                       "an open-loop experiment with 'input'");
    }
    YamlMap map(root.Required("input"), path, "input.");
    e->drive.input = ParseInputSignal(map, dir, e->options.duration);
    ParseEnable(root, path, dir, e);
    return;
  }
  e->drive.closed_loop = true;
  ControllerConfig base = e->model.controller;
  if (const YAML::Node node = root.Optional("controller")) {
    YamlMap map(node, path, "controller.");
    base = ParseController(map, base);
  } else if (!e->model.has_controller) {
    ThrowConfigError(path, root.node(), "controller",
                     "a controller section here or in the model config " +
                         e->model.path,
                     "none");
  }
  e->drive.controller = base;
  YamlMap map(root.Required("reference"), path, "reference.");
  e->drive.reference = ParseReference(map, dir, e->initial_state[0]);
  if (const YAML::Node node = root.Optional("injection")) {
    YamlMap inj(node, path, "injection.");
    e->drive.injection = ParseInputSignal(inj, dir, e->options.duration);
    e->drive.has_injection = true;
  }
  if (root.Has("supply")) {
    e->drive.supply = ParseSupply(root, [&](YamlMap& m) {
      return ParseInputSignal(m, dir, e->options.duration);
    });
    e->drive.has_supply = true;
  }
  CheckFirmwareDrive(e->model.structure, e->drive.controller, e->drive.has_supply, root);
  ParseEnable(root, path, dir, e);
}

}  // namespace

ExperimentConfig LoadExperiment(const std::string& path) {
  return ParseExperiment(LoadYamlFile(path), path, DirectoryOf(path));
}

ExperimentConfig ParseExperiment(const YAML::Node& document, const std::string& path,
                                 const std::string& dir) {
  ExperimentConfig e;
  e.path = path;
  YamlMap root(document, path, "");
  e.description = root.String("description", "");
  e.model = LoadAxisConfig(ResolvePath(dir, root.String("model")));
  ParseModelOverrides(root, &e.model);

  e.options.duration = root.Number("duration", Range::kFinitePositive);
  e.options.step = root.Number("step", 1e-5, Range::kFinitePositive);
  {
    const YAML::Node node = root.node()["step"];
    CheckRk4Step(e.model.structure, e.model.params, e.options.step,
                 node ? path + ":" + std::to_string(node.Mark().line + 1) : path, "step");
  }
  const double rate = root.Number("output_rate", 1000.0, Range::kFinitePositive);
  e.options.output_period = 1.0 / rate;
  ParseTraceChannels(root, path, &e);
  ParseNoise(root, path, &e);
  CheckTraceMemory(e, rate, path);
  e.seed = static_cast<std::uint64_t>(root.Integer("seed", 0, 0, kMaxExperimentSeed));
  if (const YAML::Node node = root.Optional("initial_state")) {
    YamlMap map(node, path, "initial_state.");
    for (int k = 0; k < kNumStates; ++k) {
      e.initial_state[k] = map.Number("y" + std::to_string(k), 0.0);
    }
    map.Finish();
  }
  e.initial_state = ConsistentInitialState(e.model, e.initial_state);
  ParseExperimentDrive(root, path, dir, &e);
  root.Finish();
  try {
    MakeGrid(e.options, e.drive);
  } catch (const std::invalid_argument& err) {
    throw std::invalid_argument(path + ": " + err.what());
  }
  return e;
}

}  // namespace axis
