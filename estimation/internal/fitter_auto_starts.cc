// Fitter's automatic random starts (estimation/internal/fitter.h): after the job's
// start ended far above the noise, tell a misfit of the model from a wrong
// minimum (estimation/internal/start_agreement.h) before paying for every start.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "common/format.h"
#include "estimation/internal/fitter.h"
#include "estimation/optimum_check.h"
#include "estimation/internal/phase_timer.h"
#include "estimation/internal/start_agreement.h"
#include "estimation/solver_settings.h"

namespace axis {

Fitter::StartsOutcome Fitter::RunStarts(const std::vector<std::vector<double>>& starts,
                                        const std::vector<std::vector<double>>& prior_path) {
  prior_path_ = prior_path;
  BuildProblem();
  BuildStages();
  SetSolverOptions();
  starts_ = starts;
  CheckControl();
  RunShorterStages();
  StartsOutcome out;
  out.cost = std::numeric_limits<double>::infinity();
  out.best = starts.empty() ? p_.theta : starts[0];
  if (RankFinalists()) {
    RunFinalists();
    out.best = best_;
    out.cost = best_cost_;
    out.summary = best_summary_;
    out.step = best_step_;
  }
  out.result = result_;
  out.simulations = p_.counter.simulations;
  out.jacobians = p_.counter.jacobians;
  return out;
}

std::vector<double> Fitter::RunRandomBatch(const std::vector<std::vector<double>>& starts,
                                           size_t first) {
  EstimationProblem again = job_;
  again.solver.starts = static_cast<int>(starts.size());
  again.solver.auto_starts = 0;
  // Every start fits the whole record: the screen horizon's ranking is what
  // failed here when its cost was at the noise while the whole record's is
  // far above it (a +6 V step whose preamp leaves its limit after 0.8 s of
  // 1.5: every start's screen cost 743–775, T_p unseen there; ranked, the
  // two finalists ended at s² = 96, while with all nine one random start
  // reached s² = 1.0).
  again.solver.finalists = std::max(job_.solver.finalists, again.solver.starts + 1);
  const StartsOutcome out = Fitter(again, control_, progress_).RunStarts(starts, ends_[0]);
  for (const FitPhase& f : out.result.phases) AddPhase(f, &result_);
  extra_simulations_ += out.simulations;
  extra_jacobians_ += out.jacobians;
  const FitResult& r = out.result;
  for (size_t s = 0; s < starts.size(); ++s) {
    result_.start_costs.push_back(s < r.start_costs.size() ? r.start_costs[s] : NAN);
    result_.start_screen_costs.push_back(s < r.start_screen_costs.size() ? r.start_screen_costs[s]
                                                                         : NAN);
    const int joined = s < r.start_joined.size() ? r.start_joined[s] : -1;
    result_.start_joined.push_back(joined == kJoinedPrior ? 0
                                   : joined >= 0          ? joined + static_cast<int>(first)
                                                          : -1);
    result_.start_joined_horizon.push_back(
        s < r.start_joined_horizon.size() ? r.start_joined_horizon[s] : 0.0);
  }
  if (out.cost < best_cost_) {
    best_cost_ = out.cost;
    best_ = out.best;
    best_summary_ = out.summary;
    best_step_ = out.step;
    std::copy(best_.begin(), best_.end(), p_.theta.begin());
    for (size_t s = 0; s < r.start_costs.size(); ++s) {
      if (r.start_costs[s] == out.cost) winner_ = first + s;
    }
  }
  // A start that joined a path ends where that path ends.
  std::vector<double> ends(starts.size(), NAN);
  for (size_t s = 0; s < starts.size() && s < r.start_costs.size(); ++s) {
    const int joined = s < r.start_joined.size() ? r.start_joined[s] : -1;
    ends[s] = joined == kJoinedPrior ? result_.start_costs[0]
              : joined >= 0          ? r.start_costs[static_cast<size_t>(joined)]
                                     : r.start_costs[s];
  }
  return ends;
}

// The job's start alone ended far above the noise: a wrong minimum of the
// output error, or the model's own misfit. A wrong minimum was the cause on
// unseen data (a wrist axis fitted from the X axis's values ended at
// s² = 575; 8 random starts reached s² = 1.0); a misfit (an accelerometer
// sampled at the instant fitted with the period mean, issue 42: s² = 9.6)
// is not left by any start, and 8 starts there cost minutes for nothing.
// The first kMisfitProbeStarts tell them apart: if every one lands at the
// job's cost (SameMinimumTolerance; a start that joins the job's path does),
// the cost has one minimum as far as they see and the misfit is the
// model's, and the rest do not run; one clearly higher (several minima) or
// lower and the rest run, as before.
void Fitter::AutoStarts() {
  const double s2 = 2.0 * best_cost_ / dof_;
  const double job_cost = best_cost_;
  const int total = job_.solver.auto_starts;
  const std::vector<std::vector<double>> random = RandomStarts(starts_[0], total);
  const size_t first = std::min<size_t>(kMisfitProbeStarts, random.size());
  if (progress_ != nullptr) {
    *progress_ << "s^2 = " << FormatNumber(s2, 4) << " after the job's start (above "
               << kAutoStartsAbove << "): " << first << " of " << total
               << " random starts first (solver.auto_starts), to tell a wrong minimum from "
                  "the model's misfit\n";
  }
  const double tolerance =
      SameMinimumTolerance(s2, CostResolution(job_cost, job_.solver.function_tolerance));
  const std::vector<double> probe_costs = RunRandomBatch(
      std::vector<std::vector<double>>(random.begin(), random.begin() + first), 1);
  const StartVerdict verdict = JudgeStarts(job_cost, probe_costs, tolerance);
  std::ostringstream note;
  note << "the job's start ended the continuation at s^2 = " << FormatNumber(s2, 4)
       << " (above " << kAutoStartsAbove << ")";
  if (verdict == StartVerdict::kSame) {
    note << "; " << first << " random starts all ended at the same s^2 (within chi^2 "
         << kSameMinimumChi2 << "·s^2): the misfit is the model's, not a "
         << "wrong minimum, so the other " << random.size() - first
         << " (solver.auto_starts) did not run; check the sensor front end ("
         << (FittedPeriod(job_, Channel::kA) > 0.0 ? "the accelerometer's sampling, instant or period_mean; " : "")
         << "filters; delays) or run fit-params --discover";
    result_.auto_starts_note = note.str();
    return;
  }
  note << ", so " << total << " random starts were added (solver.auto_starts): " << first
       << " first, "
       << (verdict == StartVerdict::kLower ? "one of which ended clearly lower"
                                           : "which found more than one minimum")
       << ", then the other " << random.size() - first;
  if (first < random.size()) {
    RunRandomBatch(std::vector<std::vector<double>>(random.begin() + first, random.end()),
                   1 + first);
  }
  note << "; " << (winner_ == 0 ? "the job's start" : "random start " + std::to_string(winner_))
       << " ended lowest";
  result_.auto_starts_note = note.str();
}

}  // namespace axis
