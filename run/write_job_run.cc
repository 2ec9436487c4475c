#include "run/write_job_run.h"

#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "common/concurrency.h"
#include "io/output_staging.h"
#include "design/experiment_design.h"
#include "discovery/diagnostics.h"
#include "discovery/force_map.h"
#include "report/html_report.h"
#include "report/report.h"
#include "report/tuning_report.h"
#include "estimation/at_estimate.h"
#include "run/job_run.h"
#include "sim/config.h"
#include "io/csv.h"

namespace axis {
namespace {

// WriteJobRun's files other than WriteFitOutputs', into the existing
// folder `dir`.
void WriteReportFiles(const JobRun& run, const std::string& dir,
                      std::vector<std::string>* warnings) {
  HtmlReportInput html;
  html.title = run.job.title;
  html.result = &run.result;
  html.job = &run.job.problem;
  html.diagnostics = &run.diagnostics;
  html.frequency_response = &run.frequency_response;
  html.discovery = run.discovered ? &run.discovery : nullptr;
  html.force_map = run.discovered && run.job.discover.force_map ? &run.force_map : nullptr;
  html.proposal = run.job.design.enabled ? &run.proposal : nullptr;
  html.tuning = run.job.tune.enabled ? &run.tuning : nullptr;
  html.move_tuning = run.job.tune.move.enabled ? &run.move_tuning : nullptr;
  html.published = run.has_published ? &run.published : nullptr;
  html.input_notes = run.input_lines;
  html.run_phases = run.phases;
  html.files = {"params.md", "params.csv", "report.json"};
  for (const std::string& stem : ExperimentFileStems(run.result)) {
    html.files.push_back(stem + ".csv");
    html.files.push_back(stem + ".png");
  }
  if (run.discovered) {
    for (const ChannelDiagnostics& d : run.diagnostics) {
      html.files.push_back("diag_" + d.experiment + "_" + d.channel + ".csv");
      html.files.push_back("diag_" + d.experiment + "_" + d.channel + ".png");
    }
    html.files.push_back("model_discovered.yaml");
    if (!run.force_map.curve.z.empty()) {
      html.files.push_back("force_map.csv");
      html.files.push_back("force_map.png");
    }
  }
  if (run.proposal.proposed) {
    for (const char* name : {"experiment_proposed.yaml", "experiment_proposed_input.csv",
                             "experiment_proposed_model.yaml"}) {
      html.files.push_back(name);
    }
  }
  if (run.job.tune.enabled) {
    WriteTuning(dir, AtEstimate(run.job.problem, run.result).model, run.tuning, &html.files);
    WriteMoveTuning(dir, AtEstimate(run.job.problem, run.result).model, run.move_tuning, &html.files);
  }
  WriteHtmlReport(dir + "/report.html", html, warnings);
  WriteProposal(dir, run.job.problem, run.job.title, run.result, run.proposal);
  if (run.discovered) {
    WriteDiagnostics(dir, run.diagnostics, warnings);
    WriteForceMap(dir, run.force_map, warnings);
    AxisConfig discovered = run.job.problem.model;
    discovered.name = run.job.problem.model.name + "_discovered";
    discovered.source = "fit-params --discover on " + run.job.title;
    WriteFileAtomic(dir + "/model_discovered.yaml",
                    "# Written by fit-params --discover: the fitted model with the\n"
                    "# effects the data asked for. Loadable by simulate-axis and\n"
                    "# fit-params as a model config.\n" +
                        AxisConfigToYaml(discovered));
  }
}

// WriteJobRun's files, into the existing folder `dir` (no staging). The
// experiments' PNGs (WriteFitOutputs) are drawn while the report's plots
// are, two sets of gnuplot runs at once rather than one after the other
// (each file is written by one of them; gnuplot's temporary names are
// unique per process and call, common/gnuplot.h); the warnings in that
// order.
void WriteJobRunFiles(const JobRun& run, const std::string& dir,
                      std::vector<std::string>* warnings) {
  std::vector<std::string> fit_warnings, report_warnings;
  ForEachConcurrently(2, 2, [&](size_t part) {
    if (part == 0) {
      WriteFitOutputs(dir, run.result, run.job.title, &fit_warnings, run.sections);
    } else {
      WriteReportFiles(run, dir, &report_warnings);
    }
  });
  if (warnings == nullptr) return;
  for (std::vector<std::string>* part : {&fit_warnings, &report_warnings}) {
    warnings->insert(warnings->end(), part->begin(), part->end());
  }
}

}  // namespace

std::vector<std::string> WriteJobRun(const JobRun& run, const std::string& dir) {
  return WriteStaged(dir, [&](const std::string& staging, std::vector<std::string>* warnings) {
    WriteJobRunFiles(run, staging, warnings);
  });
}

std::vector<std::string> WriteJobRuns(
    const std::vector<JobRun>& runs, const std::vector<std::string>& subdirs,
    const std::vector<std::pair<std::string, std::string>>& files, const std::string& dir) {
  if (runs.size() != subdirs.size()) {
    throw std::invalid_argument("WriteJobRuns: expected a folder name per run, got " +
                                std::to_string(subdirs.size()) + " for " +
                                std::to_string(runs.size()) + " runs");
  }
  return WriteStaged(dir, [&](const std::string& staging, std::vector<std::string>* warnings) {
    for (size_t k = 0; k < runs.size(); ++k) {
      const std::string sub = staging + "/" + subdirs[k];
      std::error_code ec;
      std::filesystem::create_directories(sub, ec);
      if (ec) throw std::runtime_error(sub + ": cannot create the folder: " + ec.message());
      WriteJobRunFiles(runs[k], sub, warnings);
    }
    for (const auto& [name, contents] : files) WriteFileAtomic(staging + "/" + name, contents);
  });
}

}  // namespace axis
