// The candidate effects of the discovery loop (discovery/discovery.h): the
// effects of MODEL.md §7 a model does not have, their Jacobian columns for
// the score test (discovery/score_test.h), and the job with one of them
// switched on (its parameters freed, started from the score step) or off.
#ifndef DISCOVERY_CANDIDATES_H_
#define DISCOVERY_CANDIDATES_H_

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"
#include "sim/channels.h"
#include "sim/force_map.h"

namespace axis {

struct Score;  // discovery/score.h

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
// The search interval of a discovered second-order filter's damping ζ
// (AddEffect); a refit that ends within 1 % of either end is implausible
// (discovery/significance.h ImplausibleValue).
constexpr double kLowpass2DampingBounds[2] = {0.05, 5.0};
// The search interval of a discovered Stribeck shape exponent δ
// (AddEffect); a refit that ends within 1 % of either end is implausible
// (discovery/significance.h ImplausibleValue).
constexpr double kStribeckShapeBounds[2] = {0.1, 20.0};
// The damping a discovered second-order filter starts from: the
// Butterworth filter's 1/√2.
constexpr double kButterworthDamping = 0.70710678118654752;

struct Candidate {
  std::string name;
  std::string effect;
  Channel channel = Channel::kT;  // sensor effects only
  std::vector<CandidateColumn> columns;
  // effect "force_map" only (discovery/force_map.h): the map switched on (name
  // "force_map.<kind>", columns its values f_map.<k>).
  ForceMap force_map;
};

// The candidates for `job`: every dynamic effect of MODEL.md §7 its model
// does not enable (Stribeck only once Coulomb friction is enabled; no
// motor-side effect for force_source), and sensor_delay / sensor_bias for
// every fitted channel that does not have them. `only`, if non-empty, restricts the list to those
// names (effect names, or "sensor_delay.a" style); throws
// std::invalid_argument "expected an effect of MODEL.md section 7 (…), got
// 'x'" for an unknown name.
std::vector<Candidate> ListCandidates(const EstimationProblem& job,
                                      const std::vector<std::string>& only = {});

// Whether `effect` (a Candidate::effect) is refined by another effect of
// `structure` and stays while that one does (the marginality principle of
// ListCandidates): Coulomb friction under a Stribeck term, the Stribeck
// term under its own shape exponent (stribeck_shape). The removal steps
// skip it. Never throws.
bool RefinedInModel(const std::string& effect, const AxisStructure& structure);

// The parameters the loop frees when it adds `effect` (a Candidate::name,
// e.g. "coulomb" → F_c, "spring" → k_x (x_0 stays), "cogging" → A_cog,
// phi_cog, "sensor_delay.a" → tau_d.a). Throws std::invalid_argument for a
// name that is not an effect.
std::vector<std::string> FreedParameters(const std::string& effect);

// `job` with `effect` (a Candidate::name, e.g. "coulomb", "sensor_delay.a")
// switched off and the parameters the loop frees for it fixed. Throws
// std::invalid_argument for a name that is not an effect.
EstimationProblem JobWithout(const EstimationProblem& job, const std::string& effect);

// The candidate's Jacobian columns (m × number of columns) at the job's
// model values, stacked like StackedJacobian (m its number of rows): the
// derivative of the σ-weighted residuals with respect to each column's
// parameter in its own unit, the effect switched on at the column's
// settings. A column whose simulation fails is zero. Never throws.
Eigen::MatrixXd CandidateColumns(const EstimationProblem& job, const Candidate& c, int m);

// Switches candidate `c` on in `job` and frees its parameters, starting from
// the score step of `s`; `start` < the number of starts of `c` (Stribeck:
// one per v_st of its grid; 1 for the others) picks the start.
void AddEffect(const Candidate& c, const Score& s, size_t start, EstimationProblem* job);

// ---- used by the loop's refits (discovery/internal/discovery_loop.h,
// discovery/removal.h)

// How many starts the refit of candidate `c` takes (AddEffect's `start`):
// one per v_st of the Stribeck grid, each from that column's own step
// (Score::single_step); one for every other effect. Never throws.
size_t StartsOf(const Candidate& c);

// What start `start` of candidate `c` begins from, for the report ("v_st =
// 0.02 m/s"); empty for a candidate with one start. Never throws.
std::string StartLabel(const Candidate& c, size_t start);

// Whether candidates `a` and `b` (Candidate::name) are sensor front-end
// terms of one channel ("sensor_delay.a", "sensor_lowpass.a"): to first
// order their score columns are equal (MODEL.md §6), so the discovery loop
// refits them together instead of stopping on them as indistinguishable,
// and the experiment design does not try to separate them. Never throws.
bool SameChannelFrontEnd(const std::string& a, const std::string& b);

// The candidate of a Candidate::name ("coulomb", "sensor_delay.a"); throws
// std::invalid_argument for a name that is not one.
Candidate CandidateNamed(const std::string& name);

// The parameters AddEffect frees for `c`. Never throws.
std::vector<std::string> EffectParameters(const Candidate& c);

// Switches candidate `c` off in `job` and fixes its parameters `params`.
// Never throws.
void RemoveEffect(const Candidate& c, const std::vector<std::string>& params,
                  EstimationProblem* job);

// Widens 100-fold each side of the search interval AddEffect gave the
// parameters `names` of `job` on which `fit` ended (within 1e-6 of the
// interval's width); true if any was widened. Only the sides that are a
// search interval around the score step, not a physical bound, are
// widened. Never throws.
bool WidenSearchBounds(const FitResult& fit, const std::vector<std::string>& names,
                       EstimationProblem* job);

}  // namespace axis

#endif  // DISCOVERY_CANDIDATES_H_
