#include "sim/force_map.h"

#include <cmath>
#include <sstream>

namespace axis {

std::string ForceMapKind(const ForceMap& map) {
  if (map.variable == ForceMapVariable::kV) return "v";
  return map.friction ? "x_friction" : "x";
}

std::string ForceMapKnotsProblem(const std::vector<double>& knots) {
  std::ostringstream out;
  const int n = static_cast<int>(knots.size());
  if (n < kMinForceMapKnots || n > kMaxForceMapKnots) {
    out << "expected " << kMinForceMapKnots << " to " << kMaxForceMapKnots << " knots, got " << n;
    return out.str();
  }
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(knots[k])) {
      out << "expected finite knots, got " << knots[k] << " (knot " << k << ")";
      return out.str();
    }
    if (k > 0 && !(knots[k] > knots[k - 1])) {
      out << "expected strictly increasing knots, got " << knots[k] << " after "
          << knots[k - 1] << " (knot " << k << ")";
      return out.str();
    }
  }
  return "";
}

}  // namespace axis
