// A benchmark protocol over a job (job key `benchmark:`; issue 16, the EMPS
// benchmark of testdata/emps/README.md): the job is fitted once per named
// criterion — a subset of its fitted experiments; the others are then only
// simulated — and every run is scored on columns of the job's experiments,
// the first being the benchmark's score on a validation experiment. The
// scored experiment is never fitted and, since the discovery loop reads only
// the fitted experiments (discovery/discovery.h), never chooses an effect. The
// published model (`published:`, report/published.h) simulated here and the
// figures other sources quote are set beside the runs.
#ifndef RUN_BENCHMARK_H_
#define RUN_BENCHMARK_H_

#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "common/progress.h"
#include "estimation/fit_result.h"
#include "run/benchmark_settings.h"
#include "run/fit_job.h"
#include "run/job_run.h"

namespace axis {

// One row of the table: a run of this tool, the published model simulated
// here, or a quoted figure (then only the first value is known).
struct BenchmarkRow {
  std::string model;                 // e.g. "this tool, open_loop"
  std::string fitted_on;             // the criterion's experiments, "-" if none
  std::vector<std::string> effects;  // MODEL.md §7 effects in the model
  // This tool's rows: the free parameters the fit could not determine
  // (ParameterEstimate::determined false: not an interpretable estimate).
  std::vector<std::string> undetermined;
  std::vector<double> values;        // per column; NaN where not known
  std::string source;                // quoted rows: the source
};

struct BenchmarkTable {
  std::string title;
  std::vector<BenchmarkColumn> columns;
  std::vector<BenchmarkRow> rows;
};

// `job` with only the criterion's experiments fitted: the job's other fitted
// experiments are moved to the front of `validate` (role "validate", no
// fitted channels), the output folder is `<job.out_dir>/<criterion name>`
// and the title names the criterion; it has no `benchmark:` of its own (a
// plain job for RunJob, estimation/fit.h). Throws std::invalid_argument for a
// criterion naming no experiment of `job` or leaving out one with
// `initial_state: estimate` (ParseBenchmark has checked both).
FitJob CriterionJob(const FitJob& job, const BenchmarkCriterion& criterion);

// fit-params on a job with `benchmark:`: RunJob (estimation/fit.h) once per
// criterion on CriterionJob's job, with the discovery loop if `discover` or
// the job's `discover:`; the table (MakeBenchmarkTable) printed to `out`;
// everything written as one staging folder moved into place (WriteJobRuns,
// estimation/fit.h): `<job.out_dir>/<criterion>/` (each run's files) and
// `<job.out_dir>/benchmark.md`, `benchmark.json`; warnings to `err`.
// Returns the first criterion's fit. Throws std::invalid_argument for a job
// without criteria, std::runtime_error as WriteJobRuns.
FitResult RunBenchmark(FitJob job, bool discover, ProgressStream& out, std::ostream& err);

// The table of `runs` (one per criterion of `settings`, in order), the
// published model's row from the first run's published comparison if the
// job has `published:`, and the quoted rows. Never throws.
BenchmarkTable MakeBenchmarkTable(const BenchmarkSettings& settings,
                                  const std::vector<JobRun>& runs);

// The table as Markdown (benchmark.md, and printed by fit-params), with the
// quoted sources listed under it.
std::string FormatBenchmark(const BenchmarkTable& table);

// benchmark.json: {"title", "columns": [{"experiment", "channel", "measure",
// "scale", "unit"}], "rows": [{"model", "fitted_on", "effects",
// "undetermined", "values", "source"}]} (non-finite values as null).
nlohmann::json BenchmarkToJson(const BenchmarkTable& table);

}  // namespace axis

#endif  // RUN_BENCHMARK_H_
