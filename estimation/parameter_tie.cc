#include "estimation/parameter_tie.h"

#include <algorithm>
#include <stdexcept>

#include "estimation/fit_result.h"

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

void ApplyResultTies(const FitResult& result, AxisParams<double>* params) {
  for (const ParameterEstimate& e : result.parameters) {
    if (e.tied_to.empty()) continue;
    double* field = FindParam(params, e.name);
    const double* source = FindParam(params, e.tied_to);
    if (field != nullptr && source != nullptr) *field = *source;
  }
}

void CopyTiedUncertainty(FitResult* result) {
  for (ParameterEstimate& e : result->parameters) {
    if (e.tied_to.empty()) continue;
    for (const ParameterEstimate& source : result->parameters) {
      if (!source.free || source.name != e.tied_to) continue;
      e.initial = source.initial;
      e.std_error = source.std_error;
      e.std_error_gauss_newton = source.std_error_gauss_newton;
      e.std_error_bootstrap = source.std_error_bootstrap;
      e.bootstrap_low = source.bootstrap_low;
      e.bootstrap_high = source.bootstrap_high;
      e.ci95_low = source.ci95_low;
      e.ci95_high = source.ci95_high;
      e.interval_method = source.interval_method;
      e.std_error_sandwich = source.std_error_sandwich;
    }
  }
}

}  // namespace axis
