#include "run/benchmark.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/format.h"
#include "common/progress.h"
#include "estimation/fit_result.h"
#include "run/benchmark_settings.h"
#include "run/fit_job.h"
#include "report/published.h"
#include "run/job_run.h"
#include "run/write_job_run.h"
#include "sim/channels.h"
#include "sim/config.h"
#include "io/yaml_util.h"

namespace axis {

FitJob CriterionJob(const FitJob& job, const BenchmarkCriterion& criterion) {
  FitJob out = job;
  out.problem.experiments.clear();
  std::vector<FitExperiment> simulated;
  for (const std::string& name : criterion.experiments) {
    const FitExperiment* e = FindExperiment(job.problem.experiments, name);
    if (e == nullptr) {
      throw std::invalid_argument("benchmark criterion '" + criterion.name +
                                  "': expected names of the job's fitted experiments, got '" +
                                  name + "'");
    }
    out.problem.experiments.push_back(*e);
  }
  for (const FitExperiment& e : job.problem.experiments) {
    if (FindExperiment(out.problem.experiments, e.name) != nullptr) continue;
    if (e.estimate_initial_state) {
      throw std::invalid_argument("benchmark criterion '" + criterion.name +
                                  "': expected every experiment with 'initial_state: estimate' "
                                  "(its state is fitted), got a list without '" + e.name + "'");
    }
    FitExperiment only_simulated = e;
    only_simulated.role = "validate";
    only_simulated.fitted.clear();
    simulated.push_back(only_simulated);
  }
  out.problem.validate.insert(out.problem.validate.begin(), simulated.begin(), simulated.end());
  out.out_dir = job.out_dir + "/" + criterion.name;
  out.benchmark = BenchmarkSettings();  // a plain job: RunJob refuses `benchmark:`
  out.title = job.title + " [criterion " + criterion.name + ": fitted on " +
              Join(criterion.experiments, ", ") + "]";
  return out;
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A figure of `column` from a channel's RMS error, relative error and mean
// absolute error.
double Figure(const BenchmarkColumn& column, double rms, double relative_error_percent,
              double mae) {
  const double value = column.measure == "rms"   ? rms
                       : column.measure == "mae" ? mae
                                                 : relative_error_percent;
  return column.scale * value;
}

// The column's figure in `fit`, NaN if the experiment or channel is absent.
double ColumnValue(const BenchmarkColumn& column, const std::vector<ExperimentFit>& fits) {
  for (const ExperimentFit& e : fits) {
    if (e.name != column.experiment) continue;
    for (const ChannelFit& c : e.channels) {
      if (c.channel == column.channel) {
        return Figure(column, c.rms, c.relative_error_percent, c.mae);
      }
    }
  }
  return kNaN;
}

std::string ColumnLabel(const BenchmarkColumn& c) {
  const std::string what = c.measure == "rms"   ? "RMS"
                           : c.measure == "mae" ? "MAE"
                                                : "rel. error";
  return c.experiment + " " + c.channel + " " + what + " (" + c.unit + ")";
}

}  // namespace

BenchmarkTable MakeBenchmarkTable(const BenchmarkSettings& settings,
                                  const std::vector<JobRun>& runs) {
  BenchmarkTable table;
  table.title = settings.title;
  table.columns = settings.columns;
  for (size_t k = 0; k < runs.size() && k < settings.criteria.size(); ++k) {
    BenchmarkRow row;
    row.model = "this tool, criterion " + settings.criteria[k].name;
    row.fitted_on = Join(settings.criteria[k].experiments, " + ");
    row.effects = EnabledEffectNames(runs[k].job.problem.model.structure);
    row.undetermined = runs[k].result.undetermined;
    for (const BenchmarkColumn& c : settings.columns) {
      row.values.push_back(ColumnValue(c, runs[k].result.experiments));
    }
    table.rows.push_back(row);
  }
  if (!runs.empty() && runs.front().has_published) {
    const PublishedComparison& p = runs.front().published;
    BenchmarkRow row;
    row.model = "published model, simulated here";
    row.fitted_on = "-";
    row.effects = EnabledEffectNames(runs.front().job.published.model.structure);
    row.source = p.source;
    for (const BenchmarkColumn& c : settings.columns) {
      double value = kNaN;
      for (const ChannelComparison& r : p.channels) {
        if (r.experiment != c.experiment || r.channel != c.channel) continue;
        value = Figure(c, r.published_rms, r.published_percent, r.published_mae);
      }
      row.values.push_back(value);
    }
    table.rows.push_back(row);
  }
  for (const QuotedScore& q : settings.quoted) {
    BenchmarkRow row;
    row.model = q.model + " (quoted)";
    row.fitted_on = "-";
    row.source = q.source;
    row.values.assign(settings.columns.size(), kNaN);
    for (size_t c = 0; c < settings.columns.size(); ++c) {
      if (q.experiment.empty() || settings.columns[c].experiment == q.experiment) {
        row.values[c] = q.value;
        break;
      }
    }
    table.rows.push_back(row);
  }
  return table;
}

std::string FormatBenchmark(const BenchmarkTable& table) {
  TextTable text;
  text.headers = {"model", "fitted on", "effects", "not determined by the data"};
  text.right = {false, false, false, false};
  for (const BenchmarkColumn& c : table.columns) {
    text.headers.push_back(ColumnLabel(c));
    text.right.push_back(true);
  }
  for (const BenchmarkRow& r : table.rows) {
    std::vector<std::string> cells = {r.model, r.fitted_on,
                                      r.effects.empty() ? "-" : Join(r.effects, ", "),
                                      r.undetermined.empty() ? "-" : Join(r.undetermined, ", ")};
    for (double v : r.values) cells.push_back(FormatNumber(v, 4, "-"));
    text.rows.push_back(cells);
  }
  std::ostringstream out;
  out << "Benchmark: " << table.title << "\n\n" << RenderMarkdown(text);
  bool any_source = false;
  for (const BenchmarkRow& r : table.rows) {
    if (r.source.empty()) continue;
    if (!any_source) out << "\nSources:\n";
    any_source = true;
    out << "- " << r.model << ": " << r.source << "\n";
  }
  return out.str();
}

nlohmann::json BenchmarkToJson(const BenchmarkTable& table) {
  nlohmann::json out;
  out["title"] = table.title;
  out["columns"] = nlohmann::json::array();
  for (const BenchmarkColumn& c : table.columns) {
    out["columns"].push_back({{"experiment", c.experiment},
                              {"channel", c.channel},
                              {"measure", c.measure},
                              {"scale", c.scale},
                              {"unit", c.unit}});
  }
  out["rows"] = nlohmann::json::array();
  for (const BenchmarkRow& r : table.rows) {
    nlohmann::json values = nlohmann::json::array();
    for (double v : r.values) values.push_back(JsonNumber(v));
    out["rows"].push_back({{"model", r.model},
                           {"fitted_on", r.fitted_on},
                           {"effects", r.effects},
                           {"undetermined", r.undetermined},
                           {"values", values},
                           {"source", r.source}});
  }
  return out;
}

FitResult RunBenchmark(FitJob job, bool discover, ProgressStream& out, std::ostream& err) {
  if (job.benchmark.criteria.empty()) {
    throw std::invalid_argument(job.problem.path + ": key 'benchmark.criteria': expected at least one "
                                "criterion, got none");
  }
  std::vector<JobRun> runs;
  std::vector<std::string> subdirs;
  for (const BenchmarkCriterion& criterion : job.benchmark.criteria) {
    std::string fitted;
    for (const std::string& name : criterion.experiments) fitted += " " + name;
    out << "\n=== Benchmark criterion " << criterion.name << ": fitted on" << fitted << "\n";
    runs.push_back(RunJob(CriterionJob(job, criterion), discover, out));
    subdirs.push_back(criterion.name);
  }
  const BenchmarkTable table = MakeBenchmarkTable(job.benchmark, runs);
  const std::string text = FormatBenchmark(table);
  out << "\n" << text;
  if (job.problem.solver.progress) {
    out.Status("writing the outputs", std::numeric_limits<double>::quiet_NaN());
  }
  const std::vector<std::pair<std::string, std::string>> files = {
      {"benchmark.md", "# " + job.title + "\n\n" + text},
      {"benchmark.json", BenchmarkToJson(table).dump(2) + "\n"}};
  for (const std::string& w : WriteJobRuns(runs, subdirs, files, job.out_dir)) {
    err << "fit-params: warning: " << w << "\n";
  }
  out << "wrote " << job.out_dir << "/{benchmark.md, benchmark.json, <criterion>/{report.html, "
      << "params.md, params.csv, report.json, fit_*.csv, fit_*.png}}\n";
  return std::move(runs.front().result);
}

}  // namespace axis
