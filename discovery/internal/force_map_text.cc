#include "discovery/internal/force_map_text.h"

namespace axis {

// The unit of the map's variable.
const char* VariableUnit(const ForceMap& map) {
  return map.variable == ForceMapVariable::kV ? "m/s" : "m";
}

const char* VariableName(const ForceMap& map) {
  return map.variable == ForceMapVariable::kV ? "v" : "x";
}

// "f(x)·sgn(v)" style description of the form.
std::string FormText(const ForceMap& map) {
  if (map.variable == ForceMapVariable::kV) return "f(v)";
  return map.friction ? "f(x)*sgn(v)" : "f(x)";
}

}  // namespace axis
