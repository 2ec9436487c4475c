// Model configs (configs/axes/*.yaml) and experiment files
// (configs/experiments/*.yaml): aggregate structs with defaults and one
// strict loader each. Unknown keys, missing required keys, wrong types and
// out-of-range values are std::invalid_argument naming file, line and key.
// The file formats are described in configs/README.md.
#ifndef SIM_CONFIG_H_
#define SIM_CONFIG_H_

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/axis_model.h"
#include "sim/axis_params.h"
#include "sim/controller.h"
#include "sim/data_table.h"
#include "sim/input_signal.h"
#include "sim/simulate.h"
#include "sim/yaml_util.h"

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
};

// Loads a model config. Throws std::invalid_argument as described above,
// including for non-positive M, J_m, L, T_p, T_r, r_g, K_i and for
// amplifier: force_source without coupling: rigid.
AxisConfig LoadAxisConfig(const std::string& path);

// As LoadAxisConfig, from a parsed YAML document; `path` names it in
// messages.
AxisConfig ParseAxisConfig(const YAML::Node& document, const std::string& path);

// The dynamic effects of MODEL.md §7: config name, parameter names (in
// VisitParams naming) and the switch in EffectSwitches. The one list of them.
struct EffectInfo {
  const char* name;
  std::vector<const char*> params;
  bool EffectSwitches::*flag;
};
const std::vector<EffectInfo>& DynamicEffectTable();

// Forces outside MODEL.md §7 that a model config may switch on to generate
// data (issue 10: the discovery loop's verdict on a force its library
// lacks), under `effects:` like the §7 ones:
//   friction_patch: {F_pt: N, x_pt0: m, x_pt1: m, w_pt: m}  F_pt·sgn_ε(v)
//       for x_pt0 < x < x_pt1, edges smoothed over w_pt (> 0); x_pt1 > x_pt0.
//   quadratic_drag: {C_d: N*s^2/m^2}                        C_d·v·|v|
//   position_ripple: {F_rp: N, lambda_rp: m, phi_rp: rad}
//       F_rp·sin(2π·x/λ_rp + φ_rp): periodic in the load position, λ_rp > 0.
//   velocity_bump: {F_vb: N, v_vb: m/s, w_vb: m/s}
//       F_vb·exp(−((|v| − v_vb)/w_vb)²)·sgn_ε(v): friction peaking at one
//       speed (issue 15's force-map tests), v_vb ≥ 0, w_vb > 0.
// Not effects in the sense of IsEffectName: never discovery candidates, and
// a fit job cannot name them in discover.candidates (sim/axis_model.h has
// their equations).
const std::vector<EffectInfo>& GeneratorOnlyEffectTable();

// Their names for messages: "friction_patch, quadratic_drag, position_ripple,
// velocity_bump".
std::string GeneratorOnlyEffectNameList();

// The effects switched on in `s`, as the discovery loop names them: the
// DynamicEffectTable names in its order, then sensor_delay.<channel> and
// sensor_bias.<channel> in channel order, then force_map.<kind> (x,
// x_friction or v; sim/force_map.h). Never throws.
std::vector<std::string> EnabledEffectNames(const AxisStructure& s);

// Whether `name` names one effect the way the discovery loop does: a
// DynamicEffectTable name ("coulomb"), or a SensorEffectTable name with a
// MODEL.md §6 channel ("sensor_delay.a"); with `allow_bare_sensor` also
// the sensor effect's name alone ("sensor_delay": every channel).
bool IsEffectName(const std::string& name, bool allow_bare_sensor = false);

// Whether an effect name (IsEffectName, or "force_map.x" style) belongs to
// the sensor front end (MODEL.md §6: sensor_delay, sensor_bias,
// sensor_lowpass, sensor_lowpass2, with or without a channel; and the
// accelerometer's sampling convention as the discovery loop names its
// change, "accelerometer.instant" or "accelerometer.period_mean") rather
// than to the plant. The discovery report lists the two apart. Never throws.
bool IsFrontEndEffect(const std::string& name);

