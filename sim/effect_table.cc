#include "sim/effect_table.h"

#include <string>
#include <vector>

#include "sim/channels.h"
#include "sim/force_map.h"

namespace axis {

const std::vector<EffectInfo>& DynamicEffectTable() {
  static const std::vector<EffectInfo> effects = {
      {"coulomb", {"F_c"}, &EffectSwitches::coulomb},
      {"stribeck", {"F_st", "v_st"}, &EffectSwitches::stribeck},
      {"viscous_asymmetry", {"Delta_B"}, &EffectSwitches::viscous_asymmetry},
      {"load_offset", {"F_0"}, &EffectSwitches::load_offset},
      {"spring", {"k_x", "x_0"}, &EffectSwitches::spring},
      {"payload", {"Delta_M"}, &EffectSwitches::payload},
      {"motor_coulomb", {"T_c"}, &EffectSwitches::motor_coulomb},
      {"cogging", {"A_cog", "phi_cog"}, &EffectSwitches::cogging},
      {"load_friction", {"mu_d", "mu_b"}, &EffectSwitches::load_friction},
      {"stribeck_shape", {"delta_st"}, &EffectSwitches::stribeck_shape},
  };
  return effects;
}

const std::vector<EffectInfo>& GeneratorOnlyEffectTable() {
  static const std::vector<EffectInfo> effects = {
      {"friction_patch", {"F_pt", "x_pt0", "x_pt1", "w_pt"}, &EffectSwitches::friction_patch},
      {"quadratic_drag", {"C_d"}, &EffectSwitches::quadratic_drag},
      {"position_ripple", {"F_rp", "lambda_rp", "phi_rp"}, &EffectSwitches::position_ripple},
      {"velocity_bump", {"F_vb", "v_vb", "w_vb"}, &EffectSwitches::velocity_bump},
  };
  return effects;
}

bool IsEffectName(const std::string& name, bool allow_bare_sensor) {
  const size_t dot = name.find('.');
  const std::string effect = name.substr(0, dot);
  for (const SensorEffectInfo& e : SensorEffectTable()) {
    if (effect != e.name) continue;
    if (dot == std::string::npos) return allow_bare_sensor;
    return ParseChannel(name.substr(dot + 1)).has_value();
  }
  if (dot != std::string::npos) return false;
  for (const EffectInfo& e : DynamicEffectTable()) {
    if (effect == e.name) return true;
  }
  return false;
}

bool IsFrontEndEffect(const std::string& name) {
  const std::string effect = name.substr(0, name.find('.'));
  if (effect == "accelerometer") return true;
  for (const SensorEffectInfo& e : SensorEffectTable()) {
    if (effect == e.name) return true;
  }
  return false;
}

std::string GeneratorOnlyEffectNameList() {
  std::string list;
  for (const EffectInfo& e : GeneratorOnlyEffectTable()) {
    list += (list.empty() ? "" : ", ") + std::string(e.name);
  }
  return list;
}

std::vector<std::string> EnabledEffectNames(const AxisStructure& s) {
  std::vector<std::string> out;
  for (const EffectInfo& e : DynamicEffectTable()) {
    if (s.effects.*(e.flag)) out.push_back(e.name);
  }
  for (int c = 0; c < kNumChannels; ++c) {
    const std::string channel = ChannelName(static_cast<Channel>(c));
    for (const SensorEffectInfo& e : SensorEffectTable()) {
      if ((s.sensors.*(e.flag))[static_cast<size_t>(c)]) out.push_back(e.name + ("." + channel));
    }
  }
  if (s.force_map.enabled) out.push_back("force_map." + ForceMapKind(s.force_map));
  return out;
}

std::string EffectNameList() {
  std::string list;
  for (const EffectInfo& e : DynamicEffectTable()) list += std::string(e.name) + ", ";
  for (const SensorEffectInfo& e : SensorEffectTable()) {
    list += e.name + std::string("[.channel]") + (&e == &SensorEffectTable().back() ? "" : ", ");
  }
  return list;
}

}  // namespace axis
