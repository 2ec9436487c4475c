#include "estimation/internal/start_agreement.h"

#include <algorithm>
#include <cmath>

namespace axis {

double SameMinimumTolerance(double s2, double resolution) {
  const double tol = 0.5 * kSameMinimumChi2 * s2;
  return std::isfinite(tol) ? std::max(tol, resolution) : resolution;
}

StartVerdict JudgeStarts(double job_cost, const std::vector<double>& start_costs,
                         double tolerance) {
  int same = 0;
  bool higher = false;
  for (double c : start_costs) {
    if (!std::isfinite(c)) continue;
    if (c < job_cost - tolerance) return StartVerdict::kLower;
    if (c > job_cost + tolerance) {
      higher = true;
    } else {
      ++same;
    }
  }
  return same > 0 && !higher ? StartVerdict::kSame : StartVerdict::kUndecided;
}

}  // namespace axis
