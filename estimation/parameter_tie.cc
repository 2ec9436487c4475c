#include "estimation/parameter_tie.h"

#include <algorithm>
#include <stdexcept>

namespace axis {

std::vector<std::pair<int, int>> TieIndices(const std::vector<ParameterTie>& ties) {
  std::vector<std::pair<int, int>> indices;
  if (ties.empty()) return indices;
  std::vector<std::string> names;
  const AxisParams<double> any;
  VisitParams([&](const char* name, const char*, const double&) { names.push_back(name); }, any);
  const auto index = [&](const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) {
      throw std::invalid_argument("expected a model parameter name, got '" + name + "'");
    }
    return static_cast<int>(it - names.begin());
  };
  for (const ParameterTie& tie : ties) {
    indices.emplace_back(index(tie.parameter), index(tie.source));
  }
  return indices;
}

std::string TiedTo(const std::vector<ParameterTie>& ties, const std::string& name) {
  for (const ParameterTie& tie : ties) {
    if (tie.parameter == name) return tie.source;
  }
  return "";
}

}  // namespace axis
