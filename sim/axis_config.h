// Model configs (configs/axes/*.yaml): the axis's structure, parameters and
// optional controller, as an aggregate struct with one strict loader, the
// ranges of its parameters, and the overrides an experiment or job declares
// next to `model:`. Unknown keys, missing required keys, wrong types and
// out-of-range values are std::invalid_argument naming file, line and key.
// The file format is described in configs/README.md.
#ifndef SIM_AXIS_CONFIG_H_
#define SIM_AXIS_CONFIG_H_

#include <set>
#include <string>

#include <yaml-cpp/yaml.h>

#include "io/yaml_util.h"
#include "sim/axis_model.h"
#include "sim/axis_params.h"
#include "sim/channels.h"
#include "sim/controller.h"

namespace axis {

// A model config: structure, parameters and an optional controller.
struct AxisConfig {
  std::string path;         // file it came from (for messages)
  std::string name;         // e.g. "x_axis"
  std::string source;       // provenance of the values
  AxisStructure structure;
  AxisParams<double> params;
  bool has_controller = false;
  ControllerConfig controller;  // MODEL.md §5, if has_controller
  // What the config, or the experiment or job that loaded it with its
  // overrides, states about the sensor front end (MODEL.md §6) rather than
  // leaves at its default: "accelerometer" where it names the convention,
  // and each front-end effect it switches on by channel ("sensor_delay.a",
  // "sensor_lowpass2.tach", …). A declaration is the user's knowledge of
  // the recorder: the discovery loop keeps it and reports the evidence
  // against it (discovery/discovery_session.h).
  std::set<std::string> declared;
};

// Loads a model config. Throws std::invalid_argument as described above,
// including for non-positive M, J_m, L, T_p, T_r, r_g, K_i, a voltage drive
// with R ≤ 0, a pendulum on a linear axis or gravity on a rotary one,
// `inductance: true` with an amplifier other than voltage_drive, and for
// amplifier: force_source without coupling: rigid.
AxisConfig LoadAxisConfig(const std::string& path);

// As LoadAxisConfig, from a parsed YAML document; `path` names it in
// messages.
AxisConfig ParseAxisConfig(const YAML::Node& document, const std::string& path);

// Parses the `effects:` mapping of a model config or experiment into
// `config` (switches on the named effects and sets their parameters).
// Effect names are those of MODEL.md §7; the sensor effects take a mapping
// of channel name to value (sensor_lowpass2: τ, or {tau, zeta}); force_map a mapping {variable, friction,
// knots, values} (sim/force_map.h).
void ParseEffects(YamlMap& effects, AxisConfig* config);

// The range of parameter `name` (a VisitParams name; MODEL.md §2, §7,
// configs/README.md): kPositive for masses, inertias, time constants, ...,
// kNonNegative for frictions, backlash, delays, ..., kPositiveOrInfinite
// for V_L (.inf: no limit), kAny for the rest. Every value a model holds,
// and every bound of a free parameter, must be in it.
YamlMap::Range ParamRange(const std::string& name);

// The MODEL.md §6 channel `name` (not t), read at `key` of `map` (`node`
// locates the line). Throws std::invalid_argument "<file>:<line>: key
// '<key>': expected a channel name of MODEL.md section 6 (<names>, not t),
// got '<name>'".
Channel ChannelOrThrow(const std::string& name, const YamlMap& map, const YAML::Node& node,
                       const std::string& key);

// Checks the parameters of `config` against the ranges of MODEL.md §2
// (positive masses, inertias, time constants, ...). `where` prefixes the
// message (a file or "--set"). Throws std::invalid_argument.
void ValidateAxisConfig(const AxisConfig& config, const std::string& where);

// Sets parameter `name` (a VisitParams name, MODEL.md §2/§7) to `value`.
// Throws std::invalid_argument "<where>: expected a parameter name of the
// model (R, L, ...), got 'X'" for an unknown name.
void SetParam(AxisConfig* config, const std::string& name, double value,
              const std::string& where);

// Parses `NAME=VALUE` (a --set argument) and applies it with SetParam,
// then re-validates. Throws std::invalid_argument.
void ApplySetArgument(AxisConfig* config, const std::string& assignment);

// The model overrides an experiment or job may declare next to `model:`:
// `configuration:` (amplifier, coupling, current_loop, inductance,
// accelerometer, instant_window, motion, load), `effects:` (as in a model config)
// and `set:` (parameter values by MODEL.md name). Re-validates the model.
// Throws std::invalid_argument naming the file, line and key, also where
// `configuration:` switches the inductance on without `set: {L: …}`.
void ParseModelOverrides(YamlMap& root, AxisConfig* model);

// The initial state made consistent with the coupling: in rigid coupling
// y2 = y0/r_g and y3 = y1/r_g.
AxisState<double> ConsistentInitialState(const AxisConfig& config,
                                         const AxisState<double>& y);

}  // namespace axis

#endif  // SIM_AXIS_CONFIG_H_
