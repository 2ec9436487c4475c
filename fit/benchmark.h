// A benchmark protocol over a job (job key `benchmark:`; issue 16, the EMPS
// benchmark of testdata/emps/README.md): the job is fitted once per named
// criterion — a subset of its fitted experiments; the others are then only
// simulated — and every run is scored on columns of the job's experiments,
// the first being the benchmark's score on a validation experiment. The
// scored experiment is never fitted and, since the discovery loop reads only
// the fitted experiments (fit/discovery.h), never chooses an effect. The
// published model (`published:`, fit/published.h) simulated here and the
// figures other sources quote are set beside the runs.
#ifndef FIT_BENCHMARK_H_
#define FIT_BENCHMARK_H_

#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

namespace axis {

struct FitExperiment;  // fit/job.h
struct FitJob;         // fit/job.h
struct JobRun;         // fit/fit.h
class ProgressStream;  // fit/progress.h
struct FitResult;      // fit/fit_result.h

// One column of the benchmark table: a goodness-of-fit figure of one
// channel (MODEL.md §6 name) of one experiment of the job (ChannelFit,
// fit/fit_result.h), multiplied by `scale` (e.g. 1000: m → mm).
struct BenchmarkColumn {
  std::string experiment;
  std::string channel;
  std::string measure = "rms";  // "rms" (channel unit × scale) or "relative_error_percent"
  double scale = 1.0;           // finite > 0
  std::string unit;             // label of the scaled unit, e.g. "mm"; "%" for relative errors
};

// A fitting criterion: the fitted experiments (names of the job's
// `experiments:`, at least one, each once); the job's other fitted
// experiments become validation runs of this criterion.
struct BenchmarkCriterion {
  std::string name;  // letters, digits, '_', '-', '.': names the output folder
  std::vector<std::string> experiments;
};

// A score another source publishes, not re-run: by default on the score
// column's run, in its unit; `experiment` places it in the first column on
// another run (a figure its source computed on the training run).
struct QuotedScore {
  std::string model;
  double value = 0.0;  // ≥ 0
  std::string source;
  std::string experiment;  // a column's experiment; empty: the score column
};

// The job key `benchmark:` — {title, columns: [{experiment, channel,
// measure?, scale?, unit?}, ...], criteria: {name: [experiment, ...], ...},
// quoted?: [{model, value, source, experiment?}, ...]}. The first column is
// the score and must name a `validate:` experiment (never fitted).
struct BenchmarkSettings {
  bool present = false;
  std::string title;
  std::vector<BenchmarkColumn> columns;
  std::vector<BenchmarkCriterion> criteria;
  std::vector<QuotedScore> quoted;
};

// Reads `benchmark:` of job `path`; `experiments` and `validate` are the
// job's, already loaded. Throws std::invalid_argument "<file>:<line>: key
// 'benchmark.<key>': expected …, got …" for unknown keys, a column or
// criterion naming no experiment of the job or a channel the experiment does
// not measure, a score column on a fitted experiment, a criterion that
// leaves out an experiment with `initial_state: estimate` (its state is
// fitted, so it cannot be only simulated), a repeated name, a criterion
// named benchmark.md or benchmark.json (the table's files), a `scale` other
// than 1 without its `unit`, a quoted `experiment` no column names.
void ParseBenchmark(const YAML::Node& node, const std::string& path,
                    const std::vector<FitExperiment>& experiments,
                    const std::vector<FitExperiment>& validate, BenchmarkSettings* out);

// `job` with only the criterion's experiments fitted: the job's other fitted
// experiments are moved to the front of `validate` (role "validate", no
// fitted channels), the output folder is `<job.out_dir>/<criterion name>`
// and the title names the criterion; it has no `benchmark:` of its own (a
// plain job for RunJob, fit/fit.h). Throws std::invalid_argument for a
// criterion naming no experiment of `job` or leaving out one with
// `initial_state: estimate` (ParseBenchmark has checked both).
FitJob CriterionJob(const FitJob& job, const BenchmarkCriterion& criterion);

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

// fit-params on a job with `benchmark:`: RunJob (fit/fit.h) once per
// criterion on CriterionJob's job, with the discovery loop if `discover` or
// the job's `discover:`; the table (MakeBenchmarkTable) printed to `out`;
// everything written as one staging folder moved into place (WriteJobRuns,
// fit/fit.h): `<job.out_dir>/<criterion>/` (each run's files) and
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

#endif  // FIT_BENCHMARK_H_
