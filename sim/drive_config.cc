#include "sim/drive_config.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>

#include "io/csv.h"
#include "io/data_file.h"

namespace axis {

namespace {

using Range = YamlMap::Range;

}  // namespace

void RequireColumn(const YamlMap& map, const YAML::Node& node,
                   const std::string& key, const CsvTable& table,
                   const std::string& column) {
  if (table.HasColumn(column)) return;
  ThrowConfigError(map.file(), node, key, table.ColumnExpectation(),
                   table.DescribeName(column));
}

void MakeCubicOrThrow(YamlMap& map, InputSignal* s) {
  try {
    MakeCubic(s);
  } catch (const std::invalid_argument& e) {
    ThrowConfigError(map.file(), map.Optional("interpolation"), map.KeyPath("interpolation"),
                     "samples a cubic can pass through (" + std::string(e.what()) + ")",
                     "cubic");
  }
}

InputSignal ParseColumnSignal(YamlMap& map, const std::string& base_dir) {
  InputSignal s;
  s.kind = InputSignal::Kind::kTable;
  const std::string file = ResolvePath(base_dir, map.String("file"));
  const std::string time_col = map.String("time", "t");
  const std::string value_col = map.String("column");
  const double scale = map.Number("scale", 1.0);
  s.offset = map.Number("offset", 0.0);
  const std::string mode = map.Choice("interpolation", {"linear", "hold", "cubic"}, "linear");
  s.hold = mode == "hold";
  const DataTable table = ReadDataTable(file, time_col);
  RequireColumn(map, map.node(), map.KeyPath("time"), table, time_col);
  RequireColumn(map, map.node(), map.KeyPath("column"), table, value_col);
  CheckStrictlyIncreasing(table, time_col);
  s.times = table.Column(time_col);
  s.values = table.Column(value_col);
  for (double& v : s.values) v *= scale;
  if (mode == "cubic") MakeCubicOrThrow(map, &s);
  return s;
}

InputSignal ParseInputSignal(YamlMap& map, const std::string& base_dir,
                             double duration) {
  const std::string type = map.Choice(
      "type", {"zero", "step", "ramp", "sine", "chirp", "prbs", "table", "column"});
  InputSignal s;
  s.offset = map.Number("offset", 0.0);
  if (type == "zero") {
    s.kind = InputSignal::Kind::kZero;
  } else if (type == "step") {
    s.kind = InputSignal::Kind::kStep;
    s.amplitude = map.Number("amplitude");
    s.start = map.Number("start", 0.0, Range::kNonNegative);
  } else if (type == "ramp") {
    s.kind = InputSignal::Kind::kRamp;
    s.slope = map.Number("slope");
    s.start = map.Number("start", 0.0, Range::kNonNegative);
  } else if (type == "sine") {
    s.kind = InputSignal::Kind::kSine;
    s.amplitude = map.Number("amplitude");
    s.frequency = map.Number("frequency", Range::kFinitePositive);
    s.phase = map.Number("phase", 0.0);
    s.start = map.Number("start", 0.0, Range::kNonNegative);
  } else if (type == "chirp") {
    s.kind = InputSignal::Kind::kChirp;
    s.amplitude = map.Number("amplitude");
    s.f0 = map.Number("f0", Range::kNonNegative);
    s.f1 = map.Number("f1", Range::kNonNegative);
    s.sweep_time = map.Number("sweep_time", Range::kFinitePositive);
    s.start = map.Number("start", 0.0, Range::kNonNegative);
  } else if (type == "prbs") {
    const double amplitude = map.Number("amplitude");
    const double bit_time = map.Number("bit_time", Range::kFinitePositive);
    const int order = static_cast<int>(map.Integer("order", 10, 2, 20));
    const long seed = map.Integer("seed", 1, 1, 1L << 30);
    const double bits = PrbsTableBits(duration, bit_time);
    if (!(bits <= kMaxPrbsBits)) {
      std::ostringstream got;
      got << std::setprecision(3) << bits << " bits (duration " << duration << " s / bit_time "
          << bit_time << " s): lengthen bit_time or shorten the duration";
      ThrowConfigError(map.file(), map.Optional("bit_time"), map.KeyPath("bit_time"),
                       "a PRBS of at most 1e+08 bits", got.str());
    }
    s = MakePrbs(amplitude, s.offset, bit_time, order,
                 static_cast<std::uint32_t>(seed), duration);
  } else if (type == "table") {
    s.kind = InputSignal::Kind::kTable;
    const YAML::Node points = map.Required("points");
    const std::string key = map.KeyPath("points");
    if (!points.IsSequence() || points.size() < 1) {
      ThrowConfigError(map.file(), points, key,
                       "a list of [time, value] pairs", Describe(points));
    }
    for (const YAML::Node& point : points) {
      if (!point.IsSequence() || point.size() != 2) {
        ThrowConfigError(map.file(), point, key, "a [time, value] pair",
                         Describe(point));
      }
      const double t = map.NumberFrom(point[0], key, Range::kAny);
      if (!s.times.empty() && !(t > s.times.back())) {
        ThrowConfigError(map.file(), point, key,
                         "strictly increasing times",
                         NumberText(t) + " after " + NumberText(s.times.back()));
      }
      s.times.push_back(t);
      s.values.push_back(map.NumberFrom(point[1], key, Range::kAny));
    }
    const std::string mode = map.Choice("interpolation", {"linear", "hold", "cubic"}, "linear");
    s.hold = mode == "hold";
    if (mode == "cubic") MakeCubicOrThrow(map, &s);
  } else {  // column
    s = ParseColumnSignal(map, base_dir);
  }
  map.Finish();
  return s;
}

InputShaper ParseInputShaper(YamlMap& parent) {
  YamlMap map(parent.Required("shaper"), parent.file(), parent.KeyPath("shaper."));
  const std::string name = map.String("type");
  ShaperType type = ShaperType::kNone;
  if (!ParseShaperType(name, &type)) {
    std::string names;
    for (const std::string& n : ShaperNames()) names += (names.empty() ? "" : ", ") + n;
    ThrowConfigError(map.file(), map.node()["type"], map.KeyPath("type"), "one of " + names,
                     "'" + name + "'");
  }
  double frequency = 0.0, damping = 0.0;
  if (type != ShaperType::kNone) {
    frequency = map.Number("frequency", Range::kPositive);
    damping = map.Number("damping", 0.1, Range::kNonNegative);
    if (damping >= 1.0) {
      ThrowConfigError(map.file(), map.node()["damping"], map.KeyPath("damping"),
                       "a damping ratio in [0, 1)", Describe(map.node()["damping"]));
    }
  }
  map.Finish();
  return MakeInputShaper(type, frequency, damping);
}

Reference ParseReference(YamlMap& map, const std::string& base_dir,
                         double origin) {
  Reference r;
  const std::string type = map.Choice("type", {"trapezoid", "min_jerk", "column"});
  if (type != "column") {
    r.kind = type == "min_jerk" ? Reference::Kind::kMinJerk : Reference::Kind::kTrapezoid;
    r.distance = map.Number("distance");
    r.velocity = map.Number("velocity", Range::kFinitePositive);
    r.acceleration = map.Number("acceleration", Range::kFinitePositive);
    if (r.kind == Reference::Kind::kMinJerk) {
      r.jerk = map.Number("jerk", HUGE_VAL, Range::kPositiveOrInfinite);
    }
    r.start = map.Number("start", 0.0, Range::kNonNegative);
    r.origin = map.Number("origin", origin);
    if (map.Has("shaper")) r.shaper = ParseInputShaper(map);
  } else {
    r.kind = Reference::Kind::kTable;
    r.table = ParseColumnSignal(map, base_dir);
  }
  map.Finish();
  return r;
}

void CheckDriveEnable(const AxisStructure& structure, const YamlMap& map,
                      const YAML::Node& node, const std::string& key) {
  if (structure.amplifier == Amplifier::kAnalogVelocityLoop) {
    ThrowConfigError(map.file(), node, map.KeyPath(key),
                     "a drive that an enable signal can switch off (voltage_drive, "
                     "current_source, force_source)",
                     "analog_velocity_loop (its current loop is not modelled off)");
  }
}

void CheckFirmwareDrive(const AxisStructure& structure, const ControllerConfig& controller,
                        bool has_supply, const YamlMap& map) {
  const YAML::Node node = map.node();
  if (!controller.firmware.enabled) {
    if (has_supply) {
      ThrowConfigError(map.file(), node["supply"], map.KeyPath("supply"),
                       "a supply only with controller type: servo_firmware (it turns that "
                       "loop's duty cycle into volts)",
                       "a sampled_position controller");
    }
    return;
  }
  if (structure.amplifier != Amplifier::kVoltageDrive) {
    ThrowConfigError(map.file(), node, map.KeyPath("controller"),
                     "amplifier: voltage_drive with type: servo_firmware (its output is a PWM "
                     "duty cycle of the supply)",
                     "another amplifier");
  }
  if (structure.motion != Motion::kRotary) {
    ThrowConfigError(map.file(), node, map.KeyPath("controller"),
                     "motion: rotary with type: servo_firmware (its encoder counts are per "
                     "revolution of the output shaft)",
                     "motion: linear");
  }
  if (!has_supply) {
    ThrowConfigError(map.file(), node, map.KeyPath("supply"),
                     "the drive's supply voltage (a number in V, or a column) with controller "
                     "type: servo_firmware",
                     "none");
  }
}

namespace {

// The keys of `type: servo_firmware` (sim/controller.h ServoFirmware),
// starting from `d`'s firmware and period.
ControllerConfig ParseServoFirmware(YamlMap& map, const ControllerConfig& d) {
  for (const char* law_key : {"T_track", "G_ff", "G_p", "G_i", "G_v", "alpha", "U_max",
                              "load_quantum"}) {
    if (map.Has(law_key)) {
      ThrowConfigError(map.file(), map.Optional(law_key), map.KeyPath(law_key),
                       "the firmware's keys (kp, ki, kd, kp_divisor, ki_divisor, kd_divisor, "
                       "pwm_full_scale, pwm_limit, counts_per_rev, quantized, T_s, "
                       "delay_samples) with type: servo_firmware",
                       "a key of the sampled position controller");
    }
  }
  ServoFirmware f = d.firmware;
  f.kp = map.Number("kp", f.kp, Range::kNonNegative);
  f.ki = map.Number("ki", f.ki, Range::kNonNegative);
  f.kd = map.Number("kd", f.kd, Range::kNonNegative);
  f.kp_divisor = map.Number("kp_divisor", f.kp_divisor, Range::kFinitePositive);
  f.ki_divisor = map.Number("ki_divisor", f.ki_divisor, Range::kFinitePositive);
  f.kd_divisor = map.Number("kd_divisor", f.kd_divisor, Range::kFinitePositive);
  f.pwm_full_scale = map.Number("pwm_full_scale", f.pwm_full_scale, Range::kFinitePositive);
  // An override keeps the model's limit; a new loop's is its full scale.
  f.pwm_limit = map.Number("pwm_limit", d.firmware.enabled ? f.pwm_limit : f.pwm_full_scale,
                           Range::kFinitePositive);
  if (f.pwm_limit > f.pwm_full_scale) {
    ThrowConfigError(map.file(), map.Optional("pwm_limit"), map.KeyPath("pwm_limit"),
                     "at most pwm_full_scale (" + NumberText(f.pwm_full_scale) + ")",
                     NumberText(f.pwm_limit));
  }
  f.counts_per_rev = map.Number("counts_per_rev", f.counts_per_rev, Range::kFinitePositive);
  f.quantized = map.Choice("quantized", {"true", "false"}, f.quantized ? "true" : "false") ==
                "true";
  const double T_s = map.Number("T_s", d.T_s, Range::kFinitePositive);
  const int delay = static_cast<int>(map.Integer("delay_samples", d.delay_samples, 0, 1000));
  map.Finish();
  return FirmwareLaw(f, T_s, delay);
}

}  // namespace

ControllerConfig ParseController(YamlMap& map, const ControllerConfig& d) {
  const std::string type = map.Choice(
      "type", {"sampled_position", "servo_firmware"},
      d.firmware.enabled ? "servo_firmware" : "sampled_position");
  if (type == "servo_firmware") return ParseServoFirmware(map, d);
  ControllerConfig c;
  c.T_s = map.Number("T_s", d.T_s, Range::kFinitePositive);
  c.T_track = map.Number("T_track", d.T_track, Range::kFinitePositive);
  c.G_ff = map.Number("G_ff", d.G_ff);
  c.G_p = map.Number("G_p", d.G_p);
  c.G_i = map.Number("G_i", d.G_i);
  c.G_v = map.Number("G_v", d.G_v);
  c.alpha = map.Number("alpha", d.alpha, Range::kNonNegative);
  if (c.alpha > 1.0) {
    ThrowConfigError(map.file(), map.Optional("alpha"), map.KeyPath("alpha"),
                     "a number in [0, 1]", NumberText(c.alpha));
  }
  c.U_max = map.Number("U_max", d.U_max, Range::kPositive);
  c.delay_samples = static_cast<int>(
      map.Integer("delay_samples", d.delay_samples, 0, 1000));
  c.counts_per_rev = map.Number("counts_per_rev", d.counts_per_rev,
                                Range::kNonNegative);
  c.load_quantum = map.Number("load_quantum", d.load_quantum,
                              Range::kNonNegative);
  map.Finish();
  return c;
}

void CheckSupplyPositive(const InputSignal& supply, const YamlMap& map,
                         const YAML::Node& node, const std::string& key) {
  std::ostringstream got;
  got << std::setprecision(6);
  if (supply.kind == InputSignal::Kind::kTable) {
    for (size_t k = 0; k < supply.values.size(); ++k) {
      const double v = supply.values[k] + supply.offset;
      if (std::isfinite(v) && v > 0.0) continue;
      got << v << " V at t = " << supply.times[k] << " s";
      ThrowConfigError(map.file(), node, key, "a supply voltage > 0 V throughout", got.str());
    }
    return;
  }
  double least = supply.offset;
  switch (supply.kind) {
    case InputSignal::Kind::kStep:
      least = std::min(supply.offset, supply.offset + supply.amplitude);
      break;
    case InputSignal::Kind::kSine:
    case InputSignal::Kind::kChirp:
      least = supply.offset - std::abs(supply.amplitude);
      break;
    default:  // zero, and a ramp at its start
      break;
  }
  if (std::isfinite(least) && least > 0.0) return;
  got << "a least value of " << least << " V";
  ThrowConfigError(map.file(), node, key, "a supply voltage > 0 V throughout", got.str());
}

}  // namespace axis
