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

double* FindParam(AxisParams<double>* params, const std::string& name) {
  double* found = nullptr;
  VisitParams([&](const char* n, const char*, double& field) {
    if (name == n) found = &field;
  }, *params);
  return found;
}

}  // namespace axis
