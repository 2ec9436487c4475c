// The model-discovery loop (issue 4): after a fit, test every effect of
// MODEL.md §7 the model does not have with a Lagrange-multiplier (score)
// test, add the most significant one, refit, keep it if BIC improves, and
// repeat. The score test needs no refit per candidate: it projects the
// candidate's Jacobian column(s), taken at the value that switches the effect
// off, off the span of the free parameters' Jacobian and tests the residual
// against them (Breusch & Pagan 1980; Engle 1984, "Wald, likelihood ratio and
// Lagrange multiplier tests in econometrics", §5).
#ifndef DISCOVERY_DISCOVERY_H_
#define DISCOVERY_DISCOVERY_H_

#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "discovery/diagnostics.h"
#include "estimation/fit_result.h"
#include "job/discovery_settings.h"
#include "job/fit_job.h"

namespace axis {

// One Jacobian column of a candidate: the derivative of the residual with
// respect to `param` at its current (off) value, with `settings` applied to
// other parameters first (e.g. phi_cog = 0 and π/2 for the two quadratures
// of cogging, whose phase has no effect at zero amplitude).
struct CandidateColumn {
  std::string param;
  std::vector<std::pair<std::string, double>> settings;
};

// A candidate effect: a MODEL.md §7 name, for sensor effects with the channel
// ("sensor_delay.a").
struct Candidate {
  std::string name;
  std::string effect;
  Channel channel = Channel::kT;  // sensor effects only
  std::vector<CandidateColumn> columns;
  // effect "force_map" only (discovery/force_map.h): the map switched on (name
  // "force_map.<kind>", columns its values f_map.<k>).
  ForceMap force_map;
};

// Score test of one candidate at the current fit.
struct Score {
  std::string name;
  double chi2 = 0.0;   // rᵀJ⊥(J⊥ᵀJ⊥)⁻¹J⊥ᵀr / s², s² the residual variance
  int dof = 0;         // number of columns
  double p_value = 1.0;
  double log_p_value = 0.0;  // natural log; finite where p_value is 0
  std::vector<double> step;  // Gauss–Newton step of the columns' parameters
  // The step of each column alone (−gₖ/Iₖₖ: the others held at zero), a
  // start for a refit from one column's shape (Stribeck: one per v_st of
  // the grid, where the joint step of nearly parallel columns can be far
  // larger than any of them).
  std::vector<double> single_step;
};

// Two candidates whose projected columns are nearly parallel (largest
// canonical cosine > 0.95). The residual may still prefer one: the
// conditional score statistic of a given b, chi2(a, b together) − chi2(b),
// tests what a explains beyond b (and vice versa); both below the critical
// value means this data cannot tell them apart.
struct ParallelPair {
  std::string a, b;
  double cosine = 0.0;
  double chi2_a_given_b = 0.0;  // dof of a
  double chi2_b_given_a = 0.0;  // dof of b
  bool separated = false;       // one of the two conditionals is significant
};

struct Ranking {
  std::vector<Score> scores;  // most significant first
  std::vector<ParallelPair> parallel;
  // The nearly parallel pairs that the residual does not separate.
  std::vector<std::pair<std::string, std::string>> indistinguishable;
};

// The candidates for `job`: every dynamic effect of MODEL.md §7 its model
// does not enable (Stribeck only once Coulomb friction is enabled; no
// motor-side effect for force_source), and sensor_delay / sensor_bias for
// every fitted channel that does not have them. `only`, if non-empty, restricts the list to those
// names (effect names, or "sensor_delay.a" style); throws
// std::invalid_argument "expected an effect of MODEL.md section 7 (…), got
// 'x'" for an unknown name.
std::vector<Candidate> ListCandidates(const FitJob& job,
                                      const std::vector<std::string>& only = {});

// Ranks `candidates` by their score-test p-value at the job's current
// parameter values (job.model.params must hold the fitted values); where
// p-values underflow (chi2 beyond ~1400) by the logarithm of the p-value
// (LogChiSquaredSurvival), so that such candidates are still ordered.
// Pairs are checked for indistinguishability when one of them is
// significant at `alpha` / number of candidates. Throws std::runtime_error
// if a simulation at the current point fails.
Ranking RankCandidates(const FitJob& job, const std::vector<Candidate>& candidates,
                       double alpha = 1e-3);

// Before/after figures of one channel across a discovery step.
struct ChannelChange {
  std::string experiment, channel;
  double rms_before = 0.0, rms_after = 0.0;
  double fit_percent_before = 0.0, fit_percent_after = 0.0;
};

// The channels of `before` and `after` (same experiments), RMS and fit %
// side by side; channels replayed exactly in both (RMS 0) are left out.
std::vector<ChannelChange> ChannelChanges(const FitResult& before, const FitResult& after);

// The changes as a JSON array of {"experiment", "channel", "rms_before",
// "rms_after", "fit_percent_before", "fit_percent_after"} (report.json:
// discovery steps, force map); non-finite numbers as null.
nlohmann::json ChannelChangesToJson(const std::vector<ChannelChange>& changes);

// Orthonormal basis (m × rank) of the columns of `a` (Eigen's
// ColPivHouseholderQR, rank threshold 1e-10; no columns if a is zero).
Eigen::MatrixXd Basis(const Eigen::MatrixXd& a);

// The parameters the loop frees when it adds `effect` (a Candidate::name,
// e.g. "coulomb" → F_c, "spring" → k_x (x_0 stays), "cogging" → A_cog,
// phi_cog, "sensor_delay.a" → tau_d.a). Throws std::invalid_argument for a
// name that is not an effect.
std::vector<std::string> FreedParameters(const std::string& effect);

// `job` with `effect` (a Candidate::name, e.g. "coulomb", "sensor_delay.a")
// switched off and the parameters the loop frees for it fixed. Throws
// std::invalid_argument for a name that is not an effect.
FitJob JobWithout(const FitJob& job, const std::string& effect);

// The candidate's Jacobian columns (m × number of columns) at the job's
// model values, stacked like StackedJacobian (m its number of rows): the
// derivative of the σ-weighted residuals with respect to each column's
// parameter in its own unit, the effect switched on at the column's
// settings. A column whose simulation fails is zero. Never throws.
Eigen::MatrixXd CandidateColumns(const FitJob& job, const Candidate& c, int m);

// Switches candidate `c` on in `job` and frees its parameters, starting from
// the score step of `s`; `start` < the number of starts of `c` (Stribeck:
// one per v_st of its grid; 1 for the others) picks the start.
void AddEffect(const Candidate& c, const Score& s, size_t start, FitJob* job);

struct DiscoveryStep {
  std::string effect;
  std::vector<ParameterEstimate> parameters;  // the effect's fitted parameters
  double chi2 = 0.0;
  int dof = 0;
  double p_value = 1.0;
  double bic_before = 0.0, bic_after = 0.0;
  bool kept = false;  // forward: added (BIC improved, the value is physical
                      // (`implausible` empty) and no other refit of the step
                      // had a lower BIC); removal: dropped
  bool removal = false;  // a backward step: the refit without `effect`
  // A removal for lack of significance (EffectWald after the backward
  // pass), with the test's figures; empty for a BIC removal.
  std::string insignificant;
  // Why the fitted value is not physical, if it is not (ImplausibleValue):
  // such an effect is rejected whatever BIC says (issue 10).
  std::string implausible;
  // Forward steps: the rule that chose among the significant candidates
  // (score order, or the lowest BIC of the refits when s² is far above 1),
  // and for a refit that improved BIC but lost to another candidate's,
  // why ("BIC … above coulomb's …").
  std::string rule;
  std::string outranked;
  // A forward refit that failed outright from the score step (no finite
  // BIC: far from a model that explains the data the Gauss–Newton step can
  // be far too long and the simulation leave the finite numbers) is run
  // once more from a tenth of the step; then this says so.
  std::string retried;
  // Set when an added parameter's refit ended on a bound of its search
  // interval and was continued with that side widened 100-fold.
  std::string widened;
  // A forward refit from more than one start (Stribeck: one per v_st of
  // the score test's grid): each start's BIC and which was kept (the
  // lowest); empty for one start.
  std::string starts;
  // A refit stopped on a shorter horizon because the lower bound of its BIC
  // there was already more than twice the level that decides the step (the
  // BIC before it, or the lowest BIC a refit of the step has already
  // reached; for a removal, the BIC with the effect; estimation/fit.h
  // FitParameters, FitControl::abandon_above_bic): where and why, e.g.
  // "at the 0.2 s horizon: BIC >= 3.868e+04 there already, more than 2
  // times coulomb's BIC (1.192e+04)". Then bic_after is that lower bound
  // and `parameters` and `channels` are empty. Empty for a refit that ran
  // to the whole record.
  std::string stopped;
  std::vector<ChannelChange> channels;
  double seconds = 0.0;  // s, the step's refits (summed over its starts)
};

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

struct DiscoveryReport {
  std::vector<std::string> selected;  // effects in the final model, in the order added
  std::vector<std::string> removed;   // added, then dropped by the backward pass
                                      // or for lack of significance
  // Wald tests of the effects in the final model at level `level` (alpha
  // divided by the number of candidates at the first step).
  std::vector<EffectSignificance> significance;
  double level = 0.0;
  // The final model's residual diagnostics and verdict (discovery/diagnostics.h).
  std::vector<ChannelDiagnostics> final_diagnostics;
  ResidualVerdict verdict;
  std::vector<DiscoveryStep> steps;
  Ranking ranking;                    // at the first step
  std::string stop_reason;
  // s, wall time: the base fit (set by the caller, RunFitParams), all the
  // score tests (RankCandidates at every step), and the final residual
  // diagnostics; each refit's own time is DiscoveryStep::seconds.
  double base_fit_seconds = 0.0;
  double score_seconds = 0.0;
  int score_rankings = 0;
};

// The stand-in rule of Discover (issue 10), on its own: each effect of
// report->selected (Candidate names, the last first; Coulomb skipped while
// Stribeck is in) whose EffectWald p-value at the fit `result` is not below
// `level` is refitted away (warm-started at the optimum with the effect
// off, its parameters fixed) and dropped whatever BIC says: a removal step
// with `insignificant` set is appended, the name moves to report->removed,
// and `job`/`result` become the model without it. Sets report->level and
// report->significance (the effects left); a level above 1 keeps every
// effect. Throws std::invalid_argument for a level ≤ 0 or an unknown effect
// name.
void DropInsignificant(double level, FitJob* job, FitResult* result,
                       DiscoveryReport* report, std::ostream* progress);

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
DiscoveryReport Discover(const DiscoverySettings& settings, FitJob* job,
                         FitResult* result, std::ostream* progress);

// Why the value of `effect` (a Candidate::name) fitted in `fit` has no
// physical meaning, or "" if it has one: a payload below zero (the declared
// mass is too large: a stand-in for M), a sensor delay shorter than the
// shortest sample period of the job's fitted experiments (a sub-sample
// timing error, e.g. of a smooth input read by linear interpolation between
// samples, that a delay absorbs). Effects without such a rule are physical
// at any value within their bounds.
std::string ImplausibleValue(const std::string& effect, const FitResult& fit,
                             const FitJob& job);

// The discovery table for the terminal and params.md.
std::string FormatDiscovery(const DiscoveryReport& report);

// report.json's "discovery" block: {"selected", "steps": [{"effect",
// "parameters": {name: {"value", "std_error"}}, "chi2", "dof", "p_value",
// "bic_before", "bic_after", "kept", "removal", "implausible", "insignificant", "rule", "outranked", "starts", "stopped" (if any), "channels": [...]}],
// "removed": [names], "level", "significance": [{"effect", "chi2", "dof",
// "p_value"}], "verdict": "explained" | "incomplete", "verdict_detail":
// {"s2", "s2_p_value", "tests", "threshold", "channels", "remains",
// "stand_ins_possible"}, "ranking":
// [{"effect", "chi2", "dof", "p_value"}], "indistinguishable": [[a, b]],
// "nearly_parallel": [{"a", "b", "cosine", "chi2_a_given_b",
// "chi2_b_given_a", "separated"}], "stop_reason"}.
nlohmann::json DiscoveryToJson(const DiscoveryReport& report);

}  // namespace axis

#endif  // DISCOVERY_DISCOVERY_H_
