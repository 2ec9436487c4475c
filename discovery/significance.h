// Whether an effect a fit selected stands: significantly different from
// off (a Wald test, issue 10), and physical at its fitted value.
#ifndef DISCOVERY_SIGNIFICANCE_H_
#define DISCOVERY_SIGNIFICANCE_H_

#include <string>

#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"

namespace axis {

// Wald test of one effect of a fitted model against the value that
// switches it off (issue 10: an effect in the final model must differ
// significantly from off). χ² = dᵀ·Σ⁻¹·d, Σ the covariance of the fit's
// free parameters (std_error·correlation·std_error, scaled by the residual
// variance), d the deviation from off:
// - F_c, ΔB, F_0, k_x, ΔM, T_c, τ_d.<ch>, b.<ch> from 0 (dof 1);
// - Stribeck: F_st − F_c from 0 (dof 1; F_c's variance 0 if it is fixed);
// - cogging: (A_cog·cos φ, A_cog·sin φ) from (0, 0) (dof 2; by the delta
//   method χ² = A_cog²/(var A − cov(A, φ)²/var φ)).
// A parameter that is fixed or has no finite standard error gives
// p_value NaN (not significant). Throws std::invalid_argument for an
// effect that is not a Candidate::name of MODEL.md §7.
struct EffectSignificance {
  std::string effect;
  double chi2 = 0.0;
  int dof = 1;
  double p_value = 1.0;
};
EffectSignificance EffectWald(const std::string& effect, const FitResult& fit);

// Why the value of `effect` (a Candidate::name) fitted in `fit` has no
// physical meaning, or "" if it has one: a payload below zero (the declared
// mass is too large: a stand-in for M); a Coulomb friction level below zero
// (coulomb F_c, stribeck F_st, motor_coulomb T_c: friction opposes the
// motion); a sensor filter (sensor_lowpass.<ch>, sensor_lowpass2.<ch>) whose
// cut-off 1/(2π·τ) is above the Nyquist frequency of the records fitting
// that channel in `job` (τ < T/π, T the longest output period; on `a`
// under a convention neither model nor job declares, above the sample rate,
// τ < T/(2π): the filter is seen through a convention not yet settled), or a
// second-order one whose damping ζ ended at a bound of its search
// (kLowpass2DampingBounds, discovery/candidates.h; within 1 %). Effects without such a rule — a
// delay of any length, sub-sample included, among them — are physical at
// any value within their bounds.
std::string ImplausibleValue(const std::string& effect, const FitResult& fit,
                             const EstimationProblem& job);

}  // namespace axis

#endif  // DISCOVERY_SIGNIFICANCE_H_
