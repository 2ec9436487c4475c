// Estimating the free parameters of a job (fit/job.h) with Ceres Solver:
// Levenberg–Marquardt on the σ-weighted output error of all experiments,
// multi-start, covariance from ceres::Covariance (DENSE_SVD) scaled by the
// residual variance, and goodness of fit per channel.
#ifndef FIT_FIT_H_
#define FIT_FIT_H_

#include <ostream>
#include <string>
#include <vector>

#include "fit/fit_result.h"
#include "fit/job.h"

namespace axis {

// Fits the job. Prints one line per iteration to `progress` if non-null and
// job.solver.progress. Starts: the job's initial point, then job.solver.starts
// points drawn (seeded by job.solver.seed) log-uniformly within the bounds of
// positive parameters and uniformly otherwise; the lowest final cost wins.
// Throws std::invalid_argument only for an inconsistent job (LoadFitJob has
// checked); the solver itself never throws.
FitResult FitParameters(const FitJob& job, std::ostream* progress = nullptr);

// Turns `job` into a warm refit: a fit that starts next to its optimum (the
// discovery loop's refits with one effect added at the score step; the
// residual bootstrap's refits of resampled data at the estimate) and only
// needs that optimum and its Gauss–Newton covariance. One start, no optimum
// check (solver.probe_rounds 0), the whole record at once
// (solver.first_horizon 0: the horizon continuation exists to bring a far
// start through the gear resonance's phase minima) and Gauss–Newton
// intervals. On the coulomb discovery case the refits took 36 instead of
// 108 simulations, every estimate within 0.01 standard errors of the
// continuation's (issue 11). A caller whose start may be far (a large
// effect removed, a score step far from a model that explains the data)
// restores first_horizon or checks the result (Discover does both).
void AsWarmRefit(FitJob* job);

// Fits jobs[k] (FitParameters, no progress) for every k, up to `threads`
// fits at once on their own std::threads; each fit's Ceres evaluation gets
// threads / (fits at once) threads, at least 1 (its job.solver.threads is
// overridden). The fits are independent (each builds its own problems), so
// the results are those of fitting one after the other. `seconds`, if
// non-null, receives each fit's wall time (s). Rethrows the first exception
// a fit threw (std::invalid_argument for an inconsistent job), after every
// thread has finished. threads < 1 counts as 1.
std::vector<FitResult> FitConcurrently(const std::vector<FitJob>& jobs, int threads,
                                       std::vector<double>* seconds = nullptr);

// Simulates `experiment` with `params` and fills its goodness of fit: every
// measured channel compared (fitted ones flagged with their σ), residual
// whiteness and cross-correlation with the simulated input u.
ExperimentFit EvaluateExperiment(const AxisStructure& structure,
                                 const AxisParams<double>& params,
                                 const FitExperiment& experiment);

// Options of the fit-params command.
struct FitParamsOptions {
  std::string job_path;               // a job file, or the quick form below
  std::string model_path, data_path, input_column;
  std::vector<std::string> fit_channels, free_names;
  std::string out_dir;                // overrides the job's output.dir
  bool discover = false;              // run the discovery loop (fit/discovery.h)
  // > 0: the output stream is a terminal this many columns wide, and the
  // progress shows as one updating status line; 0: plain progress lines
  // (fit/progress.h). fit-params sets it from isatty(stdout).
  int progress_columns = 0;
};

// Loads the job, fits, prints the progress (fit/progress.h) and the
// parameter and fit tables to `out` and writes report.html
// (fit/html_report.h), params.md, params.csv, report.json and
// fit_<experiment>.csv/.png into the output directory (all into a staging
// folder first, moved into place when complete). Throws std::invalid_argument on bad input
// (before anything is written) and std::runtime_error on output failures.
FitResult RunFitParams(const FitParamsOptions& options, std::ostream& out,
                       std::ostream& err);

}  // namespace axis

#endif  // FIT_FIT_H_
