// The fleet table of fit-fleet (issue 12): one row per job (an axis and one
// of its logs) with the free parameters ± standard error, the effects of
// the final model, the residual verdict, the fit % per channel, the status
// and the wall time; the comparison with an earlier fleet (--baseline); and
// the files fleet.csv, fleet.md, fleet.html and fleet.json.
#ifndef FLEET_FLEET_TABLE_H_
#define FLEET_FLEET_TABLE_H_

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "fleet/manifest.h"

namespace axis {

// A free parameter of a job's final fit (estimation/fit_result.h ParameterEstimate).
struct FleetParameter {
  std::string name, unit;   // MODEL.md name and SI unit
  double value = 0.0;
  double std_error = 0.0;   // NaN if not computed
  double ci95_low = 0.0, ci95_high = 0.0;
  bool determined = true;   // false: the data cannot determine it
};

// The goodness of fit of one channel (estimation/fit_result.h ChannelFit): the
// fitted channels of the fitted experiments, and the measured channels
// other than u of the validation experiments.
struct FleetChannelFit {
  std::string experiment, channel;
  bool fitted = false;
  double fit_percent = 0.0;  // NRMSE fit, %
};

struct FleetRow {
  std::string axis, log;
  std::string job;     // the job file, or the manifest's template
  std::string folder;  // "<axis>/<log>": the job's output folder below the fleet's
  // "ok", "not converged" (the solver stopped without converging: the
  // figures are reported but not compared) or "failed" (`error` says why).
  std::string status;
  std::string error;
  std::vector<FleetParameter> parameters;  // free parameters, job order
  // The dynamic and sensor effects of the final model (MODEL.md §7 names,
  // "sensor_delay.a" style), in DynamicEffectTable order; those the
  // discovery loop added in `discovered` (if it ran: `discovery`).
  std::vector<std::string> effects;
  bool discovery = false;
  std::vector<std::string> discovered;
  // The residual verdict of the final model (discovery/diagnostics.h
  // JudgeResiduals at the job's discover.alpha): "explained" or
  // "incomplete" ("" if not judged), s² in σ units, and what remains.
  std::string verdict;
  double s2 = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::string> remains;
  std::vector<FleetChannelFit> fits;
  double seconds = 0.0;  // s, wall time of the job (load, fit, outputs)
  int rank = 0;          // the MPI rank that ran it

  // The free parameter `name`, or null.
  const FleetParameter* FindParameter(const std::string& name) const;
  // The fit of "<experiment>/<channel>", or null.
  const FleetChannelFit* FindFit(const std::string& column) const;
};

// The columns of a fleet table: the free parameters of any row (name and
// unit, in order of first appearance), and the channel fits of any row
// ("<experiment>/<channel>", the same order).
std::vector<std::pair<std::string, std::string>> FleetParameterColumns(
    const std::vector<FleetRow>& rows);
std::vector<std::string> FleetFitColumns(const std::vector<FleetRow>& rows);

// Runs job `index` of `manifest` as fit-params would, output folder
// `out_dir`/<axis>/<log> (MakeFleetJob, RunJob, WriteJobRun), plus fit.log
// there: what fit-params prints, and the output warnings. Never throws
// (except std::bad_alloc): an exception of the job (bad data, a failed
// simulation, an unwritable folder, anything derived from std::exception
// or not) makes a row with status "failed" and its message. A crash that
// kills the process (a signal) cannot be caught here.
FleetRow RunFleetEntry(const FleetManifest& manifest, size_t index, const std::string& out_dir);

// A row as JSON (the rows of fleet.json) and back: numbers that are not
// finite are null (read back as NaN); doubles round-trip exactly.
// FleetRowFromJson throws std::invalid_argument "<where>: expected …, got
// …" for a document that is not such a row.
nlohmann::ordered_json FleetRowToJson(const FleetRow& row);
FleetRow FleetRowFromJson(const nlohmann::json& json, const std::string& where);

// A flagged difference between a row and its baseline row.
struct FleetChange {
  std::string axis, log;    // the row
  std::string baseline_log; // the baseline row it was compared with
  // "parameter", "effect appeared", "effect disappeared"
  std::string kind;
  std::string name, unit;   // the parameter or effect
  // Parameters: the new and the baseline value and standard errors, and
  // z = (new − old)/√(se_new² + se_old²) with its two-sided normal p-value.
  double value = 0.0, std_error = 0.0, baseline_value = 0.0, baseline_std_error = 0.0;
  double z = 0.0, p_value = 1.0;
  // One line, e.g. "axis r03/x (now): F_c 40.0073 ± 0.04 N, was 25.0043 ±
  // 0.0433 N (+60 %), z = 255"; "axis r03/x (now): effect stribeck appeared".
  std::string text;
};

struct FleetComparison {
  std::string baseline;  // the baseline fleet.json
  double alpha = 0.05;   // family-wise level
  int tests = 0;         // parameter comparisons made (Bonferroni)
  // Effect changes first (every one is flagged), then the parameters whose
  // p-value is below alpha / tests, by decreasing |z|.
  std::vector<FleetChange> changes;
  // Rows not compared, one line each, e.g. "r09/x (now): no baseline row",
  // "r01/x (now): failed", "r02/x (now): baseline row not converged".
  std::vector<std::string> not_compared;
};

// Compares `rows` with `baseline` (rows of an earlier fleet.json). A row is
// compared with the baseline row of the same axis and log, else with the
// baseline's last row of that axis; only rows "ok" on both sides. Every
// free parameter the two share is tested with z above (standard errors
// from both fits: the baseline's estimate is no truth either), at
// family-wise level `alpha` over all the fleet's tests (Bonferroni); an
// effect in one final model and not in the other is always a change.
// Throws std::invalid_argument unless 0 < alpha < 1.
FleetComparison CompareFleets(const std::vector<FleetRow>& rows,
                              const std::vector<FleetRow>& baseline, double alpha,
                              const std::string& baseline_path);

// The rows of a fleet.json. Throws std::invalid_argument "<path>: cannot
// read", "<path>: invalid JSON: …" or FleetRowFromJson's errors.
std::vector<FleetRow> LoadFleetJson(const std::string& path);

// A whole fleet run.
struct FleetTable {
  std::string title;
  std::string manifest;        // the manifest file
  std::vector<FleetRow> rows;  // manifest order
  int ranks = 1;               // MPI ranks
  int threads = 1;             // solver threads per job
  double wall_seconds = 0.0;   // s, the whole run
  bool compared = false;       // --baseline given: `comparison` filled
  FleetComparison comparison;
};

// fleet.md: the summary line, the changes (if compared), the table (axis,
// log, status, verdict, s², effects, each free parameter "value ± se",
// fit % per channel, time) and the failed jobs with their errors.
std::string FormatFleetMarkdown(const FleetTable& table);

// fleet.json: title, manifest, ranks, threads, wall_seconds, rows
// (FleetRowToJson), and "comparison" if compared.
nlohmann::ordered_json FleetTableToJson(const FleetTable& table);

// The table as fleet.csv holds it: a row per job (axis, log, status,
// verdict, s2, effects, discovered, per free parameter of any row its value
// and "<name>_se", per channel "fit_<experiment>_<channel>" (%), seconds,
// rank, folder, error; empty cells where a row has none). Never throws
// (except std::bad_alloc).
std::string FleetCsv(const FleetTable& table);

}  // namespace axis

#endif  // FLEET_FLEET_TABLE_H_
