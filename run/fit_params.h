// The fit-params command as a function: load the job (or the quick form),
// run it (RunJob, or RunBenchmark for a job with `benchmark:`), write its
// outputs. apps/fit_params.cc parses the flags and calls RunFitParams.
#ifndef RUN_FIT_PARAMS_H_
#define RUN_FIT_PARAMS_H_

#include <ostream>
#include <string>
#include <vector>

#include "estimation/fit_result.h"

namespace axis {

// Options of the fit-params command.
struct FitParamsOptions {
  std::string job_path;               // a job file, or the quick form below
  std::string model_path, data_path, input_column;
  std::vector<std::string> fit_channels, free_names;
  std::string out_dir;                // overrides the job's output.dir
  bool discover = false;              // run the discovery loop (discovery/discovery.h)
  // > 0: the output stream is a terminal this many columns wide, and the
  // progress shows as one updating status line; 0: plain progress lines
  // (common/progress.h). fit-params sets it from isatty(stdout).
  int progress_columns = 0;
};

// Loads the job, fits (RunJob, with the progress of common/progress.h),
// prints the parameter and fit tables to `out` and writes report.html
// (report/html_report.h), params.md, params.csv, report.json and
// fit_<experiment>.csv/.png into the output directory (WriteJobRun: all into
// a staging folder first, moved into place when complete); warnings go to
// `err`. A job with `benchmark:` (run/benchmark.h) is run once per
// criterion, each run's files in `<out>/<criterion>/`, the benchmark table
// printed and written to `<out>/benchmark.md` and `benchmark.json`
// (RunBenchmark); the first criterion's fit is returned. Throws
// std::invalid_argument on bad input (before anything is written) and
// std::runtime_error on output failures.
FitResult RunFitParams(const FitParamsOptions& options, std::ostream& out,
                       std::ostream& err);

}  // namespace axis

#endif  // RUN_FIT_PARAMS_H_
