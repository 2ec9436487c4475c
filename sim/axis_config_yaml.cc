#include "sim/axis_config_yaml.h"

#include <algorithm>
#include <array>
#include <set>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "sim/effect_table.h"

namespace axis {
namespace {

const std::vector<std::string> kCurrentLoops = {"full", "quasi_steady"};

// The `effects:` block of AxisConfigToYaml (none if nothing is switched
// on): each switched effect with its parameters, the force map, the sensor
// delays and biases. `params`: a copy of config.params (FindParam reads
// through a mutable pointer).
void EmitEffects(const AxisConfig& config, AxisParams<double>& params, YAML::Emitter& out) {
  const EffectSwitches& sw = config.structure.effects;
  const SensorSwitches& sensors = config.structure.sensors;
  bool any_sensor = false;
  for (const SensorEffectInfo& e : SensorEffectTable()) {
    for (bool on : sensors.*(e.flag)) any_sensor = any_sensor || on;
  }
  bool any = any_sensor || config.structure.force_map.enabled;
  std::vector<const EffectInfo*> switched;
  for (const auto* table : {&DynamicEffectTable(), &GeneratorOnlyEffectTable()}) {
    for (const EffectInfo& e : *table) {
      // A Stribeck exponent off the Gaussian 2 (a job that freed
      // delta_st) is written as its own block too, so that it loads back.
      const bool shaped = std::string(e.name) == "stribeck_shape" &&
                          sw.stribeck && config.params.delta_st != kGaussianStribeckShape;
      if (sw.*(e.flag) || shaped) switched.push_back(&e);
    }
  }
  any = any || !switched.empty();
  if (!any) return;
  out << YAML::Key << "effects" << YAML::Value << YAML::BeginMap;
  for (const EffectInfo* effect : switched) {
    const EffectInfo& e = *effect;
    out << YAML::Key << e.name << YAML::Value << YAML::BeginMap;
    for (const char* p : e.params) {
      out << YAML::Key << p << YAML::Value << *FindParam(&params, p);
    }
    if (std::string(e.name) == "cogging") {
      out << YAML::Key << "N_cog" << YAML::Value << config.structure.N_cog;
    }
    out << YAML::EndMap;
  }
  if (config.structure.force_map.enabled) {
    const ForceMap& f = config.structure.force_map;
    out << YAML::Key << "force_map" << YAML::Value << YAML::BeginMap << YAML::Key
        << "variable" << YAML::Value << (f.variable == ForceMapVariable::kV ? "v" : "x")
        << YAML::Key << "friction" << YAML::Value << (f.friction ? "true" : "false")
        << YAML::Key << "knots" << YAML::Value << YAML::Flow << f.knots << YAML::Key
        << "values" << YAML::Value << YAML::Flow
        << std::vector<double>(params.f_map.begin(), params.f_map.begin() + f.knots.size())
        << YAML::EndMap;
  }
  for (const SensorEffectInfo& e : SensorEffectTable()) {
    const std::array<bool, kNumChannels>& on = sensors.*(e.flag);
    if (std::find(on.begin(), on.end(), true) == on.end()) continue;
    out << YAML::Key << e.name << YAML::Value << YAML::BeginMap;
    for (int c = 0; c < kNumChannels; ++c) {
      if (!on[c]) continue;
      const std::string suffix = std::string(".") + ChannelName(static_cast<Channel>(c));
      out << YAML::Key << ChannelName(static_cast<Channel>(c)) << YAML::Value;
      if (e.params.size() == 1) {
        out << *FindParam(&params, e.params[0] + suffix);
      } else {
        out << YAML::Flow << YAML::BeginMap << YAML::Key << "tau" << YAML::Value
            << *FindParam(&params, e.params[0] + suffix) << YAML::Key << "zeta" << YAML::Value
            << *FindParam(&params, e.params[1] + suffix) << YAML::EndMap;
      }
    }
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

// The `controller:` block of AxisConfigToYaml.
void EmitController(const ControllerConfig& c, YAML::Emitter& out) {
  if (c.firmware.enabled) {  // its own keys: an experiment's {kp: ...} re-derives the law
    const ServoFirmware& f = c.firmware;
    out << YAML::Key << "controller" << YAML::Value << YAML::BeginMap
        << YAML::Key << "type" << YAML::Value << "servo_firmware"
        << YAML::Key << "kp" << YAML::Value << f.kp
        << YAML::Key << "ki" << YAML::Value << f.ki
        << YAML::Key << "kd" << YAML::Value << f.kd
        << YAML::Key << "kp_divisor" << YAML::Value << f.kp_divisor
        << YAML::Key << "ki_divisor" << YAML::Value << f.ki_divisor
        << YAML::Key << "kd_divisor" << YAML::Value << f.kd_divisor
        << YAML::Key << "pwm_full_scale" << YAML::Value << f.pwm_full_scale
        << YAML::Key << "pwm_limit" << YAML::Value << f.pwm_limit
        << YAML::Key << "counts_per_rev" << YAML::Value << f.counts_per_rev
        << YAML::Key << "quantized" << YAML::Value << (f.quantized ? "true" : "false")
        << YAML::Key << "T_s" << YAML::Value << c.T_s
        << YAML::Key << "delay_samples" << YAML::Value << c.delay_samples
        << YAML::EndMap;
    return;
  }
  out << YAML::Key << "controller" << YAML::Value << YAML::BeginMap
      << YAML::Key << "T_s" << YAML::Value << c.T_s
      << YAML::Key << "T_track" << YAML::Value << c.T_track
      << YAML::Key << "G_ff" << YAML::Value << c.G_ff
      << YAML::Key << "G_p" << YAML::Value << c.G_p
      << YAML::Key << "G_i" << YAML::Value << c.G_i
      << YAML::Key << "G_v" << YAML::Value << c.G_v
      << YAML::Key << "alpha" << YAML::Value << c.alpha
      << YAML::Key << "U_max" << YAML::Value << c.U_max
      << YAML::Key << "delay_samples" << YAML::Value << c.delay_samples
      << YAML::Key << "counts_per_rev" << YAML::Value << c.counts_per_rev
      << YAML::Key << "load_quantum" << YAML::Value << c.load_quantum
      << YAML::EndMap;
}

}  // namespace

std::string AxisConfigToYaml(const AxisConfig& config) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << config.name;
  out << YAML::Key << "source" << YAML::Value << config.source;
  const char* amplifiers[] = {"analog_velocity_loop", "current_source", "force_source",
                              "voltage_drive"};
  static_assert(static_cast<int>(Amplifier::kVoltageDrive) == 3, "one name per Amplifier");
  out << YAML::Key << "amplifier" << YAML::Value
      << amplifiers[static_cast<int>(config.structure.amplifier)];
  out << YAML::Key << "coupling" << YAML::Value
      << (config.structure.coupling == Coupling::kRigid ? "rigid" : "gear");
  out << YAML::Key << "current_loop" << YAML::Value
      << kCurrentLoops[static_cast<int>(config.structure.current_loop)];
  out << YAML::Key << "inductance" << YAML::Value
      << (config.structure.inductance ? "true" : "false");
  out << YAML::Key << "accelerometer" << YAML::Value
      << (config.structure.accelerometer == AccelerometerSampling::kInstant
              ? "instant"
              : "period_mean");
  out << YAML::Key << "instant_window" << YAML::Value << config.structure.instant_window;
  out << YAML::Key << "motion" << YAML::Value
      << (config.structure.motion == Motion::kRotary ? "rotary" : "linear");
  const char* loads[] = {"none", "gravity", "pendulum"};
  out << YAML::Key << "load" << YAML::Value << loads[static_cast<int>(config.structure.load)];
  // Parameters of MODEL.md §2 and §4, and the sgn_ε widths v_eps and
  // omega_eps of §7 (effect parameters go with their effect).
  std::set<std::string> effect_params;
  for (const auto* table : {&DynamicEffectTable(), &GeneratorOnlyEffectTable()}) {
    for (const EffectInfo& e : *table) {
      for (const char* p : e.params) effect_params.insert(p);
    }
  }
  out << YAML::Key << "parameters" << YAML::Value << YAML::BeginMap;
  AxisParams<double> params = config.params;
  VisitParams([&](const char* name, const char*, double& value) {
    const std::string n = name;
    if (n.find('.') != std::string::npos || effect_params.count(n)) return;
    out << YAML::Key << n << YAML::Value << value;
  }, params);
  out << YAML::EndMap;
  EmitEffects(config, params, out);
  if (config.has_controller) EmitController(config.controller, out);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace axis
