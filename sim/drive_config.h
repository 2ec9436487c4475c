// The loaders of what drives an experiment (configs/README.md): input
// signals (step, ramp, sine, chirp, PRBS, tables, data columns), controller
// references (trapezoid, minimum-jerk, a column) and the sampled position
// controller's settings (MODEL.md §5). Strict: unknown keys, wrong types and
// out-of-range values are std::invalid_argument naming file, line and key
// (io/yaml_util.h).
#ifndef SIM_DRIVE_CONFIG_H_
#define SIM_DRIVE_CONFIG_H_

#include <string>

#include <yaml-cpp/yaml.h>

#include "io/data_table.h"
#include "io/yaml_util.h"
#include "sim/controller.h"
#include "sim/input_shaper.h"
#include "sim/input_signal.h"

namespace axis {

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

// A move's `shaper:` mapping (sim/input_shaper.h): `type` (ShaperNames(),
// any case), `frequency` (Hz, > 0) and `damping` (ζ in [0, 1), default
// 0.1; neither for `type: none`). Throws std::invalid_argument naming the
// key.
InputShaper ParseInputShaper(YamlMap& parent);

// A controller reference (MODEL.md §5): `type: trapezoid` (distance,
// velocity, acceleration, start, origin, shaper), `type: min_jerk` (the
// same and jerk, optional) or `type: column` (the keys of
// ParseColumnSignal). Calls Finish(). Throws std::invalid_argument.
Reference ParseReference(YamlMap& map, const std::string& base_dir,
                         double origin);

// Throws the config error "<file>:<line>: key '<key>': expected a supply
// voltage > 0 V throughout, got <value> V at t = <t> s" (a table's first
// sample that is ≤ 0 or not finite) or "... got a least value of <value> V"
// (a step's two levels, a sine's or chirp's offset − |amplitude|, a ramp's
// value at its start) unless `supply` stays above 0 V. `map` and `node`
// locate the key.
void CheckSupplyPositive(const InputSignal& supply, const YamlMap& map,
                         const YAML::Node& node, const std::string& key);

// The drive's supply voltage `supply:` of a closed-loop experiment whose
// controller outputs a duty cycle (Drive::supply, MODEL.md §5): a number
// (V, > 0) as a constant signal, or a mapping read by `signal` (a column of
// the record, or a signal type) whose every value is > 0 V
// (CheckSupplyPositive). Throws std::invalid_argument naming the key for a
// value ≤ 0 or not finite, and whatever `signal` throws.
template <typename SignalOf>
InputSignal ParseSupply(YamlMap& root, const SignalOf& signal) {
  const YAML::Node node = root.Optional("supply");
  if (node.IsScalar()) {
    InputSignal constant;
    constant.offset = root.Number("supply", YamlMap::Range::kPositive);
    return constant;
  }
  YamlMap map(node, root.file(), root.KeyPath("supply."));
  InputSignal supply = signal(map);
  CheckSupplyPositive(supply, root, node, root.KeyPath("supply"));
  return supply;
}

// Throws the config error "<file>:<line>: key '<key>': expected a drive that
// an enable signal can switch off (voltage_drive, current_source,
// force_source), got analog_velocity_loop (its current loop is not
// modelled off)" for a model with the analog velocity loop (MODEL.md §4
// drive enable). `node` locates the line.
void CheckDriveEnable(const AxisStructure& structure, const YamlMap& map,
                      const YAML::Node& node, const std::string& key);

// Throws the config error naming `map`'s file, line and key unless a
// closed-loop experiment's controller, drive and supply fit together
// (MODEL.md §4–§5): a `servo_firmware` loop needs `amplifier:
// voltage_drive` (its output is a PWM duty cycle), `motion: rotary` (its
// counts are per revolution of the output shaft) and a `supply:`
// (`has_supply`); a `supply:` needs a `servo_firmware` loop (it turns the
// duty cycle into volts).
void CheckFirmwareDrive(const AxisStructure& structure, const ControllerConfig& controller,
                        bool has_supply, const YamlMap& map);

// The controller settings of MODEL.md §5, starting from `defaults`:
// `type: sampled_position` (the law's own keys T_s, T_track, G_ff, G_p,
// G_i, G_v, alpha, U_max, delay_samples, counts_per_rev, load_quantum) or
// `type: servo_firmware` (kp, ki, kd, kp_divisor, ki_divisor, kd_divisor,
// pwm_full_scale, pwm_limit, counts_per_rev, quantized, T_s,
// delay_samples; FirmwareLaw). The type defaults to that of `defaults`, so
// an experiment overrides a firmware model's gain with `{kp: 800}`.
ControllerConfig ParseController(YamlMap& map, const ControllerConfig& defaults);

}  // namespace axis

#endif  // SIM_DRIVE_CONFIG_H_
