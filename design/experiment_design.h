// The next experiment (issue 15 part 2): when two candidate effects cannot
// be told apart on the data (the discovery loop's `indistinguishable` pair),
// or a free parameter's relative standard error is above the job's
// `design.rel_se`, search a family of inputs for the record that would
// decide, by simulation at the current estimates:
// - T-optimal (Atkinson & Fedorov 1975, "The design of experiments for
//   discriminating between two rival models", Biometrika 62(1)), linearised
//   as in the score test of discovery/discovery.h: under the truth "a" (the
//   current model plus a at its score step β_a from the data), the data
//   leave the model by d_a = J_a·β_a; what the rival b cannot absorb is the
//   noncentrality of the conditional score statistic of a given b,
//   ‖P⊥[J_f, J_b]·d_a‖² (σ-weighted residuals, so in χ² units), over the
//   recorded experiments and the proposed one stacked (J_f: the free
//   parameters). The criterion is the smaller of the two directions, so the
//   record decides whichever candidate is true.
// - D-optimal: the determinant of the free parameters' information JᵀJ over
//   the experiments and the proposed one, reported as predicted standard
//   errors s·sqrt(diag (JᵀJ)⁻¹) (s² the fit's residual variance).
// The family, a record of design.duration s from rest at the centre c of
// design.travel (half-width w):
// - open loop (the job's first experiment driven by an input): the
//   set-velocity voltage U within ±design.max_voltage: step pairs (0.1 s at
//   rest, +L for T, −L for T, then 0), sines, chirps and PRBS over a grid of
//   levels, durations, frequencies and bit times (Family in the .cc);
// - closed loop (its first experiment has a controller and a reference):
//   the reference position for that controller, sampled at the output
//   period and read by linear interpolation: moves (0.1 s at rest, to c + D
//   in T, a dwell, to c − D in 2T, a dwell, back to c in T; D = 0.3, 0.6,
//   0.9·w), sines c + A·sin(2πft) and PRBS c ± A (A = 0.3, 0.6, 0.9·w)
//   (ClosedLoopFamily), each after 0.1 s at rest at c. The controller's
//   output saturates at its U_max as in any closed-loop run: a fast
//   reference can drive it to the limit. The experiment's injection, if
//   any, is not part of the proposal.
// A candidate is feasible if the position stays inside design.travel in the
// simulation of the current model and, for T, of both rival models.
#ifndef DESIGN_EXPERIMENT_DESIGN_H_
#define DESIGN_EXPERIMENT_DESIGN_H_

#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "estimation/fit_result.h"
#include "design/design_settings.h"
#include "discovery/discovery_settings.h"
#include "estimation/estimation_problem.h"
#include "sim/input_signal.h"

namespace axis {

// One input of the family, scored.
struct DesignCandidate {
  std::string family;       // "steps", "sine", "chirp", "prbs"
  std::string description;  // e.g. "sine 5 V, 1 Hz"
  // Open loop: the set-velocity voltage U(t) (V); closed loop: the
  // reference position (m), a table at the output period.
  InputSignal input;
  // Open loop (V): the step height, sine/chirp amplitude, PRBS level;
  // closed loop (m): the move's distance D, the sine's or PRBS's A.
  double level = 0.0;
  double bit_time = 0.0;  // s: PRBS only
  bool feasible = false;
  double x_min = 0.0, x_max = 0.0;  // m, predicted travel (all models simulated)
  // T: predicted noncentralities (χ² units) of the conditional score
  // statistics, a beyond b under truth a and b beyond a under truth b; the
  // criterion is their minimum. D: log det of the information.
  double chi2_a_given_b = 0.0;
  double chi2_b_given_a = 0.0;
  double criterion = 0.0;
};

struct ExperimentProposal {
  bool proposed = false;
  bool closed_loop = false;  // the family is reference positions (see above)
  std::string reason;      // why (not) proposed, one sentence
  std::string criterion;   // "T-optimal" or "D-optimal" ("" if not proposed)
  std::string a, b;        // T: the pair
  int dof_a = 0, dof_b = 0;
  double critical_a = 0.0, critical_b = 0.0;  // χ² critical values at the loop's level
  // The records' own noncentralities (without the proposal), as above.
  double chi2_a_given_b_now = 0.0, chi2_b_given_a_now = 0.0;
  DesignCandidate best;
  std::vector<DesignCandidate> candidates;  // every input tried, in family order
  // D: per free parameter (job.free order): the current and the predicted
  // relative standard errors.
  std::vector<std::string> names;
  std::vector<double> rel_se_now, rel_se_predicted;
  double duration = 0.0;  // s
  double start_x = 0.0;   // m, the rest position it starts at
  double seconds = 0.0;   // wall time of the search
};

// Proposes the next experiment for `job` at the estimates of `result` (the
// final model of the loop), within `design`. T-optimal for the pair the
// loop would stop on (its most significant candidate with a twin) in a
// fresh score ranking at the final model (ListCandidates with
// discover.candidates, RankCandidates at discover.alpha) in which one
// member is significant; else D-optimal if a free parameter's relative
// standard error exceeds design.rel_se > 0; else nothing (reason says
// why). The fitted channels and σ of the proposal are those of
// job.experiments[0], its step and output period too, and in closed loop
// its controller. The candidate inputs are scored side by side on
// job.solver.threads threads; the best is the highest criterion (of equal
// ones the first in family order; an input whose criterion is not finite
// is never the best), whatever the order they end in, and the `design:`
// progress lines come after every input is scored, in family order.
// Throws std::invalid_argument if the job has no fitted experiment;
// std::runtime_error if the simulation at the estimates fails.
ExperimentProposal ProposeExperiment(const EstimationProblem& job, const FitResult& result,
                                     const DesignSettings& design,
                                     const DiscoverySettings& discover,
                                     std::ostream* progress = nullptr);

// The proposal as text (params.md section "Next experiment") and as JSON
// (report.json "next_experiment").
std::string FormatProposal(const ExperimentProposal& proposal);
nlohmann::json ProposalToJson(const ExperimentProposal& proposal);

// Writes `dir`/experiment_proposed.yaml (an experiment file for
// simulate-axis: the input, duration, step, output rate, u, x and the
// fitted channels with their σ from the job as noise, the start state, and
// as a comment the job entry that fits the recorded run),
// `dir`/experiment_proposed_model.yaml (the job's model at the fitted
// values, which the experiment file names; in closed loop with the first
// experiment's controller) and `dir`/experiment_proposed_input.csv (t, u at
// the output rate: the input to run on the machine; in closed loop t, x_ref:
// the reference position, which the experiment file reads as a column),
// each atomically (RunJob's writer stages the
// folder, so a failure leaves none of them).
// `title` names the job in the model's source. Nothing is written unless
// proposal.proposed. Throws std::runtime_error if a file cannot be written.
void WriteProposal(const std::string& dir, const EstimationProblem& job, const std::string& title,
                   const FitResult& result, const ExperimentProposal& proposal);

}  // namespace axis

#endif  // DESIGN_EXPERIMENT_DESIGN_H_
