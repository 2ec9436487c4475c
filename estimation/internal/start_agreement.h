// Misfit or a wrong minimum (issue 42): whether a few random starts that
// ran after the job's start ended far above the noise (kAutoStartsAbove,
// estimation/solver_settings.h) land at the same cost as it, clearly lower, or
// neither. Used by the fit (estimation/internal/fitter.cc Fitter::AutoStarts) to stop
// after the first starts when the misfit is the model's.
#ifndef ESTIMATION_INTERNAL_START_AGREEMENT_H_
#define ESTIMATION_INTERNAL_START_AGREEMENT_H_

#include <vector>

namespace axis {

// The random starts run first (of SolverSettings::auto_starts) to tell a
// misfit of the model from a wrong minimum of the job's start. Agreement of
// every one is the evidence, so more of them are harder to fool: on the
// wrong-minimum case of FitTest.AStartFarAboveTheNoiseAddsRandomStarts 5 of
// 8 random starts ended at the job's minimum, one at a higher one and one at
// the noise; if a fraction q of the starts falls into the job's basin, all
// k do with probability q^k (24 % for q = 5/8, k = 3; 39 % for k = 2).
constexpr int kMisfitProbeStarts = 3;

// Two minima whose χ² (= 2·cost) differ by less than this many units of s²
// are the same fit as far as the data can tell: 3.84 is the 95 % quantile
// of χ²₁ (a likelihood-ratio test of one parameter would not tell them
// apart), scaled by s² because a residual variance of s² (in units of the
// declared σ²) scales the cost's variation alike.
constexpr double kSameMinimumChi2 = 3.84;

enum class StartVerdict {
  kLower,      // a start ended clearly lower: the job's start was a wrong minimum
  kSame,       // every start that ended did so at the job's cost: one minimum, the
               // misfit is the model's
  kUndecided,  // a start ended clearly higher (several minima: more starts may
               // find a lower one), or none ended
};

// The cost tolerance of SameMinimum in cost units (½χ²): ½·kSameMinimumChi2·s2,
// at least `resolution` (CostResolution, estimation/optimum_check.h). NaN
// s2 gives `resolution`. Never throws.
double SameMinimumTolerance(double s2, double resolution);

// The verdict on the random starts' final costs `start_costs` (½Σr² on the
// whole record; NaN or +inf for a start not continued or failed) against the
// job's start's `job_cost`, with the tolerance `tolerance` (cost units, e.g.
// SameMinimumTolerance): kLower if one is below job_cost − tolerance, else
// kSame if every finite one is within ±tolerance (and there is one), else
// kUndecided. Never throws.
StartVerdict JudgeStarts(double job_cost, const std::vector<double>& start_costs,
                         double tolerance);

}  // namespace axis

#endif  // ESTIMATION_INTERNAL_START_AGREEMENT_H_
