// The forms of the force map (discovery/force_map.h) as candidates of the
// force-map step: the values of x and v the experiments visit, the knots
// over them, the candidate of each form (f(x), f(x)·sgn_ε(v), f(v)), its
// refit's job, and the transfer of a library effect's force into the map.
#ifndef DISCOVERY_INTERNAL_FORCE_MAP_FORMS_H_
#define DISCOVERY_INTERNAL_FORCE_MAP_FORMS_H_

#include <string>
#include <vector>

#include "discovery/candidates.h"
#include "estimation/estimation_problem.h"
#include "sim/force_map.h"

namespace axis {

// Bounds (N) of a map value in the refits: wide enough never to bind for a
// servo axis (its forces are far below), finite for Ceres' bounds.
constexpr double kForceBound = 1.0e6;

// The values of x and v the fitted experiments visit at the job's values,
// at their sample instants, pooled.
struct Visited {
  std::vector<double> x, v;
};

// Throws std::runtime_error naming the experiment whose simulation at the
// job's values fails.
Visited VisitedValues(const EstimationProblem& job);

// About `count` knots for the values `samples` visits: half at its
// quantiles (Ruppert, Wand & Carroll 2003, "Semiparametric Regression",
// §5.5: where the data spend their time, so that every interval holds
// samples), half spread uniformly over its range (where it passes quickly:
// a velocity crossed only while accelerating still shapes the response);
// both ends included, and a knot closer than a quarter of the uniform
// spacing to the previous one dropped. Empty if fewer than kMinForceMapKnots remain
// (the variable hardly moves). Never throws.
std::vector<double> MapKnots(std::vector<double> samples, int count);

// The candidate of the map of `variable` (`friction`: f(x)·sgn_ε(v)) with
// `knots`: named "force_map.<kind>" (ForceMapKind), one column f_map.<k>
// per knot. Never throws.
Candidate MapCandidate(ForceMapVariable variable, bool friction, std::vector<double> knots);

// `job` with the map of `c` switched on at zero and its values free (the
// last K entries of job.free), as a warm refit with `first_horizon`.
// Its values are bounded by ±kForceBound; solver progress off. Never throws.
EstimationProblem MapJob(const EstimationProblem& job, const Candidate& c, double first_horizon);

// Moves the load force of `effect` (about to be switched off in `job`) into
// the map where the map can carry it exactly or nearly: Coulomb friction
// F_c·sgn_ε(v) (and the motor side's T_c/r_g, the same through the gear)
// into f(x)·sgn_ε(v) or f(v); a load offset F_0 into f(x) or f(v); a
// spring k_x·(x − x_0) into f(x). The refit without the effect then starts
// from the same model instead of one missing the effect's share (for
// f(x)·sgn_ε(v) and F_c the two are the same force). Never throws.
void TransferToMap(const std::string& effect, EstimationProblem* job);

}  // namespace axis

#endif  // DISCOVERY_INTERNAL_FORCE_MAP_FORMS_H_