// The list of effect names for messages: "coulomb, stribeck, …,
// sensor_delay[.channel], sensor_bias[.channel], …".
std::string EffectNameList();

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

// Checks the parameters of `config` against the ranges of MODEL.md §2
// (positive masses, inertias, time constants, ...). `where` prefixes the
// message (a file or "--set"). Throws std::invalid_argument.
void ValidateAxisConfig(const AxisConfig& config, const std::string& where);

// The config as YAML that LoadAxisConfig reads back: structure, every
// parameter of MODEL.md §2, the enabled effects with their parameters, and
// the controller if any.
std::string AxisConfigToYaml(const AxisConfig& config);

// Sets parameter `name` (a VisitParams name, MODEL.md §2/§7) to `value`.
// Throws std::invalid_argument "<where>: expected a parameter name of the
// model (R, L, ...), got 'X'" for an unknown name.
void SetParam(AxisConfig* config, const std::string& name, double value,
              const std::string& where);

// Parses `NAME=VALUE` (a --set argument) and applies it with SetParam,
// then re-validates. Throws std::invalid_argument.
void ApplySetArgument(AxisConfig* config, const std::string& assignment);

// An input signal from a mapping with `type:` step | ramp | sine | chirp |
// prbs | table | column (see configs/README.md); `duration` bounds the PRBS.
// Data files are resolved against `base_dir`.
InputSignal ParseInputSignal(YamlMap& map, const std::string& base_dir,
                             double duration);

// MakeCubic(s) (sim/input_signal.h) for the mapping `map` that set
// `interpolation: cubic`; its error becomes a config error naming the file,
// line and key.
void MakeCubicOrThrow(YamlMap& map, InputSignal* s);

// Throws the config error "<file>:<line>: key '<key>': expected a column of
// <data file> (<its columns>), got '<column>'" unless `table` has `column`
// (for a MAT file "expected a variable of <file> that is a real numeric
// vector of N finite values ... (<its columns>), got 'kp' (a 1x1 double)",
// DataTable::ColumnExpectation and DescribeName); `node` locates the line.
void RequireColumn(const YamlMap& map, const YAML::Node& node,
                   const std::string& key, const DataTable& table,
                   const std::string& column);

// A column of a data file (keys file, time, column, scale, offset,
// interpolation; a CSV or, named *.mat, a MAT file: ReadDataTable) as a
// table signal; does not call Finish(). Throws std::invalid_argument naming
// the key if a column does not exist, and the errors of ReadCsv (file, line)
// or ReadMatFile (file, variable).
InputSignal ParseColumnSignal(YamlMap& map, const std::string& base_dir);

// A controller reference (MODEL.md §5): `type: trapezoid` (distance,
// velocity, acceleration, start, origin), `type: min_jerk` (the same and
// jerk, optional) or `type: column` (the keys of
// ParseColumnSignal). Calls Finish(). Throws std::invalid_argument.
Reference ParseReference(YamlMap& map, const std::string& base_dir,
                         double origin);

// The controller settings of MODEL.md §5, starting from `defaults`.
ControllerConfig ParseController(YamlMap& map, const ControllerConfig& defaults);

// The model overrides an experiment or job may declare next to `model:`:
// `configuration:` (amplifier, coupling), `effects:` (as in a model config)
// and `set:` (parameter values by MODEL.md name). Re-validates the model.
// Throws std::invalid_argument naming the file, line and key.
void ParseModelOverrides(YamlMap& root, AxisConfig* model);

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

// The initial state made consistent with the coupling: in rigid coupling
// y2 = y0/r_g and y3 = y1/r_g.
AxisState<double> ConsistentInitialState(const AxisConfig& config,
                                         const AxisState<double>& y);

}  // namespace axis

#endif  // SIM_CONFIG_H_
