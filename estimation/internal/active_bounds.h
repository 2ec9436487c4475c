// Levenberg–Marquardt within θ's bounds by an active set: the entries held
// on a bound they press against are held constant, the others solved. Ceres
// projects every trust-region step onto the bounds (ParameterBlock::Plus
// clamps x + Δ) but judges the step by the decrease its unprojected
// Gauss–Newton model predicted; with an entry on a bound and the gradient
// pressing it outward, the model keeps predicting the outward part that the
// projection removes, the ratio of actual to predicted decrease settles
// well below 1/4 (0.107 on a first-order accelerometer filter whose time
// constant sat on its lower bound, independent square + sweep records), the
// trust region shrinks at every step and the solve crawls for tens of
// iterations until its parameter tolerance stops it short of the minimum.
// Holding such an entry constant (ceres::SubsetManifold) removes the
// outward part from the model. Internal to estimation/.
#ifndef ESTIMATION_INTERNAL_ACTIVE_BOUNDS_H_
#define ESTIMATION_INTERNAL_ACTIVE_BOUNDS_H_

#include <vector>

#include <ceres/ceres.h>

namespace axis {

struct EvaluationCounter;

// Runs `options` on `problem`, whose only varying parameter block is
// `theta` (n = lower.size() entries, its bounds `lower` and `upper` as set
// on the problem, no manifold), as Ceres would, until it crawls: three
// successful steps in a row, each with an entry on a bound and less than
// half its predicted decrease (an iteration callback; the state read every
// iteration). Then, as an active-set method (Nocedal & Wright, "Numerical
// Optimization", 2nd ed., §16.5, on the KKT conditions of a box, §12.3),
// every entry on a bound whose cost gradient points out of the box is held
// constant (ceres::SubsetManifold) and the run starts again from there;
// once a run with entries held ends by itself, the held entries whose
// gradient has turned inward are released and the run starts again. Ends
// when a run ends by itself (a tolerance, the iteration limit, a failure, a
// caller's callback) with nothing to release, or after eight rounds. A run
// that does not crawl is one ceres::Solve, to the last bit (no gradient is
// evaluated, nothing held): fits whose entries stay off their bounds, or
// leave them, follow the path they followed without it (holding every
// entry that touched a bound from a factor-2 start sent the paper job's
// starts to 1306 Jacobians instead of 150). The rounds share
// options.max_num_iterations. `summary` starts at the first round's
// initial cost, sums the rounds' steps, evaluations and times, and ends
// with the last round's cost and termination (a later round that fails
// leaves θ, cost and termination at the round before it). The gradient at a run's end
// is the Jacobian the run evaluated last, which an ExperimentCost remembers
// (estimation/internal/last_jacobian_memo.h). Each run evaluates its trial
// points with `counter`'s guard off and is repeated with it on if it fails
// (SolveOptimistically, estimation/internal/optimistic_solve.h; `counter`
// the problem's costs' counter, or null for plain runs). Leaves the problem
// without a manifold on `theta`. `final_radius`, if not null, receives the
// trust-region radius (Ceres' IterationSummary::trust_region_radius) at
// the end of the last round whose end θ holds; untouched if none.
void SolveWithinBounds(const ceres::Solver::Options& options, ceres::Problem* problem,
                       double* theta, const std::vector<double>& lower,
                       const std::vector<double>& upper, EvaluationCounter* counter,
                       ceres::Solver::Summary* summary, double* final_radius = nullptr);

// The entries of θ on a bound whose cost gradient `gradient` (∂cost/∂θ)
// points out of the box: on the lower bound with ∂cost/∂θ_k > 0, on the
// upper with ∂cost/∂θ_k < 0. Sorted; all sizes equal.
std::vector<int> PressedBounds(const double* theta, const std::vector<double>& gradient,
                               const std::vector<double>& lower,
                               const std::vector<double>& upper);

}  // namespace axis

#endif  // ESTIMATION_INTERNAL_ACTIVE_BOUNDS_H_
