#include "sim/force_map.h"

#include <cmath>
#include <sstream>

namespace axis {

std::string ForceMapKind(const ForceMap& map) {
  if (map.variable == ForceMapVariable::kV) return "v";
  return map.friction ? "x_friction" : "x";
}

KnotsProblem ForceMapKnotsProblem(const std::vector<double>& knots) {
  const auto text = [](double x) {
    std::ostringstream out;
    out << x;
    return out.str();
  };
  const int n = static_cast<int>(knots.size());
  if (n < kMinForceMapKnots || n > kMaxForceMapKnots) {
    return {std::to_string(kMinForceMapKnots) + " to " + std::to_string(kMaxForceMapKnots) +
                " knots",
            std::to_string(n)};
  }
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(knots[k])) {
      return {"finite knots", text(knots[k]) + " (knot " + std::to_string(k) + ")"};
    }
    if (k > 0 && !(knots[k] > knots[k - 1])) {
      return {"strictly increasing knots", text(knots[k]) + " after " + text(knots[k - 1]) +
                                               " (knot " + std::to_string(k) + ")"};
    }
  }
  return {};
}

}  // namespace axis
