#include "run/fit_params.h"

#include <limits>
#include <stdexcept>
#include <utility>

#include "io/output_staging.h"
#include "common/progress.h"
#include "estimation/fit_result.h"
#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "run/benchmark.h"
#include "run/job_run.h"
#include "run/write_job_run.h"
#include "io/interrupt.h"

namespace axis {

FitResult RunFitParams(const FitParamsOptions& options, std::ostream& terminal,
                       std::ostream& err) {
  // Everything printed goes through the progress stream, so that on a
  // terminal the status line is erased before other text (common/progress.h).
  ProgressStream out(terminal, options.progress_columns);
  FitJob job;
  if (!options.job_path.empty()) {
    job = LoadFitJob(options.job_path);
  } else {
    job = MakeQuickJob(options.model_path, options.data_path,
                       options.input_column, options.fit_channels,
                       options.free_names);
  }
  if (!options.out_dir.empty()) job.out_dir = options.out_dir;
  if (job.out_dir.empty()) {
    throw std::invalid_argument(
        (options.job_path.empty() ? std::string("command line") : options.job_path) +
        ": expected an output directory (--out DIR or output.dir in the job), "
        "got none");
  }
  CheckOutputDirectory(job.out_dir);  // before the fit, not after it
  SetInterruptTarget(job.out_dir);
  out << "fit-params: " << job.title << "\n"
      << "  " << job.problem.experiments.size() << " fitted experiment(s), "
      << job.problem.validate.size() << " validation experiment(s), "
      << job.problem.free.size() << " free parameter(s), " << job.problem.solver.starts + 1
      << " start(s)\n";
  if (job.benchmark.present) return RunBenchmark(std::move(job), options.discover, out, err);
  JobRun run = RunJob(std::move(job), options.discover, out);
  if (run.job.problem.solver.progress) {
    out.Status("writing the outputs", std::numeric_limits<double>::quiet_NaN());
  }
  for (const std::string& w : WriteJobRun(run, run.job.out_dir)) {
    err << "fit-params: warning: " << w << "\n";
  }
  out << "wrote " << run.job.out_dir
      << "/{report.html, params.md, params.csv, report.json, fit_*.csv, fit_*.png}\n";
  return std::move(run.result);
}

}  // namespace axis
