#include "estimation/full_loop_refit.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "estimation/at_estimate.h"
#include "estimation/parameter_tie.h"

namespace axis {
namespace {

bool Positive(double x) { return std::isfinite(x) && x > 0.0; }

const ParameterEstimate* Find(const FitResult& r, const std::string& name) {
  for (const ParameterEstimate& e : r.parameters) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

// The end `end` of the quasi-steady interval about `q`, carried to `value`
// with the ratio r (CarryQuasiSteadyIntervals).
double CarryEnd(double end, double q, double value, double r) {
  if (Positive(end) && Positive(q) && Positive(value)) return value * std::pow(end / q, r);
  return value + r * (end - q);
}

// Gives every free parameter of `to` that is in `from` from's interval,
// moved to its value and widened by the Gauss–Newton ratio (never narrowed),
// and the parameters tied to them theirs.
void MoveIntervals(const FitResult& from, FitResult* to) {
  for (ParameterEstimate& e : to->parameters) {
    const ParameterEstimate* q = e.free ? Find(from, e.name) : nullptr;
    if (q == nullptr) continue;
    // Wider where the full loop's Gauss–Newton scale is, never narrower:
    // on a cost made rough by many backlash contacts at 10 µs that scale is
    // an artifact (a PRBS record: T_p's 5.6 times smaller, the truth 14 of
    // those off; the quasi-steady interval held it at 1.8).
    const double ratio = e.std_error_gauss_newton / q->std_error_gauss_newton;
    const double r = Positive(ratio) ? std::max(1.0, ratio) : 1.0;
    e.ci95_low = CarryEnd(q->ci95_low, q->value, e.value, r);
    e.ci95_high = CarryEnd(q->ci95_high, q->value, e.value, r);
    e.std_error = r * q->std_error;
    e.interval_method = q->interval_method;
    e.determined = e.determined && q->determined;
  }
  CopyTiedUncertainty(to);
}

}  // namespace

EstimationProblem FullLoopRefitProblem(const EstimationProblem& problem, const FitResult& quasi,
                                       const CurrentLoopCheck& check,
                                       FullLoopRefitSettings::Intervals intervals, double* step) {
  EstimationProblem full = WithFullLoop(AtEstimate(problem, quasi), step);
  full.solver.starts = 0;
  full.solver.auto_starts = 0;
  full.solver.first_horizon = 0.0;
  full.start_near_minimum = true;  // the bias-corrected estimate
  for (FreeParameter& f : full.free) {
    for (size_t k = 0; k < check.names.size() && k < check.shift.size(); ++k) {
      if (check.names[k] != f.name || !std::isfinite(check.shift[k])) continue;
      f.initial = std::clamp(f.initial - check.shift[k], f.lower, f.upper);
    }
  }
  if (intervals == FullLoopRefitSettings::Intervals::kCarried) {
    full.solver.probe_rounds = 0;
    full.solver.local_starts = 0.0;
    full.uncertainty.method = UncertaintySettings::Method::kGaussNewton;
    // A local solve whose intervals are carried over needs the estimate to
    // a small fraction of its standard error, not to the last digit: it
    // stops once a step changes the cost by less than ½·δ²·s², what a
    // Gauss–Newton step of δ = kFullLoopRefitStepSe standard errors
    // lowers it by (the cost is ½Σ(r/σ)², s² = 2·cost/dof). Ceres'
    // function_tolerance is relative to the cost at the current point, the
    // quasi-steady fit's within the shift's share.
    if (Positive(quasi.final_cost) && Positive(quasi.residual_variance)) {
      const double absolute =
          0.5 * kFullLoopRefitStepSe * kFullLoopRefitStepSe * quasi.residual_variance;
      full.solver.function_tolerance =
          std::max(full.solver.function_tolerance, absolute / quasi.final_cost);
    }
  }
  return full;
}

void CarryQuasiSteadyIntervals(const FitResult& quasi, FitResult* full) {
  MoveIntervals(quasi, full);
  for (ParameterEstimate& e : full->parameters) {
    if (e.free && Find(quasi, e.name) != nullptr) {
      e.interval_method += ", carried from the quasi-steady fit";
    }
  }
  full->optimum_verified = quasi.optimum_verified;
  full->optimum_check = "in the quasi-steady fit: " + quasi.optimum_check +
                        "; the full loop refitted locally from its bias-corrected estimate";
  full->uncertainty_method = quasi.uncertainty_method;
  full->uncertainty_note = "the quasi-steady fit's intervals, moved to the full loop's "
                           "estimate and widened by the ratio of the two models' "
                           "Gauss-Newton standard errors where the full loop's is larger "
                           "(simulation.full_loop_intervals: carried): " +
                           quasi.uncertainty_note;
}

void CarryIntervalsAcrossRemoval(const FitResult& carried, FitResult* refit) {
  MoveIntervals(carried, refit);
  refit->optimum_verified = carried.optimum_verified;
  refit->optimum_check = carried.optimum_check;
  refit->uncertainty_method = carried.uncertainty_method;
  refit->uncertainty_note = carried.uncertainty_note;
}

}  // namespace axis
