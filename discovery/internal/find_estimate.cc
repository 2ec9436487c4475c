#include "discovery/internal/find_estimate.h"

namespace axis {

// The estimate of `name` in `fit`, or nullptr.
const ParameterEstimate* FindEstimate(const FitResult& fit, const std::string& name) {
  for (const ParameterEstimate& e : fit.parameters) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

}  // namespace axis
