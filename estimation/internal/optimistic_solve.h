// A Levenberg–Marquardt run whose trial points are simulated in double, the
// sensitivity guard (estimation/experiment_cost.h ExperimentCost) only where
// a run needs it. Internal to estimation/.
//
// Why: Ceres evaluates a trial point's residuals alone, accepts or rejects
// the step, and only then evaluates the Jacobian at an accepted point; if
// that evaluation fails (a sensitivity that is not finite or beyond
// ExperimentCost::kMaxSensitivity: a grazing backlash contact, chattering
// at a limit) the run ends in FAILURE. The guard — each trial point
// simulated with a one-direction Jet, so that such a point fails as a
// trial and the step is rejected — prevents that, at 2.2 times the cost of
// a double simulation per trial point (Rk4Step<Jet<1>> against
// Rk4Step<double>, bench_rk4_step), and the trial points of a fit's runs
// were about a third of a discovery job's time (perf, an independent PRBS
// record with Coulomb friction: ExperimentCost::Residuals<Jet<1>> 38.7 % of
// the samples). A run whose accepted points all have a Jacobian needs no
// guard and, without it, usually follows the same path (the same residuals
// to the last bits, the same accept/reject decisions); a run that meets such
// a point fails, and is run again from its start with the guard on, which
// is the guarded run. Two cases part ways: Ceres tests its function
// tolerance on a candidate before accepting it, so a candidate the guard
// would have failed can end the run in convergence at the point before it;
// and the guard judges the sum of the columns against
// ExperimentCost::kMaxSensitivity, so it can fail a point whose Jacobian
// would pass. The rerun's progress lines count the iterations from 0 again.
#ifndef ESTIMATION_INTERNAL_OPTIMISTIC_SOLVE_H_
#define ESTIMATION_INTERNAL_OPTIMISTIC_SOLVE_H_

#include <functional>

#include <ceres/ceres.h>

namespace axis {

struct EvaluationCounter;

// ceres::Solve(options, problem, summary) with counter->guard off, the n
// entries of `theta` (the problem's varying parameter block) saved first;
// if that run ends unusable (Solver::Summary::IsSolutionUsable false),
// θ is put back to its start, `before_rerun` (if set: callbacks' state)
// is called and the run is repeated with the guard on. The summary is the
// run that stands, its evaluation counts and times including the first
// run's where there were two. With `counter` null or its guard already off,
// one plain ceres::Solve. Leaves counter->guard as it found it. θ after an
// unusable run: wherever Ceres left it (at its start unless
// options.update_state_every_iteration). Never throws but std::bad_alloc.
void SolveOptimistically(const ceres::Solver::Options& options, ceres::Problem* problem,
                         double* theta, int n, EvaluationCounter* counter,
                         ceres::Solver::Summary* summary,
                         const std::function<void()>& before_rerun = {});

}  // namespace axis

#endif  // ESTIMATION_INTERNAL_OPTIMISTIC_SOLVE_H_
