#include "sim/axis_params.h"

namespace axis {

const std::vector<SensorEffectInfo>& SensorEffectTable() {
  static const std::vector<SensorEffectInfo> effects = {
      {"sensor_delay", {"tau_d"}, &SensorSwitches::delay},
      {"sensor_bias", {"b"}, &SensorSwitches::bias},
      {"sensor_lowpass", {"tau_lp"}, &SensorSwitches::lowpass},
      {"sensor_lowpass2", {"tau_lp2", "zeta_lp2"}, &SensorSwitches::lowpass2},
  };
  return effects;
}

bool IsSensorParameter(const std::string& name) {
  for (const SensorEffectInfo& e : SensorEffectTable()) {
    for (const char* prefix : e.params) {
      const std::string head = std::string(prefix) + ".";
      if (name.compare(0, head.size(), head) == 0) return true;
    }
  }
  return false;
}

std::vector<ParamInfo> ListParams() {
  std::vector<ParamInfo> out;
  AxisParams<double> p;
  VisitParams([&](const char* name, const char* unit,
                  double&) { out.push_back({name, unit}); },
              p);
  return out;
}

std::string ParamUnit(const std::string& name) {
  for (const ParamInfo& info : ListParams()) {
    if (info.name == name) return info.unit;
  }
  return "";
}

std::string ParamUnit(const std::string& name, Motion motion) {
  const std::string unit = ParamUnit(name);
  if (motion == Motion::kLinear || unit.empty()) return unit;
  // The load's parameters (MODEL.md §2–§7): the motor's, the drive's, the
  // pendulum's and the time constants keep their units.
  static const char* const kLoadSide[] = {
      "H", "M", "B_a", "b_g", "k_g", "F_s", "w", "g_F", "v_eps", "F_c", "F_st", "v_st",
      "Delta_B", "F_0", "k_x", "x_0", "Delta_M", "F_pt", "x_pt0", "x_pt1", "w_pt", "C_d",
      "F_rp", "lambda_rp", "F_vb", "v_vb", "w_vb"};
  if (name == "r_g") return "rad/rad";  // load radians per motor radian
  for (const char* load : kLoadSide) {
    if (name == load) return RotaryLoadUnit(unit);
  }
  if (name.compare(0, 6, "f_map.") == 0) return RotaryLoadUnit(unit);
  if (name.compare(0, 2, "b.") == 0) {
    const std::optional<Channel> c = ParseChannel(name.substr(2));
    if (c) return ChannelUnit(*c, true);
  }
  return unit;
}

double* FindParam(AxisParams<double>* params, const std::string& name) {
  double* found = nullptr;
  VisitParams([&](const char* n, const char*, double& field) {
    if (name == n) found = &field;
  }, *params);
  return found;
}

}  // namespace axis
