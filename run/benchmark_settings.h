// The job key `benchmark:` (issue 16, the EMPS benchmark of
// testdata/emps/README.md): a protocol over a job, fitted once per named
// criterion — a subset of its fitted experiments; the others are then only
// simulated — and every run scored on columns of the job's experiments,
// the first being the score on a validation experiment. The settings, their
// strict loader and the job of one criterion; running the protocol is
// run/benchmark.h.
#ifndef RUN_BENCHMARK_SETTINGS_H_
#define RUN_BENCHMARK_SETTINGS_H_

#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>


namespace axis {

struct FitExperiment;  // estimation/estimation_problem.h

// One column of the benchmark table: a goodness-of-fit figure of one
// channel (MODEL.md §6 name) of one experiment of the job (ChannelFit,
// estimation/fit_result.h), multiplied by `scale` (e.g. 1000: m → mm).
struct BenchmarkColumn {
  std::string experiment;
  std::string channel;
  // "rms", "mae" (mean absolute error; both channel unit × scale) or
  // "relative_error_percent"
  std::string measure = "rms";
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
// than 1 without its `unit`, a quoted `experiment` no column names. A
// column's unit defaults to its channel's on a linear axis, or on a rotary
// one if `rotary` (ChannelUnit, sim/channels.h).
void ParseBenchmark(const YAML::Node& node, const std::string& path,
                    const std::vector<FitExperiment>& experiments,
                    const std::vector<FitExperiment>& validate, BenchmarkSettings* out,
                    bool rotary = false);




}  // namespace axis

#endif  // RUN_BENCHMARK_SETTINGS_H_
