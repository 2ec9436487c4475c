// The residual bootstrap that cross-checks a fit's intervals (issue 9; why:
// estimation/uncertainty.h).
#ifndef ESTIMATION_RESIDUAL_BOOTSTRAP_H_
#define ESTIMATION_RESIDUAL_BOOTSTRAP_H_

#include <ostream>

#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"

namespace axis {

// Residual bootstrap (Efron & Tibshirani, "An Introduction to the
// Bootstrap", 1993, §9.5; moving blocks, Künsch 1989): `settings.bootstrap`
// replicate data sets, each the fitted trace of `fit` plus its residuals
// (measured − simulated, per fitted channel of every fitted experiment)
// resampled in blocks of `settings.block` consecutive samples (random
// starts, seeded by settings.seed; blocks keep the residuals' correlation
// over shorter lags). Each replicate is refitted from the estimate (one
// start, whole record at once, no optimum check, Gauss–Newton covariance).
// Writes into fit->parameters (free ones) the replicates' standard deviation
// (std_error_bootstrap) and their 2.5 / 97.5 % percentiles (bootstrap_low /
// bootstrap_high), and the number of converged refits into
// fit->bootstrap_replicates. `fit` must come from FitParameters(job);
// throws std::invalid_argument if it does not match the job's experiments
// and channels. Refits start where the estimate is, so on a cost with local
// minima (estimation/fit.h, optimum check) they measure the local spread.
void ResidualBootstrap(const EstimationProblem& job, FitResult* fit, std::ostream* progress);

}  // namespace axis

#endif  // ESTIMATION_RESIDUAL_BOOTSTRAP_H_
