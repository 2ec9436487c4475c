#include "tune/tune_settings.h"

#include <algorithm>
#include <cmath>

#include "common/format.h"
#include "io/yaml_util.h"

namespace axis {
namespace {

using Range = YamlMap::Range;

// `key` of `map` in [low, high] (an inclusive or exclusive end as said by
// `expected`), else the config error naming it.
double Within(YamlMap& map, const std::string& key, double fallback, double low, double high,
              bool open_low, const std::string& expected) {
  const double x = map.Number(key, fallback, Range::kAny);
  const bool above = open_low ? x > low : x >= low;
  if (map.Has(key) && !(above && x <= high)) {
    ThrowConfigError(map.file(), map.Optional(key), map.KeyPath(key), expected, FormatNumber(x));
  }
  return x;
}

void ParseStep(YamlMap& tune, TuneSpec* s) {
  const YAML::Node node = tune.Optional("step");
  if (!node) return;
  YamlMap map(node, tune.file(), "tune.step.");
  s->step_voltage = Within(map, "voltage", s->step_voltage, 0.0, 10.0, true,
                           "a set-velocity voltage in (0, 10] V");
  s->duration = Within(map, "duration", s->duration, 0.1, 60.0, false,
                       "a simulated time in [0.1, 60] s");
  map.Finish();
}

void ParseSpec(YamlMap& tune, TuneSpec* s) {
  const YAML::Node node = tune.Optional("spec");
  if (!node) return;
  YamlMap map(node, tune.file(), "tune.spec.");
  constexpr double kBig = 1e30;
  s->settling_band = Within(map, "settling_band", s->settling_band, 0.0, 0.5, true,
                            "a fraction of the final velocity in (0, 0.5]");
  s->ringing_after = Within(map, "ringing_after", s->ringing_after, 0.0, 60.0, false,
                            "a time in [0, 60] s");
  s->max_settling_time = Within(map, "settling_time", s->max_settling_time, 0.0, kBig, true,
                                "a settling time > 0 s");
  s->max_overshoot = Within(map, "overshoot", s->max_overshoot, 0.0, kBig, false,
                            "a fraction of the final velocity >= 0");
  s->max_current = Within(map, "current", s->max_current, 0.0, kBig, true,
                          "the motor's current rating > 0 A");
  s->min_voltage_headroom = Within(map, "voltage_headroom", s->min_voltage_headroom, 0.0, kBig,
                                   false, "a margin >= 0 V");
  s->max_ringing = Within(map, "ringing", s->max_ringing, 0.0, kBig, true,
                          "a residual vibration > 0 m/s");
  s->max_ringing_decay = Within(map, "ringing_decay", s->max_ringing_decay, 0.0, kBig, true,
                                "an e-folding time > 0 s");
  s->velocity_gain = Within(map, "velocity_gain", s->velocity_gain, 0.0, kBig, true,
                            "a velocity gain > 0 m/s per V");
  map.Finish();
}

void ParseTp(YamlMap& tune, TuneSettings* out) {
  const YAML::Node node = tune.Optional("T_p");
  if (!node) return;
  YamlMap map(node, tune.file(), "tune.T_p.");
  out->T_p_low = Within(map, "low", out->T_p_low, 0.0, 100.0, true, "a time constant in (0, 100] s");
  out->T_p_high =
      Within(map, "high", out->T_p_high, 0.0, 100.0, true, "a time constant in (0, 100] s");
  if (!(out->T_p_low < out->T_p_high)) {
    ThrowConfigError(tune.file(), node, "tune.T_p", "low < high",
                     FormatNumber(out->T_p_low) + " and " + FormatNumber(out->T_p_high));
  }
  out->curve_points = static_cast<int>(map.Integer("points", out->curve_points, 5, 200));
  map.Finish();
}

void ParseMoveSpec(YamlMap& move, MoveSpec* s) {
  constexpr double kBig = 1e30;
  s->distance = move.Number("distance", s->distance, Range::kAny);
  if (move.Has("distance") && s->distance == 0.0) {
    ThrowConfigError(move.file(), move.Optional("distance"), move.KeyPath("distance"),
                     "a nonzero distance in m", "0");
  }
  if (const YAML::Node node = move.Optional("limits")) {
    YamlMap map(node, move.file(), "tune.move.limits.");
    s->max_velocity = map.Number("velocity", s->max_velocity, Range::kPositive);
    s->max_acceleration = map.Number("acceleration", s->max_acceleration, Range::kPositive);
    s->max_jerk = map.Number("jerk", s->max_jerk, Range::kPositiveOrInfinite);
    map.Finish();
  }
  if (const YAML::Node node = move.Optional("profiles")) {
    s->profiles.clear();
    if (!node.IsSequence() || node.size() == 0) {
      ThrowConfigError(move.file(), node, "tune.move.profiles",
                       "a list of trapezoid and/or min_jerk", "not a nonempty list");
    }
    for (const YAML::Node& p : node) {
      const std::string name = p.IsScalar() ? p.Scalar() : "";
      if (name != "trapezoid" && name != "min_jerk") {
        ThrowConfigError(move.file(), p, "tune.move.profiles", "trapezoid or min_jerk",
                         name.empty() ? "not a name" : name);
      }
      s->profiles.push_back(name);
    }
  }
  s->settle = Within(move, "settle", s->settle, 0.05, 60.0, false, "a time in [0.05, 60] s");
  if (const YAML::Node node = move.Optional("spec")) {
    YamlMap map(node, move.file(), "tune.move.spec.");
    s->position_band = Within(map, "position_band", s->position_band, 0.0, kBig, true,
                              "a band > 0 m");
    s->ringing_after = Within(map, "ringing_after", s->ringing_after, 0.0, 60.0, false,
                              "a time in [0, 60] s");
    s->max_settling_time = Within(map, "settling_time", s->max_settling_time, 0.0, kBig, false,
                                  "a settling time >= 0 s");
    s->max_following_error = Within(map, "following_error", s->max_following_error, 0.0, kBig,
                                    true, "a following error > 0 m");
    s->max_overshoot = Within(map, "overshoot", s->max_overshoot, 0.0, kBig, false,
                              "an overshoot >= 0 m");
    s->max_current = Within(map, "current", s->max_current, 0.0, kBig, true,
                            "the motor's current rating > 0 A");
    s->max_ringing = Within(map, "ringing", s->max_ringing, 0.0, kBig, true,
                            "a residual vibration > 0 m");
    map.Finish();
  }
}

void ParseGains(YamlMap& move, MoveTuneSettings* out) {
  const YAML::Node node = move.Optional("gains");
  if (!node) return;
  YamlMap map(node, move.file(), "tune.move.gains.");
  out->gains.clear();
  for (const char* name : {"G_p", "G_i", "G_v", "G_ff", "alpha"}) {
    const YAML::Node g = map.Optional(name);
    if (!g) continue;
    const std::string key = std::string("tune.move.gains.") + name;
    if (!g.IsSequence() || g.size() != 2) {
      ThrowConfigError(move.file(), g, key, "[low, high]", "not a pair");
    }
    const double low = map.NumberFrom(g[0], key + "[0]", Range::kNonNegative);
    const double high = map.NumberFrom(g[1], key + "[1]", Range::kPositive);
    const bool alpha = std::string(name) == "alpha";
    if (!(low < high && (!alpha || (low > 0.0 && high <= 1.0)))) {
      ThrowConfigError(move.file(), g, key,
                       alpha ? "[low, high] with 0 < low < high <= 1" : "[low, high] with 0 <= low < high",
                       FormatNumber(low) + ", " + FormatNumber(high));
    }
    out->gains.push_back({name, low, high});
  }
  map.Finish();
  if (out->gains.empty()) {
    ThrowConfigError(move.file(), node, "tune.move.gains",
                     "at least one of G_p, G_i, G_v, G_ff, alpha", "none");
  }
}

// `[low, high]` at `key` of `map` into *low, *high, with low >= `min`
// (> min if `open`), high < `max` and low < high.
void ParseRange(YamlMap& map, const std::string& key, double min, bool open, double max,
                const std::string& expected, double* low, double* high) {
  const YAML::Node node = map.Optional(key);
  if (!node) return;
  if (!node.IsSequence() || node.size() != 2) {
    ThrowConfigError(map.file(), node, map.KeyPath(key), "[low, high]", "not a pair");
  }
  const double a = map.NumberFrom(node[0], map.KeyPath(key) + "[0]", Range::kAny);
  const double b = map.NumberFrom(node[1], map.KeyPath(key) + "[1]", Range::kAny);
  if (!((open ? a > min : a >= min) && a < b && b < max)) {
    ThrowConfigError(map.file(), node, map.KeyPath(key), expected,
                     FormatNumber(a) + ", " + FormatNumber(b));
  }
  *low = a;
  *high = b;
}

void ParseShapers(YamlMap& move, MoveTuneSettings* out) {
  if (const YAML::Node node = move.Optional("shapers")) {
    std::string names;
    for (size_t k = 1; k < ShaperNames().size(); ++k) {
      names += (names.empty() ? "" : ", ") + ShaperNames()[k];
    }
    if (!node.IsSequence()) {
      ThrowConfigError(move.file(), node, "tune.move.shapers", "a list of " + names,
                       "not a list");
    }
    out->shapers.clear();
    for (const YAML::Node& p : node) {
      ShaperType type = ShaperType::kNone;
      const std::string name = p.IsScalar() ? p.Scalar() : "";
      if (!ParseShaperType(name, &type) || type == ShaperType::kNone) {
        ThrowConfigError(move.file(), p, "tune.move.shapers", "one of " + names,
                         name.empty() ? "not a name" : "'" + name + "'");
      }
      if (std::find(out->shapers.begin(), out->shapers.end(), type) != out->shapers.end()) {
        ThrowConfigError(move.file(), p, "tune.move.shapers", "each shaper once",
                         "'" + name + "' again");
      }
      out->shapers.push_back(type);
    }
  }
  // The longest shaper (3HUMP_EI, two damped periods) at 0.05 Hz lasts
  // 40 s: every search simulates it.
  ParseRange(move, "shaper_frequency", 0.05, false, HUGE_VAL,
             "[low, high] Hz with 0.05 <= low < high", &out->shaper_frequency_low,
             &out->shaper_frequency_high);
  ParseRange(move, "shaper_damping", 0.0, false, 1.0,
             "[low, high] with 0 <= low < high < 1", &out->shaper_damping_low,
             &out->shaper_damping_high);
  for (const char* key : {"shaper_frequency", "shaper_damping"}) {
    if (move.Has(key) && out->shapers.empty()) {
      ThrowConfigError(move.file(), move.Optional(key), move.KeyPath(key),
                       "a range only with tune.move.shapers (the shapers it is searched for)",
                       "no shapers");
    }
  }
}

void ParseKlipper(YamlMap& move, KlipperRuleSettings* out) {
  const YAML::Node node = move.Optional("klipper");
  if (!node) return;
  out->enabled = true;
  if (node.IsNull()) return;  // `klipper:` alone: the defaults
  YamlMap map(node, move.file(), "tune.move.klipper.");
  out->min_freq = Within(map, "min_freq", out->min_freq, 0.0, 1e6, true, "a frequency > 0 Hz");
  out->max_freq = Within(map, "max_freq", out->max_freq, out->min_freq, 1e6, true,
                         "a frequency above min_freq (" + FormatNumber(out->min_freq) + " Hz)");
  out->accel_per_hz = Within(map, "accel_per_hz", out->accel_per_hz, 0.0, 1e6, true,
                             "an acceleration per Hz > 0 m/s^2/Hz");
  out->hz_per_sec = Within(map, "hz_per_sec", out->hz_per_sec, 0.0, 1e6, true,
                           "a sweep rate > 0 Hz/s");
  map.Finish();
  if (!(out->max_freq > out->min_freq)) {
    ThrowConfigError(move.file(), node, "tune.move.klipper.max_freq",
                     "a frequency above min_freq (" + FormatNumber(out->min_freq) + " Hz)",
                     FormatNumber(out->max_freq) + " Hz");
  }
  if ((out->max_freq - out->min_freq) / out->hz_per_sec > 3600.0) {
    ThrowConfigError(move.file(), node, "tune.move.klipper",
                     "a resonance test of at most an hour ((max_freq - min_freq)/hz_per_sec)",
                     FormatNumber((out->max_freq - out->min_freq) / out->hz_per_sec) + " s");
  }
}

void ParseMove(YamlMap& tune, MoveTuneSettings* out) {
  const YAML::Node node = tune.Optional("move");
  if (!node) return;
  YamlMap move(node, tune.file(), "tune.move.");
  out->enabled = true;
  ParseMoveSpec(move, &out->spec);
  ParseGains(move, out);
  ParseShapers(move, out);
  ParseKlipper(move, &out->klipper);
  if (const YAML::Node b = move.Optional("slow_down")) {
    try {
      out->slow_down = b.as<bool>();
    } catch (const YAML::Exception&) {
      ThrowConfigError(move.file(), b, "tune.move.slow_down", "true or false", b.Scalar());
    }
  }
  out->evaluations = static_cast<int>(move.Integer("evaluations", out->evaluations, 20, 5000));
  out->margin = Within(move, "margin", out->margin, 0.0, 0.5, false, "a fraction in [0, 0.5]");
  move.Finish();
}

}  // namespace

void ParseTuneSettings(const YAML::Node& node, const std::string& path, TuneSettings* out) {
  YamlMap tune(node, path, "tune.");
  out->enabled = true;
  ParseStep(tune, &out->spec);
  ParseSpec(tune, &out->spec);
  ParseTp(tune, out);
  out->samples = static_cast<int>(tune.Integer("samples", out->samples, 0, 1000));
  ParseMove(tune, &out->move);
  tune.Finish();
}

}  // namespace axis
