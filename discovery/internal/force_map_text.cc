#include "discovery/internal/force_map_text.h"

namespace axis {

const char* VariableUnit(const ForceMap& map, bool rotary) {
  if (map.variable == ForceMapVariable::kV) return rotary ? "rad/s" : "m/s";
  return rotary ? "rad" : "m";
}

const char* MapForceUnit(bool rotary) { return rotary ? "N*m" : "N"; }

const char* VariableName(const ForceMap& map) {
  return map.variable == ForceMapVariable::kV ? "v" : "x";
}

// "f(x)·sgn(v)" style description of the form.
std::string FormText(const ForceMap& map) {
  if (map.variable == ForceMapVariable::kV) return "f(v)";
  return map.friction ? "f(x)*sgn(v)" : "f(x)";
}

}  // namespace axis
