// What the model-discovery loop (discovery/discovery.h Discover) did: its
// steps, the effects it selected and removed, the first step's ranking, the
// significance of the effects left and the final model's verdict; as text
// and as report.json's "discovery" block.
#ifndef DISCOVERY_DISCOVERY_REPORT_H_
#define DISCOVERY_DISCOVERY_REPORT_H_

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "discovery/channel_changes.h"
#include "discovery/diagnostics.h"
#include "discovery/score_test.h"
#include "discovery/significance.h"
#include "estimation/fit_result.h"

namespace axis {

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
  // A removal of a significant effect too small to matter
  // (discovery/materiality.h: its contribution and floor); empty otherwise.
  std::string negligible;
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
  // Set when a delay's refit was moved to where its own simulation lined up
  // with the records and continued (discovery/internal/discovery_loop.cc
  // RealignDelay).
  std::string realigned;
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

// ">= " before a step's bic_after that is a lower bound (a stopped refit,
// DiscoveryStep::stopped), else "". Never throws.
const char* BoundMark(const DiscoveryStep& s);

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
  // What the user should read beside the selection: a declaration of the
  // front end kept against the evidence, with its figures
  // (discovery/discovery_session.h); a significant effect too small to
  // matter, dropped (discovery/materiality.h). One sentence each.
  std::vector<std::string> notes;
};

// The selected effects split into the plant's and the sensor front end's
// (IsFrontEndEffect, sim/config.h), each in the order given. Never throws.
struct SelectedParts {
  std::vector<std::string> plant;
  std::vector<std::string> front_end;
};
SelectedParts SplitSelected(const std::vector<std::string>& selected);

// The discovery table for the terminal and params.md.
std::string FormatDiscovery(const DiscoveryReport& report);

// report.json's "discovery" block: {"selected", "selected_plant",
// "selected_front_end", "steps": [{"effect",
// "parameters": {name: {"value", "std_error"}}, "chi2", "dof", "p_value",
// "bic_before", "bic_after", "kept", "removal", "implausible", "insignificant",
// "negligible", "rule", "outranked", "starts", "stopped" (if any), "channels": [...]}],
// "notes": [sentences],
// "removed": [names], "level", "significance": [{"effect", "chi2", "dof",
// "p_value"}], "verdict": "explained" | "incomplete", "verdict_detail":
// {"s2", "s2_p_value", "tests", "threshold", "channels", "remains",
// "stand_ins_possible"}, "ranking":
// [{"effect", "chi2", "dof", "p_value"}], "indistinguishable": [[a, b]],
// "nearly_parallel": [{"a", "b", "cosine", "chi2_a_given_b",
// "chi2_b_given_a", "separated"}], "stop_reason"}.
nlohmann::json DiscoveryToJson(const DiscoveryReport& report);


}  // namespace axis

#endif  // DISCOVERY_DISCOVERY_REPORT_H_
