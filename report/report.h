// Writing a FitResult: terminal tables, and the files of an output directory
// (params.md, params.csv, report.json, fit_<experiment>.csv/.png).
//
// Every file is written atomically (to a temporary in the same directory,
// then renamed over the target; see WriteFileAtomic in io/csv.h), so a
// reader sees either the previous file or the complete new one, and a failed
// write leaves no partial file. Write errors are std::runtime_error naming
// the path.
#ifndef REPORT_REPORT_H_
#define REPORT_REPORT_H_

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "estimation/fit_result.h"

namespace axis {

// Sections a caller adds to the report (the discovery loop): Markdown
// appended to params.md, and keys merged into report.json's top level.

struct ReportSections {
  std::string markdown;
  nlohmann::json json = nlohmann::json::object();
};

// A fixed-width text table of the parameters for the terminal, one row per
// parameter, free ones first (then fixed, each in result order): name, unit,
// value, std error, 95 % interval "[low, high]", initial, and "free" or
// "fixed" ("-" for a fixed parameter's std error and interval). A parameter
// with determined == false has "(not determined by the data)" after its
// free/fixed. Numbers with 6 significant digits; NaN prints as "nan". Ends
// with a newline. Never throws (except std::bad_alloc).
// The residual bootstrap's cross-check (estimation/uncertainty.h), one line per
// free parameter: the reported std error (FitResult::uncertainty_method),
// the Gauss–Newton one, the bootstrap's and its 95 % percentile interval;
// empty if no bootstrap ran.
std::string FormatBootstrap(const FitResult& result);

std::string FormatParameterTable(const FitResult& result);

// A fixed-width text table of the goodness of fit, one row per experiment and
// channel: experiment, role, channel, unit, fitted (yes/no), RMS and max
// error (channel unit), fit % (NRMSE), relative error %, the Ljung–Box
// p-value of the residual and the peak normalised cross-correlation of the
// residual with the input u with its lag in samples. Ends with a newline.
std::string FormatFitTable(const FitResult& result);

// One line: the wall time of FitParameters and, per phase
// (FitResult::phases), its seconds, simulations and Jacobian evaluations,
// e.g. "time: 41.2 s (starts 2.1 s: 40 simulations, 35 Jacobians, …)".
std::string FormatPhases(const FitResult& result);

// The final cost (½Σr²) of every start, the job's first, comma-separated;
// a start not continued to the whole record (solver.finalists) shows its
// cost at the end of the shorter horizons instead, and one that joined an
// earlier start's path (FitResult::start_joined) says which and where;
// "none" without starts.
std::string FormatStartCosts(const FitResult& result);

// The base names "fit_<name>" of the per-experiment files, one per entry of
// result.experiments: characters of the name other than ASCII letters,
// digits, '.', '-' and '_' become '_', an empty name becomes
// "experiment<index+1>", and a name equal to an earlier one (after this
// mapping) gets "_2", "_3", ... appended, so that no two experiments share a
// file.
std::vector<std::string> ExperimentFileStems(const FitResult& result);

// Writes the parameters as CSV: the header
//   name,unit,value,std_error,ci95_low,ci95_high,initial,free
// then one row per parameter in FormatParameterTable's order, numbers with
// the shortest text that reads back exactly, `free` as "free" or "fixed".
// A fixed parameter's std_error, ci95_low and ci95_high are empty cells; a
// free one's non-finite values are written "nan", "inf" or "-inf". Text
// cells are quoted where needed (a comma, quote or line break). Throws
// std::runtime_error naming `path` if it cannot be written.
void WriteParamsCsv(const std::string& path, const FitResult& result);

// Writes a Markdown report: "# <title>", the parameter table, the
// correlation matrix of the free parameters, the parameters not determined
// by the data (or "none"), the fit table, and the solver's account (cost
// initial/final, converged, the final cost of every start, AIC/BIC, number
// of residuals and residual variance, iterations, simulations, Jacobian
// evaluations, Ceres' termination message). Throws std::runtime_error naming
// `path` if it cannot be written.
void WriteParamsMarkdown(const std::string& path, const FitResult& result,
                         const std::string& title,
                         const ReportSections& extra = {});

// Writes the whole result as JSON (2-space indented):
//   {"parameters": [{"name", "unit", "value", "std_error", "ci95_low",
//                    "ci95_high", "initial", "free": bool,
//                    "determined": bool}],
//    "experiments": [{"name", "role": "fit"|"validate", "csv",
//                     "channels": [{"channel", "unit", "rms", "fit_percent",
//                                   "max_error", "mae", "relative_error_percent",
//                                   "ljung_box_q", "ljung_box_lags",
//                                   "ljung_box_p", "input_xcorr_peak",
//                                   "input_xcorr_lag", "sigma", "fitted"}]}],
//    "cost": {"initial", "final"}, "converged": bool,
//    "starts": [final cost of every start], "start_screen_costs": [...],
//    "screen_horizon", "start_joined": [earlier start whose path each
//    joined, or -1], "start_joined_horizon": [s, 0 if none], "aic", "bic",
//    "num_residuals",
//    "residual_variance", "iterations", "simulations",
//    "jacobian_evaluations", "termination",
//    "correlation": {"names": [...], "matrix": [[...], ...]},
//    "undetermined": [...]}
// ("csv" is the experiment's file name, ExperimentFileStems + ".csv"). A
// fixed parameter's std_error and ci95 are null; every NaN or infinite number
// is null. Strings that are not valid UTF-8 have the bad bytes replaced by
// U+FFFD. Throws std::runtime_error naming `path` if it cannot be written.
void WriteReportJson(const std::string& path, const FitResult& result,
                     const ReportSections& extra = {});

// The document WriteReportJson writes, in memory (key order kept; NaN and
// infinite numbers are null). Never throws (except std::bad_alloc).
nlohmann::ordered_json ReportJson(const FitResult& result,
                                  const ReportSections& extra = {});

// Writes the traces of one experiment as CSV: the column "t" (s), then for
// each channel c, in order, "<c>_measured", "<c>_simulated" and
// "<c>_residual" (= simulated − measured), in the channel unit; one row per
// sample, numbers with 12 significant digits (ReadCsv reads the file back if
// every value is finite; NaN and infinite values are written "nan", "inf",
// "-inf"). Throws std::invalid_argument (writing nothing) if a channel's
// measured or simulated length differs from t's, and std::runtime_error
// naming `path` if it cannot be written.
void WriteExperimentCsv(const std::string& path, const ExperimentFit& fit);

// Plots one experiment with gnuplot into the PNG `png_path`, reading the
// traces from `csv_path`, which must have been written by WriteExperimentCsv
// for the same `fit` (columns are addressed by position). One row per
// channel: left the measured and simulated channel against t, right the
// residual; titles carry the experiment and channel name and the unit. A
// series with no finite value is left out, an empty panel noted "no finite
// values" (a diverged simulation still gets its measured trace). Uses
// the pngcairo terminal if gnuplot has it, else png. gnuplot is found on
// PATH and run directly (no shell), its output drawn into a temporary file
// in png_path's directory that is then renamed to png_path.
//
// Returns true if the plot was written. Returns false, leaving no file and
// setting *warning (if warning is not null), if gnuplot is not on PATH
// ("gnuplot not found: no plot written for <name>"), if there is nothing to
// plot (no channels or no samples), if a path contains a line break, or if
// gnuplot fails (the message carries its exit status and last error line).
// Throws std::runtime_error naming png_path only if the finished plot cannot
// be renamed into place.
bool WriteExperimentPlot(const std::string& png_path,
                         const std::string& csv_path, const ExperimentFit& fit,
                         std::string* warning);


// The panels of WriteExperimentPlot (measured and simulated against t, the
// residual beside them, units on the axes, a legend per panel) as inline
// SVG (RenderGnuplotSvg), from `csv_path` written by WriteExperimentCsv for
// `fit` (or for a copy of `fit` with fewer samples: the plot reads the
// file). Temporary files go beside csv_path. Returns false with *warning
// set as RenderGnuplotSvg, or if there is nothing to plot.
bool RenderExperimentSvg(const std::string& csv_path, const ExperimentFit& fit,
                         const std::string& id_prefix, std::string* svg,
                         std::string* warning);


// Writes every output of a fit into `dir` (created with its parents if
// missing): params.csv, params.md (titled `title`), report.json, and for each
// experiment <stem>.csv and <stem>.png (stems from ExperimentFileStems, e.g.
// fit_step.csv); the experiments' CSV and plot pairs are written several at
// once (common/concurrency.h ProcessThreads). Plot problems (WriteExperimentPlot
// returning false) do not stop the run: their messages are appended to
// *warnings (if not null) in experiment order. Throws std::runtime_error
// naming the directory or file that cannot be created or written (every
// file written stays complete; of several failures, the first
// experiment's), and
// std::invalid_argument as WriteExperimentCsv.
void WriteFitOutputs(const std::string& dir, const FitResult& result,
                     const std::string& title,
                     std::vector<std::string>* warnings,
                     const ReportSections& extra = {});

}  // namespace axis

#endif  // REPORT_REPORT_H_
