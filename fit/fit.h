// Estimating the free parameters of a job (fit/job.h) with Ceres Solver:
// Levenberg–Marquardt on the σ-weighted output error of all experiments,
// multi-start, covariance from ceres::Covariance (DENSE_SVD) scaled by the
// residual variance, and goodness of fit per channel.
#ifndef FIT_FIT_H_
#define FIT_FIT_H_

#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "fit/current_loop_check.h"
#include "fit/diagnostics.h"
#include "fit/discovery.h"
#include "fit/experiment_design.h"
#include "fit/force_map.h"
#include "fit/fit_result.h"
#include "fit/job.h"
#include "fit/published.h"
#include "fit/report.h"

namespace axis {

// Fits the job. Prints one line per iteration to `progress` if non-null and
// job.solver.progress. Starts: the job's initial point, then job.solver.starts
// points drawn (seeded by job.solver.seed) log-uniformly within the bounds of
// positive parameters and uniformly otherwise; the lowest final cost wins.
// With a finite job.solver.abandon_above_bic (the discovery loop's refits),
// a start whose BIC can no longer end below it stops on a shorter horizon of
// the continuation (a stage's cost is a prefix of the whole record's, so
// 2·(its minimum) + n·ln(m) bounds the final BIC from below; the minimum
// taken as the lower of the stage's end point and the start); if every
// start stops, the result says where (FitResult::abandoned_horizon).
// job.solver.stop_after_horizon > 0 stops every start so after that horizon
// (a screen), and the result carries the stages every start ran
// (FitResult::checkpoint); a fit of the same job given that as
// job.solver.resume takes those stages as run and goes on after them, with
// the same end as running them again (bit for bit on the same number of
// threads; fit/horizon_checkpoint.h). A start that meets an earlier start's
// point after a shorter horizon (within its parameter tolerance) stops
// (FitResult::start_joined). With job.solver.publish_level the fit
// publishes its BIC there when it ends (also when it throws: +inf); with
// job.solver.pending_level it stops as under abandon_above_bic at that
// level once another fit publishes it, and may block until then
// (fit/screen.h SharedLevel). Throws std::invalid_argument for an
// inconsistent job (LoadFitJob has checked), for a solver.resume that is
// not a checkpoint of this job, and for a pending_level with
// solver.starts > 0 or a stop_after_horizon; the solver itself never
// throws.
FitResult FitParameters(const FitJob& job, std::ostream* progress = nullptr);

// Sets `e`'s initial arm position y0 = y[0] (m) and velocity y1 = y[1]
// (m/s), with the motor's y2 = y0/r_g (rad), y3 = y1/r_g (rad/s): the gear
// undeflected, as `initial_state: estimate` fits them (configs/README.md;
// MODEL.md §1). r_g in m/rad, > 0.
void SetArmState(const std::array<double, 2>& y, double r_g, FitExperiment* e);

// Turns `job` into a warm refit: a fit that starts next to its optimum (the
// residual bootstrap's refits of resampled data at the estimate) and only
// needs that optimum and its Gauss–Newton covariance. One start, no optimum
// check (solver.probe_rounds 0), the whole record at once
// (solver.first_horizon 0: the horizon continuation exists to bring a far
// start through the gear resonance's phase minima) and Gauss–Newton
// intervals. The discovery loop's refits use these settings but restore
// first_horizon: with an effect added at its score step or removed, the
// start is not near enough (issue 11: on EMPS the whole record at once
// ended the Stribeck refit in a minimum 100 BIC higher).
void AsWarmRefit(FitJob* job);

// The smallest change of a cost (½Σr² of σ-weighted residuals) that the
// solver resolves: `function_tolerance` (Ceres' relative stop, at least
// 1e-9) times |cost|, plus 1e-6. Two fits whose costs differ by less ended
// at the same optimum as far as the solver can tell (the optimum check's
// "lower" point, fit/fit.cc; the force map's removal ties,
// fit/force_map.cc). Never throws.
double CostResolution(double cost, double function_tolerance);

// Fits jobs[k] (FitParameters, no progress) for every k, up to `threads`
// fits at once on their own std::threads; each fit's Ceres evaluation gets
// threads / (fits at once) threads, at least 1 (its job.solver.threads is
// overridden), taken in index order. The fits are independent (each builds
// its own problems), so the results are those of fitting one after the
// other, except that a fit with solver.pending_level waits for its level:
// its publisher must come at a lower index (it then always runs first or
// beside it; fit/screen.h SharedLevel). `seconds`, if
// non-null, receives each fit's wall time (s). Rethrows the exception of
// the lowest-indexed fit that threw (std::invalid_argument for an
// inconsistent job), after every fit has run (fit/concurrency.h
// ForEachConcurrently). threads < 1 counts as 1.
std::vector<FitResult> FitConcurrently(const std::vector<FitJob>& jobs, int threads,
                                       std::vector<double>* seconds = nullptr);

// Simulates `experiment` with `params` and fills its goodness of fit: every
// measured channel compared (fitted ones flagged with their σ), residual
// whiteness and cross-correlation with the simulated input u.
ExperimentFit EvaluateExperiment(const AxisStructure& structure,
                                 const AxisParams<double>& params,
                                 const FitExperiment& experiment);

// A job run as fit-params runs it, before anything is written (RunJob).
struct JobRun {
  // The job; after discovery its model holds the selected effects with
  // their fitted values.
  FitJob job;
  // The final fit: after discovery, of the augmented model; with
  // uncertainty.bootstrap > 0, with the bootstrap's figures.
  FitResult result;
  bool discovered = false;  // the discovery loop ran
  // If discovered: the loop's report, and the residual diagnostics of the
  // model as declared at the base fit.
  DiscoveryReport discovery;
  std::vector<ChannelDiagnostics> diagnostics;
  // If discovered with discover.force_map: the force-map step after the
  // loop (fit/force_map.h); with a map kept, `job` and `result` hold it.
  ForceMapReport force_map;
  // With `design:` (fit/experiment_design.h): the next experiment, at the
  // final estimates.
  ExperimentProposal proposal;
  // With current_loop: quasi_steady, what the approximation costs the final
  // estimate (fit/current_loop_check.h); ran = false otherwise.
  CurrentLoopCheck loop_check;
  bool has_published = false;     // the job has `published:`
  PublishedComparison published;  // if has_published
  // What params.md and report.json add to the fit's own tables: how input
  // columns were read, the published comparison, the discovery loop.
  ReportSections sections;
  // How input columns were read, one line each ("<experiment>: <note>"),
  // for report.html.
  std::vector<std::string> input_lines;
};

// Runs `job` as fit-params does, writing no file: FitParameters; with
// `discover` or the job's `discover:`, the residual diagnostics and the
// discovery loop (Discover); the residual bootstrap if
// uncertainty.bootstrap > 0; the published comparison if the job has one.
// A job with `benchmark:` is refused (std::invalid_argument): fit-params runs
// each of its criteria as a job of its own (CriterionJob, fit/benchmark.h).
// Prints to `out` what fit-params prints between its two header lines and
// its "wrote" line: notes on input columns, the solver's progress (if
// job.solver.progress; from the calling thread only), the discovery tables,
// the parameter and fit tables, the cost, time, optimum-check and
// uncertainty lines, the published table. Throws std::invalid_argument for
// an inconsistent job (LoadFitJob has checked) and std::runtime_error if a
// diagnostic simulation fails.
JobRun RunJob(FitJob job, bool discover, std::ostream& out);

// Writes the outputs of `run` into `dir` (created with its parents if
// missing): WriteFitOutputs' files and, if run.discovered, the
// diag_*.csv/.png of the declared model and model_discovered.yaml. They go
// to a staging folder moved into place when complete (MakeStagingDirectory,
// CommitStagingDirectory; interrupts held meanwhile). Returns the warnings
// (plots not drawn), naming the final paths. Throws std::runtime_error
// naming what cannot be written (nothing is left in `dir` then).
std::vector<std::string> WriteJobRun(const JobRun& run, const std::string& dir);

// As WriteJobRun for several runs written as one: run k into
// `<dir>/<subdirs[k]>`, and each (file name, contents) of `files` into
// `dir`, all in one staging folder moved into place when complete. Used for
// a job's benchmark criteria (fit/benchmark.h). Throws std::invalid_argument
// if the sizes of `runs` and `subdirs` differ, std::runtime_error as
// WriteJobRun.
std::vector<std::string> WriteJobRuns(
    const std::vector<JobRun>& runs, const std::vector<std::string>& subdirs,
    const std::vector<std::pair<std::string, std::string>>& files, const std::string& dir);

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

// Loads the job, fits (RunJob, with the progress of fit/progress.h),
// prints the parameter and fit tables to `out` and writes report.html
// (fit/html_report.h), params.md, params.csv, report.json and
// fit_<experiment>.csv/.png into the output directory (WriteJobRun: all into
// a staging folder first, moved into place when complete); warnings go to
// `err`. A job with `benchmark:` (fit/benchmark.h) is run once per
// criterion, each run's files in `<out>/<criterion>/`, the benchmark table
// printed and written to `<out>/benchmark.md` and `benchmark.json`
// (RunBenchmark); the first criterion's fit is returned. Throws
// std::invalid_argument on bad input (before anything is written) and
// std::runtime_error on output failures.
FitResult RunFitParams(const FitParamsOptions& options, std::ostream& out,
                       std::ostream& err);

}  // namespace axis

#endif  // FIT_FIT_H_
