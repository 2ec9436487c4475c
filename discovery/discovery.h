// The model-discovery loop (issue 4): after a fit, test every effect of
// MODEL.md §7 the model does not have with a Lagrange-multiplier (score)
// test, add the most significant one, refit, keep it if BIC improves, and
// repeat. The score test needs no refit per candidate: it projects the
// candidate's Jacobian column(s), taken at the value that switches the effect
// off, off the span of the free parameters' Jacobian and tests the residual
// against them (Breusch & Pagan 1980; Engle 1984, "Wald, likelihood ratio and
// Lagrange multiplier tests in econometrics", §5).
//
// Where its parts are: the candidates (discovery/candidates.h), the score
// test (discovery/score_test.h), the significance and plausibility of an
// effect (discovery/significance.h), the removal of an effect
// (discovery/removal.h), the report (discovery/discovery_report.h), the
// loop's steps (discovery/internal/discovery_loop.h).
#ifndef DISCOVERY_DISCOVERY_H_
#define DISCOVERY_DISCOVERY_H_

#include <functional>
#include <ostream>

#include "discovery/discovery_report.h"
#include "estimation/fit_result.h"
#include "discovery/discovery_settings.h"
#include "estimation/estimation_problem.h"

namespace axis {

// Runs the loop from the fit `result` of `job`; on return `job` and `result`
// hold the augmented model and its fit. After the forward steps, one
// backward pass refits without each added effect but the last (an effect
// added while a later one was missing may have stood in for it) and drops
// it if BIC improves; Coulomb stays while Stribeck is in. Then every effect
// left, the last added first, must pass EffectWald at alpha / (number of
// candidates at the first step), or is refitted away and dropped whatever
// BIC says. Last, the final model's residuals are diagnosed and judged
// (JudgeResiduals at alpha). Progress lines go to `progress`. Refits that
// cannot win stop early (issue 11): a refit whose BIC's lower bound on a
// shorter horizon passes twice the deciding level stops there
// (DiscoveryStep::stopped); when several candidates are refitted at once
// (s² far above 1), a screen of their first four horizons orders them, and
// the lowest there runs first and alone to set that level.
// `stage`, if set, is called with the name of each step as it begins
// ("discovery step 1 (at most 3)", "discovery backward pass"), for the
// run's phases (common/phase_log.h).
DiscoveryReport Discover(const DiscoverySettings& settings, EstimationProblem* job,
                         FitResult* result, std::ostream* progress,
                         const std::function<void(const char*)>& stage = {});

}  // namespace axis

#endif  // DISCOVERY_DISCOVERY_H_
