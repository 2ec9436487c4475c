// A parameter tied to another: the job key `tie: {K_e: K_tau}` makes the
// model parameter K_e take K_tau's value wherever the fit sets parameters
// (ParameterMap::Apply, ApplyEstimates), free or fixed. For constants that
// physics makes equal but a model lists apart: in SI units a DC motor's
// back-EMF constant K_e (V·s/rad) is its torque constant K_τ (N·m/A)
// (MODEL.md §4, the voltage drive). With both free and R fixed, a voltage
// drive's records determine only K_τ/R and K_τ·K_e/R, so a fixed R that is
// off shows as K_e ≠ K_τ; tied, with R free, the same two products are
// fitted by K_τ and R (configs/README.md `tie:`).
#ifndef ESTIMATION_PARAMETER_TIE_H_
#define ESTIMATION_PARAMETER_TIE_H_

#include <string>
#include <utility>
#include <vector>

#include "sim/axis_params.h"

namespace axis {

struct FitResult;  // estimation/fit_result.h

// `parameter` takes the value of `source` (both VisitParams names). The job
// loader (run/load_fit_job.cc) refuses a tied parameter that is free, a
// source that is itself tied, a parameter tied twice and names that are no
// model parameter.
struct ParameterTie {
  std::string parameter;  // e.g. "K_e"
  std::string source;     // e.g. "K_tau"
};

// The VisitParams positions of each tie's (parameter, source), in `ties`
// order. Throws std::invalid_argument naming an unknown name.
std::vector<std::pair<int, int>> TieIndices(const std::vector<ParameterTie>& ties);

// Sets each tied parameter of `params` to its source's value, for
// `indices` = TieIndices(ties). T: double or a ceres::Jet (the tied field
// then carries the source's derivatives). Never throws but std::bad_alloc.
template <typename T>
void ApplyTies(const std::vector<std::pair<int, int>>& indices, AxisParams<T>* params) {
  if (indices.empty()) return;
  std::vector<T*> fields;
  VisitParams([&](const char*, const char*, T& field) { fields.push_back(&field); }, *params);
  for (const auto& [parameter, source] : indices) *fields[parameter] = *fields[source];
}

// The source `name` is tied to, or "" if it is not tied. Never throws.
std::string TiedTo(const std::vector<ParameterTie>& ties, const std::string& name);

// Sets each parameter `result` reports tied (ParameterEstimate::tied_to)
// to its source's value in `params`: for models moved away from the
// estimate after the fit (the tuner's interval ends and joint samples,
// tune/). Never throws.
void ApplyResultTies(const FitResult& result, AxisParams<double>* params);

// Gives each tied estimate of result->parameters the initial value,
// standard errors, bootstrap figures and interval of its source where the
// source is free (the same value); run again by every step that changes
// the free ones' (the fit's end, the sandwich errors, the bootstrap, the
// carried quasi-steady intervals). Never throws.
void CopyTiedUncertainty(FitResult* result);

}  // namespace axis

#endif  // ESTIMATION_PARAMETER_TIE_H_
