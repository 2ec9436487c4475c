// The estimate of one parameter in a fit's result, by name (the loop's
// widened search bounds, the Wald test and the plausibility rules).
#ifndef DISCOVERY_INTERNAL_FIND_ESTIMATE_H_
#define DISCOVERY_INTERNAL_FIND_ESTIMATE_H_

#include <string>

#include "estimation/fit_result.h"

namespace axis {

// The estimate of `name` in `fit` (FitResult::parameters, free or fixed),
// or nullptr; the pointer is into `fit`. Never throws.
const ParameterEstimate* FindEstimate(const FitResult& fit, const std::string& name);

}  // namespace axis

#endif  // DISCOVERY_INTERNAL_FIND_ESTIMATE_H_
