// The job pipeline: one job run as fit-params runs it — the fit, the
// discovery loop and force map, the current-loop check and full-loop
// refit, the residual diagnostics, the bootstrap, the next experiment and
// the published comparison — before anything is written (WriteJobRun,
// run/write_job_run.h). Every front end runs it: fit-params, fit-campaign's
// seeds, fit-fleet's jobs and the Python module's fit.
#ifndef RUN_JOB_RUN_H_
#define RUN_JOB_RUN_H_

#include <ostream>
#include <string>
#include <vector>

#include "common/phase_log.h"
#include "design/experiment_design.h"
#include "discovery/diagnostics.h"
#include "discovery/discovery.h"
#include "discovery/force_map.h"
#include "discovery/frequency_response.h"
#include "estimation/current_loop_check.h"
#include "estimation/sampling_check.h"
#include "estimation/fit_result.h"
#include "run/fit_job.h"
#include "report/published.h"
#include "report/report.h"
#include "tune/analog_loop_tuning.h"
#include "tune/move_tuning.h"

namespace axis {

// A job run as fit-params runs it, before anything is written (RunJob).
struct JobRun {
  // Where the run's time went (common/phase_log.h): the base fit, the
  // checks, each discovery step, the backward pass, the full-loop refit,
  // the tables; writing the outputs comes after and is not among them.
  std::vector<RunPhase> phases;
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
  // loop (discovery/force_map.h); with a map kept, `job` and `result` hold it.
  ForceMapReport force_map;
  // With `design:` (design/experiment_design.h): the next experiment, at the
  // final estimates.
  ExperimentProposal proposal;
  // With `tune:` (tune/analog_loop_tuning.h): the analog loop tuned to the
  // job's spec at the final estimates.
  AnalogLoopTuning tuning;
  // With `tune.move:` (tune/move_tuning.h): the position controller and the
  // move tuned on the axis with the analog loop as proposed.
  MoveTuning move_tuning;
  // With current_loop: quasi_steady, declared or the screen of a full-loop
  // job (estimation/quasi_steady_screen.h), what the approximation costs the
  // final estimate (estimation/current_loop_check.h); ran = false otherwise.
  CurrentLoopCheck loop_check;
  // The declared model refitted under each accelerometer convention with a
  // free delay on `a`, and the whole fit's χ² of each (report.json
  // accelerometer_check; estimation/sampling_check.h); ran = false when no
  // fitted experiment fits `a`.
  SamplingCheck sampling_check;
  bool has_published = false;     // the job has `published:`
  PublishedComparison published;  // if has_published
  // What params.md and report.json add to the fit's own tables: how input
  // columns were read, the published comparison, the discovery loop.
  ReportSections sections;
  // The frequency response of each fitted experiment at the final
  // estimate (discovery/frequency_response.h; report.json
  // "frequency_response", report.html's Bode plots); empty with
  // frequency_response_note set where the model at the estimate did not
  // simulate.
  std::vector<ExperimentFrequencyResponse> frequency_response;
  std::string frequency_response_note;
  // How input columns were read, one line each ("<experiment>: <note>"),
  // for report.html.
  std::vector<std::string> input_lines;
};

// Runs `job` as fit-params does, writing no file: a model with the analog
// velocity loop and the full current loop on its quasi-steady screen first
// (estimation/quasi_steady_screen.h; simulation.quasi_steady_screen), then
// refitted with the full loop; FitParameters; with
// `discover` or the job's `discover:`, the residual diagnostics and the
// discovery loop (Discover); the residual bootstrap if
// uncertainty.bootstrap > 0; the published comparison if the job has one.
// A job with `benchmark:` is refused (std::invalid_argument): fit-params runs
// each of its criteria as a job of its own (CriterionJob, run/benchmark.h).
// Prints to `out` what fit-params prints between its two header lines and
// its "wrote" line: notes on input columns, the solver's progress (if
// job.problem.solver.progress; from the calling thread only), the discovery tables,
// the parameter and fit tables, the cost, time, optimum-check and
// uncertainty lines, the published table. Throws std::invalid_argument for
// an inconsistent job (LoadFitJob has checked) and std::runtime_error if a
// diagnostic simulation fails.
JobRun RunJob(FitJob job, bool discover, std::ostream& out);

}  // namespace axis

#endif  // RUN_JOB_RUN_H_
