// The force-map step of the discovery loop (issue 15, MODEL.md §7
// `force_map`): when the library of effects leaves the verdict `incomplete`
// and the residual still has binned structure against the position x or the
// velocity v (discovery/diagnostics.h), learn the missing load force as a smooth
// nonparametric function — f(x), f(x)·sgn_ε(v) or f(v), a natural cubic
// spline through values at knots spread over the range the fitted
// experiments visit (sim/force_map.h) — its values fitted with the rest of
// the model by the same Ceres fit under a second-difference roughness
// penalty ½λ‖D·f‖² (a P-spline: Eilers & Marx 1996, "Flexible smoothing with
// B-splines and penalties", Statistical Science 11(2)), λ chosen by BIC with
// the effective number of parameters (Hastie & Tibshirani 1990,
// "Generalized Additive Models", §3.5: edf = tr((JᵀJ + λP)⁻¹JᵀJ)) over a
// grid. The map's 95 % band is the Bayesian one of a penalised fit,
// s²·(JᵀJ + λP)⁻¹ (Wahba 1983, "Bayesian confidence intervals for the
// cross-validated smoothing spline", JRSS B 45(1); Nychka 1988 on its
// average coverage).
#ifndef DISCOVERY_FORCE_MAP_H_
#define DISCOVERY_FORCE_MAP_H_

#include <ostream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <ceres/ceres.h>
#include <nlohmann/json.hpp>

#include "discovery/channel_changes.h"
#include "discovery/diagnostics.h"
#include "discovery/discovery_report.h"
#include "discovery/score_test.h"
#include "estimation/fit_result.h"
#include "discovery/discovery_settings.h"
#include "discovery/force_map_report.h"
#include "estimation/estimation_problem.h"
#include "sim/force_map.h"

namespace axis {

// Runs the force-map step after the discovery loop: `loop` is the loop's
// report (its verdict and final diagnostics), `job`/`result` its final
// model and fit (replaced by the model with the map if it is kept). Runs
// only when the verdict is `incomplete` and a bin test against x or v failed
// at the verdict's threshold. Then: the score tests of f(x), f(x)·sgn_ε(v)
// and f(v) (about settings.force_map_knots knots over the values the fitted
// experiments visit, half at their quantiles, half uniform);
// every form significant at alpha/(number of forms) refitted at a small λ
// (all at once, the first by score publishing its BIC as the level the
// others stop above: estimation/shared_level.h SharedLevel), the lowest BIC (edf) wins;
// for it, the λ of the lowest linearised BIC over
// 10⁻⁶..10² times the mean information per knot, refitted there; kept if
// its BIC is below the library model's. With the map kept, a backward pass
// refits without each effect the loop selected (the last first; Coulomb
// while Stribeck is in stays) and drops it if BIC does not rise beyond
// the solver's accuracy (a tie: the map carries it). Progress lines go
// to `progress`. Throws std::runtime_error if a simulation at a fitted
// point fails.
ForceMapReport AddForceMap(const DiscoverySettings& settings, const DiscoveryReport& loop,
                           EstimationProblem* job, FitResult* result, std::ostream* progress);

// Moves the effects the step's backward pass removed from loop->selected
// to loop->removed, so that `selected` names the final model's effects.
// Never throws.
void ApplyRemovals(const ForceMapReport& report, DiscoveryReport* loop);

// The step as text for the terminal and params.md: why, the score tests,
// the λ grid, the before/after table, the verdict and where the force is
// significant.
std::string FormatForceMap(const ForceMapReport& report);

// report.json's "force_map" block: {"tried", "kept", "reason", "structure",
// "scores": [{"effect", "chi2", "dof", "p_value"}], "forms": [{"effect",
// "bic", "edf", "stopped"}], "removals": [{"effect", "bic_with", "bic_without",
// "removed"}], "kind", "variable",
// "friction", "knots", "values", "std_errors", "lambda", "edf", "s2",
// "bic_before", "bic_after", "grid": [{"lambda", "edf", "chi2", "bic"}],
// "channels": [...], "verdict", "remains", "significant", "seconds"}.
nlohmann::json ForceMapToJson(const ForceMapReport& report);

// Writes the curve of `report` as CSV: header "<x or v>,force,low,high",
// one row per point. Throws std::runtime_error naming `path` if it cannot
// be written.
void WriteForceMapCsv(const std::string& path, const ForceMapReport& report);

// The gnuplot commands that plot the curve from `csv_path` (written by
// WriteForceMapCsv) into `output`: the force against its variable with the
// 95 % band and the zero line, units on the axes. `svg`: gnuplot's svg
// terminal (RenderGnuplotSvg, report/report.h), else a 1000×600 PNG. Paths
// must not contain a quote or a line break.
std::string ForceMapPlotScript(const ForceMapReport& report, const std::string& csv_path,
                               const std::string& output, bool svg);

// Writes force_map.csv (z, force, low, high) and force_map.png (the force
// with its 95 % band against the variable, gnuplot) into `dir` if a map was
// refitted (report.curve not empty); gnuplot problems are appended to `warnings`. Throws
// std::runtime_error if a file cannot be written.
void WriteForceMap(const std::string& dir, const ForceMapReport& report,
                   std::vector<std::string>* warnings);

}  // namespace axis

#endif  // DISCOVERY_FORCE_MAP_H_
