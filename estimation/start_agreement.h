// Misfit or a wrong minimum (issue 42): whether a few random starts that
// ran after the job's start ended far above the noise (kAutoStartsAbove,
// job/solver_settings.h) land at the same cost as it, clearly lower, or
// neither. Used by the fit (estimation/fitter.cc Fitter::AutoStarts) to stop
// after the first starts when the misfit is the model's.
#ifndef ESTIMATION_START_AGREEMENT_H_
#define ESTIMATION_START_AGREEMENT_H_

#include <vector>

namespace axis {

// The random starts run first (of SolverSettings::auto_starts) to tell a
// misfit of the model from a wrong minimum of the job's start.
constexpr int kMisfitProbeStarts = 2;

// Two minima whose χ² (= 2·cost) differ by less than this many units of s²
// are the same fit as far as the data can tell: 3.84 is the 95 % quantile
// of χ²₁ (a likelihood-ratio test of one parameter would not tell them
// apart), scaled by s² because a residual variance of s² (in units of the
// declared σ²) scales the cost's variation alike.
constexpr double kSameMinimumChi2 = 3.84;

enum class StartVerdict {
  kLower,      // a start ended clearly lower: the job's start was a wrong minimum
  kSame,       // one ended at the same cost, none lower: the misfit is the model's
  kUndecided,  // every start ended clearly higher (or failed): no evidence
};

// The cost tolerance of SameMinimum in cost units (½χ²): ½·kSameMinimumChi2·s2,
// at least `resolution` (CostResolution, estimation/optimum_check.h). NaN
// s2 gives `resolution`. Never throws.
double SameMinimumTolerance(double s2, double resolution);

// The verdict on the random starts' final costs `start_costs` (½Σr² on the
// whole record; NaN or +inf for a start not continued or failed) against the
// job's start's `job_cost`, with the tolerance `tolerance` (cost units, e.g.
// SameMinimumTolerance): kLower if one is below job_cost − tolerance, else
// kSame if one is within ±tolerance, else kUndecided. Never throws.
StartVerdict JudgeStarts(double job_cost, const std::vector<double>& start_costs,
                         double tolerance);

}  // namespace axis

#endif  // ESTIMATION_START_AGREEMENT_H_
