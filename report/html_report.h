// report.html (issue 14): one self-contained page per run that a person
// opens, reads and sends on. Everything is inside the file: the style sheet
// and a few lines of script (sorting a table by a click on its header) are
// inline, the plots are inline SVG drawn by gnuplot's svg terminal
// (RenderGnuplotSvg, report/report.h); the page loads nothing, neither from
// the network nor from beside it. Every text that comes from a job, a model
// config or a data file (titles, names, paths, notes) is HTML-escaped.
//
// Sections, each present when the run has it: the job's title and data
// files; a summary (cost, BIC, optimum check, the verdict); the parameter
// table (value, standard error, 95 % interval, initial value, bounds,
// free/fixed; the fixed ones folded); the correlations of the free
// parameters as a coloured table (a heat map from −1 blue to +1 red); the
// goodness of fit per experiment and channel; per experiment the measured
// and simulated traces and the residuals (SVG); the residual diagnostics
// (tables and SVG of the binned mean residuals); the frequency response
// (Bode magnitude, phase and coherence SVG); the discovery loop (first
// ranking, every step with its before/after table, significance, the final
// model's diagnostics, the verdict with what remains); the validation
// experiments; the published comparison; the solver's account.
#ifndef REPORT_HTML_REPORT_H_
#define REPORT_HTML_REPORT_H_

#include <string>
#include <vector>

#include "design/experiment_design.h"
#include "common/phase_log.h"
#include "discovery/diagnostics.h"
#include "discovery/discovery.h"
#include "discovery/force_map.h"
#include "discovery/frequency_response.h"
#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"
#include "report/published.h"
#include "tune/analog_loop_tuning.h"
#include "tune/move_tuning.h"

namespace axis {

// What the page shows. `result` is required; a null pointer leaves its
// section out. The pointed-to objects must outlive the call.
struct HtmlReportInput {
  std::string title;                  // the job's title ("Fit report" if empty)
  const FitResult* result = nullptr;  // the final fit
  // The job of the final model (after discovery: with its effects): data
  // files, windows, fitted channels with σ, bounds of the free parameters.
  const EstimationProblem* job = nullptr;
  // Residual diagnostics of the model as declared (with discovery: before
  // the loop; without: of the fitted model).
  const std::vector<ChannelDiagnostics>* diagnostics = nullptr;
  const DiscoveryReport* discovery = nullptr;  // the loop ran
  // The force-map step after the loop (discovery/force_map.h), if the job asked
  // for it: its text and, if a map was refitted, its plot.
  const ForceMapReport* force_map = nullptr;
  // The frequency response of each fitted experiment
  // (discovery/frequency_response.h): a table, the notes of the records
  // without one, and a Bode plot (magnitude, phase, coherence) per
  // experiment and channel.
  const std::vector<ExperimentFrequencyResponse>* frequency_response = nullptr;
  const PublishedComparison* published = nullptr;  // the job has `published:`
  // The next experiment (design/experiment_design.h), if the job has
  // `design:`: FormatProposal's text and, if one was proposed, the ten
  // best feasible inputs of the family by the criterion.
  const ExperimentProposal* proposal = nullptr;
  // The tuning (tune/analog_loop_tuning.h), if the job has `tune:`: its
  // text (report/tuning_report.h FormatTuning).
  const AnalogLoopTuning* tuning = nullptr;
  // The move tuning (tune/move_tuning.h), if the job has `tune.move:`.
  const MoveTuning* move_tuning = nullptr;
  // How drive columns were read where the job did not say, one line each
  // ("<experiment>: <note>").
  std::vector<std::string> input_notes;
  // The run's other output files, listed on the page (names, no links).
  std::vector<std::string> files;
  // Where the run's time went, phase by phase (common/phase_log.h); none
  // drawn if empty.
  std::vector<RunPhase> run_phases;
};

// The number of inline SVG plots RenderHtmlReport draws when gnuplot works:
// one per experiment of the result, one per channel of `diagnostics`, one
// per channel of the discovery's final diagnostics, one for a force map
// with a curve, one per channel of the frequency response.
int HtmlReportPlotCount(const HtmlReportInput& input);

// The page as text. Plots are drawn by gnuplot, several at once
// (common/concurrency.h ProcessThreads), with temporary files in
// `scratch_dir` (removed again); traces longer than about 2000 samples are
// thinned for the plot, keeping each series' minimum and maximum in every
// stretch of samples so that spikes stay visible (the fit_*.csv files keep
// every sample). A plot that cannot be drawn (gnuplot missing or failing)
// is replaced by a note on the page and its message appended to *warnings
// (if not null). Throws std::invalid_argument "expected a fit result, got
// none" if input.result is null, std::runtime_error if a temporary file
// cannot be written.
std::string RenderHtmlReport(const HtmlReportInput& input, const std::string& scratch_dir,
                             std::vector<std::string>* warnings);

// Writes RenderHtmlReport(input) to `path` atomically (WriteFileAtomic,
// io/csv.h), with its temporary files in path's folder. Throws as
// RenderHtmlReport, and std::runtime_error naming `path` if it cannot be
// written.
void WriteHtmlReport(const std::string& path, const HtmlReportInput& input,
                     std::vector<std::string>* warnings);

// `text` with &, <, >, " and ' replaced by character references, and bytes
// that are not valid UTF-8 by U+FFFD, so that it reads as the same text in
// HTML content and in quoted attribute values.
std::string HtmlEscape(const std::string& text);

// Building blocks of the project's HTML pages, shared by report.html and
// fit-fleet's fleet.html (fleet/internal/fleet_html.h): one style sheet, tables
// sortable by a click on a header, sections with a navigation bar.

// A table cell: its HTML (already escaped), whether it is a number
// (right-aligned) and, if not empty, the value a sortable table sorts by
// instead of the text.
struct HtmlCell {
  std::string html;
  bool number = false;
  std::string sort;
};

// A text cell (HtmlEscape'd). Never throws (except std::bad_alloc).
HtmlCell HtmlTextCell(const std::string& text);

// A number cell: FormatNumber(value, digits) ("—" for NaN), right-aligned,
// sorted by its full value. Never throws (except std::bad_alloc).
HtmlCell HtmlNumberCell(double value, int digits = 6);

struct HtmlTable {
  std::vector<std::string> headers;            // plain text, escaped when rendered
  std::vector<std::vector<HtmlCell>> rows;
  bool sortable = false;                       // a click on a header sorts by it
  std::string css_class;                       // extra class of the <table>
};

// The table as HTML, in a box that scrolls sideways if it is wider than the
// page. Never throws (except std::bad_alloc).
std::string RenderHtmlTable(const HtmlTable& table);

// A section of a page: its id (the navigation bar's anchor; letters,
// digits, '-', '_'), its heading (text) and its body (HTML).
struct HtmlSection {
  std::string id, heading, body;
};

// A whole self-contained page: `document_title` in <title>, `heading` as
// <h1>, `intro` (text) below it, a navigation bar to the sections, the
// sections in order, the project's style sheet and the sorting script
// inline. Never throws (except std::bad_alloc).
std::string RenderHtmlPage(const std::string& document_title, const std::string& heading,
                           const std::string& intro, const std::vector<HtmlSection>& sections);

}  // namespace axis

#endif  // REPORT_HTML_REPORT_H_
