// Whether an effect the loop selected changes what the user sees (issue
// 56): significance alone is not enough on long records, where a term that
// moves no sample by more than a sliver of the noise still passes a Wald
// test (16,000 residuals: a payload of 2.5 g on a 25 kg axis at p = 5e-19,
// its contribution a hundredth of σ). Records made by another
// implementation carry such slivers of model error (another integrator,
// other sample timing: s² = 1.04 where the models agree), and a tool must
// not report them as physics.
//
// The rule: an effect is material if its contribution to some fitted
// channel — the RMS over the samples of ŷ with it minus ŷ with it switched
// off, the other parameters as fitted — is at least kMaterialShare of that
// channel's σ, or if its value is at least its physical floor (below).
// Else it is negligible: the loop refits the model without it and reports
// it as a note, not a selection.
//
// kMaterialShare = 0.25: a contribution c·σ explains c² of the noise
// variance, so below 0.25 it moves the residual variance by less than
// 6 % — the size of the model error seen on other implementations' records
// (s² 1.02–1.06 with every effect right) — and changes the residual RMS
// by less than 3 %, which no engineer reading the traces can see.
//
// Physical floors (a change the machine's own description makes material
// whatever the record): a payload ΔM of at least 1 % of M (a tool's or a
// part's mass on a carriage); a viscous asymmetry ΔB of at least 5 % of
// B_a (a guide or a seal worn on one side). The other effects have no
// floor of their own: their contribution alone decides.
#ifndef DISCOVERY_MATERIALITY_H_
#define DISCOVERY_MATERIALITY_H_

#include <ostream>
#include <string>

#include "discovery/discovery_report.h"
#include "estimation/estimation_problem.h"
#include "estimation/fit_result.h"

namespace axis {

// The contribution's share of σ above which an effect is material.
constexpr double kMaterialShare = 0.25;

// How much an effect changes the fitted channels (EffectContribution).
struct Contribution {
  double share = 0.0;      // the largest RMS(ŷ_on − ŷ_off)/σ over the fitted channels
  std::string channel;     // where (experiment/channel)
  double value = 0.0;      // the effect's first parameter as fitted (its unit)
  double floor = 0.0;      // its physical floor (same unit), +inf where it has none
  bool material = true;    // share ≥ kMaterialShare or |value| ≥ floor
};

// The contribution of `effect` (a Candidate::name, enabled in `problem`)
// at the estimate of `fit`: the fitted experiments simulated at the
// estimate with the effect and without it (its switch off, every other
// parameter as fitted). A simulation that fails gives share +inf (the
// effect is kept: the rule cannot judge it). Throws std::invalid_argument
// for an unknown effect name.
Contribution EffectContribution(const std::string& effect, const EstimationProblem& problem,
                                const FitResult& fit);

// "<effect> (<name> = <value> <unit>) is significant but negligible: it
// changes no fitted channel by more than <share>·σ (largest on <channel>),
// below 0.25·σ, and <value> is below its floor <floor>" — the note for a
// negligible effect, the units those of an axis moving as `motion`
// (ParamUnit). Never throws.
std::string NegligibleNote(const std::string& effect, const Contribution& c,
                           Motion motion = Motion::kLinear);

// The rule on its own, after the significance rule: each effect of
// report->selected (the last first; the accelerometer's convention step
// and Coulomb while Stribeck is in skipped) that is not material at the
// fit `result` is refitted away (RefitsWithout, discovery/removal.h) and
// dropped whatever BIC says: a removal step with DiscoveryStep::negligible
// set, and its NegligibleNote in report->notes. A refit without it that
// stops or fails keeps it. Progress lines go to `progress`. Throws as
// FitParameters does.
void DropNegligible(EstimationProblem* job, FitResult* result, DiscoveryReport* report,
                    std::ostream* progress);

}  // namespace axis

#endif  // DISCOVERY_MATERIALITY_H_
