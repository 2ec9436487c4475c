// The force map's variable and form as the reports name them
// (discovery/force_map.h: the text, report.json, the CSV and the plot).
#ifndef DISCOVERY_INTERNAL_FORCE_MAP_TEXT_H_
#define DISCOVERY_INTERNAL_FORCE_MAP_TEXT_H_

#include <string>

#include "sim/force_map.h"

namespace axis {

// The unit of the map's variable: "m/s" for f(v), else "m"; "rad/s" and
// "rad" on a rotary axis (`rotary`, AxisStructure::motion). Never throws.
const char* VariableUnit(const ForceMap& map, bool rotary);

// The unit of the map's values: "N", or "N*m" on a rotary axis. Never throws.
const char* MapForceUnit(bool rotary);

// The map's variable: "v" for f(v), else "x". Never throws.
const char* VariableName(const ForceMap& map);

// "f(x)*sgn(v)" style description of the form. Never throws.
std::string FormText(const ForceMap& map);

}  // namespace axis

#endif  // DISCOVERY_INTERNAL_FORCE_MAP_TEXT_H_
