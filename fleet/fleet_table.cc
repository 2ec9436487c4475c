#include "fleet/fleet_table.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/format.h"
#include "common/json_fields.h"
#include "discovery/diagnostics.h"
#include "estimation/fit_result.h"
#include "run/fit_job.h"
#include "run/job_run.h"
#include "run/write_job_run.h"
#include "sim/channels.h"
#include "sim/config.h"
#include "io/csv.h"

namespace axis {
namespace {

using Json = nlohmann::ordered_json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void FillRow(const JobRun& run, FleetRow* row) {
  const FitResult& r = run.result;
  row->status = r.converged ? "ok" : "not converged";
  for (const ParameterEstimate& p : r.parameters) {
    if (!p.free) continue;
    row->parameters.push_back(
        {p.name, p.unit, p.value, p.std_error, p.ci95_low, p.ci95_high, p.determined});
  }
  row->effects = EnabledEffectNames(run.job.problem.model.structure);
  row->discovery = run.discovered;
  ResidualVerdict verdict;
  if (run.discovered) {
    row->discovered = run.discovery.selected;
    verdict = run.discovery.verdict;
  } else if (!run.diagnostics.empty()) {
    verdict = JudgeResiduals(run.diagnostics, r, run.job.discover.alpha);
  }
  row->verdict = verdict.verdict;
  row->s2 = verdict.verdict.empty() ? kNaN : verdict.s2;
  row->remains = verdict.remains;
  for (const ExperimentFit& e : r.experiments) {
    for (const ChannelFit& c : e.channels) {
      const bool shown = e.role == "fit" ? c.fitted : c.channel != "u";
      if (shown) row->fits.push_back({e.name, c.channel, c.fitted, c.fit_percent});
    }
  }
}

// ------------------------------------------------------------- JSON

Json Number(double v) { return JsonNumber<Json>(v); }

// ------------------------------------------------------------- comparison

std::string RowName(const FleetRow& r) { return r.axis + " (" + r.log + ")"; }

// " (+42 %)", the change relative to the baseline; "" where the baseline
// value is within two standard errors of 0 (a percentage of nothing).
std::string RelativeChange(double value, double baseline, double baseline_se) {
  if (!(std::fabs(baseline) > 2.0 * baseline_se) || !std::isfinite(baseline)) return "";
  const double percent = 100.0 * (value - baseline) / std::fabs(baseline);
  return std::string(" (") + (percent >= 0 ? "+" : "") + FormatNumber(percent, 2) + " %)";
}

std::string ValueText(double value, double se, const std::string& unit) {
  return FormatNumber(value, 6) + " ± " + FormatNumber(se, 2) + (unit.empty() ? "" : " " + unit);
}

// ------------------------------------------------------------- files

std::string CsvNumber(double v) { return std::isfinite(v) ? FormatNumber(v, 17) : ""; }

}  // namespace

std::string FleetCsv(const FleetTable& table) {
  const auto params = FleetParameterColumns(table.rows);
  const auto fits = FleetFitColumns(table.rows);
  std::vector<std::string> header = {"axis", "log", "status", "verdict", "s2", "effects",
                                     "discovered"};
  for (const auto& [name, unit] : params) {
    header.push_back(name);
    header.push_back(name + "_se");
  }
  for (const std::string& f : fits) header.push_back("fit_" + f);
  for (const char* h : {"seconds", "rank", "folder", "error"}) header.push_back(h);
  std::string out;
  for (size_t k = 0; k < header.size(); ++k) out += (k ? "," : "") + CsvField(header[k]);
  out += "\n";
  for (const FleetRow& r : table.rows) {
    std::vector<std::string> cells = {r.axis, r.log, r.status, r.verdict, CsvNumber(r.s2),
                                      Join(r.effects, " "), Join(r.discovered, " ")};
    for (const auto& column : params) {
      const FleetParameter* p = r.FindParameter(column.first);
      cells.push_back(p ? CsvNumber(p->value) : "");
      cells.push_back(p ? CsvNumber(p->std_error) : "");
    }
    for (const std::string& f : fits) {
      const FleetChannelFit* c = r.FindFit(f);
      cells.push_back(c ? CsvNumber(c->fit_percent) : "");
    }
    cells.push_back(FormatNumber(r.seconds, 4));
    cells.push_back(std::to_string(r.rank));
    cells.push_back(r.folder);
    cells.push_back(r.error);
    for (size_t k = 0; k < cells.size(); ++k) out += (k ? "," : "") + CsvField(cells[k]);
    out += "\n";
  }
  return out;
}

// A Markdown table cell: '|' escaped, line breaks as spaces.
std::string MdCell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|') {
      out += "\\|";
    } else if (c == '\n' || c == '\r') {
      out += ' ';
    } else {
      out += c;
    }
  }
  return out;
}

const FleetParameter* FleetRow::FindParameter(const std::string& name) const {
  for (const FleetParameter& p : parameters) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

const FleetChannelFit* FleetRow::FindFit(const std::string& column) const {
  for (const FleetChannelFit& f : fits) {
    if (f.experiment + "/" + f.channel == column) return &f;
  }
  return nullptr;
}

std::vector<std::pair<std::string, std::string>> FleetParameterColumns(
    const std::vector<FleetRow>& rows) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const FleetRow& r : rows) {
    for (const FleetParameter& p : r.parameters) {
      const bool seen = std::any_of(out.begin(), out.end(),
                                    [&p](const auto& c) { return c.first == p.name; });
      if (!seen) out.emplace_back(p.name, p.unit);
    }
  }
  return out;
}

std::vector<std::string> FleetFitColumns(const std::vector<FleetRow>& rows) {
  std::vector<std::string> out;
  for (const FleetRow& r : rows) {
    for (const FleetChannelFit& f : r.fits) {
      const std::string name = f.experiment + "/" + f.channel;
      if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
    }
  }
  return out;
}

FleetRow RunFleetEntry(const FleetManifest& manifest, size_t index, const std::string& out_dir) {
  const FleetEntry& entry = manifest.entries.at(index);
  FleetRow row;
  row.axis = entry.axis;
  row.log = entry.log;
  row.job = entry.job_path.empty() ? manifest.template_path : entry.job_path;
  row.folder = entry.Folder();
  const auto start = std::chrono::steady_clock::now();
  try {
    FitJob job = MakeFleetJob(manifest, entry, out_dir);
    std::ostringstream log;
    log << "fit-fleet: " << job.title << "\n";
    JobRun run = RunJob(std::move(job), manifest.discover, log);
    for (const std::string& w : WriteJobRun(run, run.job.out_dir)) log << "warning: " << w << "\n";
    WriteFileAtomic(run.job.out_dir + "/fit.log", log.str());
    FillRow(run, &row);
  } catch (const std::exception& e) {
    row.status = "failed";
    row.error = e.what();
  } catch (...) {
    row.status = "failed";
    row.error = "an exception not derived from std::exception";
  }
  if (row.status == "failed") row.parameters.clear();
  row.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return row;
}

nlohmann::ordered_json FleetRowToJson(const FleetRow& r) {
  Json j;
  j["axis"] = r.axis;
  j["log"] = r.log;
  j["job"] = r.job;
  j["folder"] = r.folder;
  j["status"] = r.status;
  j["error"] = r.error;
  Json params = Json::array();
  for (const FleetParameter& p : r.parameters) {
    params.push_back({{"name", p.name},
                      {"unit", p.unit},
                      {"value", Number(p.value)},
                      {"std_error", Number(p.std_error)},
                      {"ci95_low", Number(p.ci95_low)},
                      {"ci95_high", Number(p.ci95_high)},
                      {"determined", p.determined}});
  }
  j["parameters"] = params;
  j["effects"] = r.effects;
  j["discovery"] = r.discovery;
  j["discovered"] = r.discovered;
  j["verdict"] = r.verdict;
  j["s2"] = Number(r.s2);
  j["remains"] = r.remains;
  Json fits = Json::array();
  for (const FleetChannelFit& f : r.fits) {
    fits.push_back({{"experiment", f.experiment},
                    {"channel", f.channel},
                    {"fitted", f.fitted},
                    {"fit_percent", Number(f.fit_percent)}});
  }
  j["fits"] = fits;
  j["seconds"] = Number(r.seconds);
  j["rank"] = r.rank;
  return j;
}

FleetRow FleetRowFromJson(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) {
    throw std::invalid_argument(where + ": expected a row (an object), got " +
                                j.dump().substr(0, 60));
  }
  FleetRow r;
  r.axis = JsonStringField(j, "axis", where);
  r.log = JsonStringField(j, "log", where);
  r.job = JsonStringField(j, "job", where);
  r.folder = JsonStringField(j, "folder", where);
  r.status = JsonStringField(j, "status", where);
  if (r.status != "ok" && r.status != "not converged" && r.status != "failed") {
    throw std::invalid_argument(where + ".status: expected ok, not converged or failed, got '" +
                                r.status + "'");
  }
  r.error = JsonStringField(j, "error", where);
  const nlohmann::json& params = JsonArrayField(j, "parameters", where);
  for (size_t k = 0; k < params.size(); ++k) {
    const std::string at = where + ".parameters[" + std::to_string(k) + "]";
    r.parameters.push_back(
        {JsonStringField(params[k], "name", at), JsonStringField(params[k], "unit", at),
         JsonNumberField(params[k], "value", at), JsonNumberField(params[k], "std_error", at),
         JsonNumberField(params[k], "ci95_low", at), JsonNumberField(params[k], "ci95_high", at),
         JsonBoolField(params[k], "determined", at)});
  }
  r.effects = JsonStrings(j, "effects", where);
  r.discovery = JsonBoolField(j, "discovery", where);
  r.discovered = JsonStrings(j, "discovered", where);
  r.verdict = JsonStringField(j, "verdict", where);
  r.s2 = JsonNumberField(j, "s2", where);
  r.remains = JsonStrings(j, "remains", where);
  const nlohmann::json& fits = JsonArrayField(j, "fits", where);
  for (size_t k = 0; k < fits.size(); ++k) {
    const std::string at = where + ".fits[" + std::to_string(k) + "]";
    r.fits.push_back({JsonStringField(fits[k], "experiment", at),
                      JsonStringField(fits[k], "channel", at), JsonBoolField(fits[k], "fitted", at),
                      JsonNumberField(fits[k], "fit_percent", at)});
  }
  r.seconds = JsonNumberField(j, "seconds", where);
  const nlohmann::json& rank =
      JsonField(j, "rank", where, nlohmann::json::value_t::number_float, "an integer");
  r.rank = rank.is_number_integer() ? rank.get<int>() : 0;
  return r;
}

FleetComparison CompareFleets(const std::vector<FleetRow>& rows,
                              const std::vector<FleetRow>& baseline, double alpha,
                              const std::string& baseline_path) {
  if (!(alpha > 0.0 && alpha < 1.0)) {
    throw std::invalid_argument("CompareFleets: expected a level in (0, 1), got " +
                                FormatNumber(alpha));
  }
  FleetComparison c;
  c.baseline = baseline_path;
  c.alpha = alpha;
  std::vector<FleetChange> effects, parameters;
  for (const FleetRow& r : rows) {
    const FleetRow* old = nullptr;
    for (const FleetRow& b : baseline) {
      if (b.axis != r.axis) continue;
      if (b.log == r.log) {
        old = &b;
        break;
      }
      old = &b;  // the last row of the axis unless one has the same log
    }
    if (old == nullptr) {
      c.not_compared.push_back(RowName(r) + ": no baseline row");
      continue;
    }
    if (r.status != "ok") {
      c.not_compared.push_back(RowName(r) + ": " + r.status);
      continue;
    }
    if (old->status != "ok") {
      c.not_compared.push_back(RowName(r) + ": baseline row (" + old->log + ") " + old->status);
      continue;
    }
    const std::string prefix = "axis " + RowName(r) + ": ";
    for (const auto& [mine, theirs, kind] :
         {std::make_tuple(&r.effects, &old->effects, "effect appeared"),
          std::make_tuple(&old->effects, &r.effects, "effect disappeared")}) {
      for (const std::string& e : *mine) {
        if (std::find(theirs->begin(), theirs->end(), e) != theirs->end()) continue;
        FleetChange change;
        change.axis = r.axis;
        change.log = r.log;
        change.baseline_log = old->log;
        change.kind = kind;
        change.name = e;
        change.text = prefix + "effect " + e + (std::string(kind) == "effect appeared"
                                                    ? " appeared"
                                                    : " disappeared");
        effects.push_back(change);
      }
    }
    for (const FleetParameter& p : r.parameters) {
      const FleetParameter* q = old->FindParameter(p.name);
      if (q == nullptr) continue;
      const double se = std::sqrt(p.std_error * p.std_error + q->std_error * q->std_error);
      if (!std::isfinite(se) || se <= 0.0 || !std::isfinite(p.value) ||
          !std::isfinite(q->value)) {
        c.not_compared.push_back(RowName(r) + ": " + p.name + " has no finite standard error");
        continue;
      }
      ++c.tests;
      FleetChange change;
      change.axis = r.axis;
      change.log = r.log;
      change.baseline_log = old->log;
      change.kind = "parameter";
      change.name = p.name;
      change.unit = p.unit;
      change.value = p.value;
      change.std_error = p.std_error;
      change.baseline_value = q->value;
      change.baseline_std_error = q->std_error;
      change.z = (p.value - q->value) / se;
      change.p_value = std::erfc(std::fabs(change.z) / std::sqrt(2.0));
      change.text = prefix + p.name + " " + ValueText(p.value, p.std_error, p.unit) + ", was " +
                    ValueText(q->value, q->std_error, q->unit) +
                    RelativeChange(p.value, q->value, q->std_error) + ", z = " + FormatNumber(change.z, 3);
      parameters.push_back(change);
    }
  }
  const double threshold = c.tests > 0 ? alpha / c.tests : alpha;
  parameters.erase(std::remove_if(parameters.begin(), parameters.end(),
                                  [threshold](const FleetChange& x) {
                                    return !(x.p_value < threshold);
                                  }),
                   parameters.end());
  std::stable_sort(parameters.begin(), parameters.end(),
                   [](const FleetChange& a, const FleetChange& b) {
                     return std::fabs(a.z) > std::fabs(b.z);
                   });
  c.changes = effects;
  c.changes.insert(c.changes.end(), parameters.begin(), parameters.end());
  return c;
}

std::vector<FleetRow> LoadFleetJson(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw std::invalid_argument(path + ": expected a fleet.json file, got a directory");
  }
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path + ": cannot read");
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(path + ": invalid JSON: " + e.what());
  } catch (const std::ios_base::failure& e) {
    throw std::invalid_argument(path + ": cannot read: " + e.what());
  }
  std::vector<FleetRow> rows;
  const nlohmann::json& list = JsonArrayField(doc, "rows", path);
  for (size_t k = 0; k < list.size(); ++k) {
    rows.push_back(FleetRowFromJson(list[k], path + ": rows[" + std::to_string(k) + "]"));
  }
  return rows;
}

std::string FormatFleetMarkdown(const FleetTable& t) {
  int ok = 0, not_converged = 0, failed = 0;
  for (const FleetRow& r : t.rows) {
    ok += r.status == "ok";
    not_converged += r.status == "not converged";
    failed += r.status == "failed";
  }
  std::ostringstream out;
  out << "# " << t.title << "\n\n"
      << t.rows.size() << " jobs: " << ok << " ok, " << not_converged << " not converged, "
      << failed << " failed; " << t.ranks << " rank(s), " << t.threads
      << " solver thread(s) per job; " << FormatNumber(t.wall_seconds, 3) << " s wall.\n"
      << "Manifest: " << t.manifest << "\n";
  if (t.compared) {
    const FleetComparison& c = t.comparison;
    out << "\n## Changes since " << c.baseline << "\n\n"
        << "Each free parameter against its baseline fit: z = (new − old)/√(se_new² + se_old²), "
        << "flagged when its two-sided p-value is below " << FormatNumber(c.alpha) << "/"
        << c.tests << " (family-wise level " << FormatNumber(c.alpha) << " over " << c.tests
        << " comparisons); effects that appeared or disappeared are always flagged.\n\n";
    if (c.changes.empty()) out << "No change.\n";
    for (const FleetChange& ch : c.changes) out << "- " << ch.text << "\n";
    if (!c.not_compared.empty()) {
      out << "\nNot compared:\n\n";
      for (const std::string& n : c.not_compared) out << "- " << n << "\n";
    }
  }
  const auto params = FleetParameterColumns(t.rows);
  const auto fits = FleetFitColumns(t.rows);
  out << "\n## Axes\n\n| axis | log | status | verdict | s² | effects |";
  for (const auto& [name, unit] : params) out << " " << name << " (" << unit << ") |";
  for (const std::string& f : fits) out << " fit % " << f << " |";
  out << " time (s) |\n|---|---|---|---|---|---|";
  for (size_t k = 0; k < params.size() + fits.size(); ++k) out << "---|";
  out << "---|\n";
  for (const FleetRow& r : t.rows) {
    out << "| " << MdCell(r.axis) << " | " << MdCell(r.log) << " | " << r.status << " | "
        << (r.verdict.empty() ? "-" : r.verdict) << " | " << FormatNumber(r.s2, 3, "-") << " | "
        << MdCell(Join(r.effects, ", ")) << " |";
    for (const auto& column : params) {
      const FleetParameter* p = r.FindParameter(column.first);
      out << " " << (p ? FormatNumber(p->value, 6) + " ± " + FormatNumber(p->std_error, 2) : "")
          << " |";
    }
    for (const std::string& f : fits) {
      const FleetChannelFit* c = r.FindFit(f);
      out << " " << (c ? FormatNumber(c->fit_percent, 4) : "") << " |";
    }
    out << " " << FormatNumber(r.seconds, 3) << " |\n";
  }
  if (failed > 0) {
    out << "\n## Failed jobs\n\n";
    for (const FleetRow& r : t.rows) {
      if (r.status == "failed") out << "- " << RowName(r) << ": " << r.error << "\n";
    }
  }
  bool remains = false;
  for (const FleetRow& r : t.rows) remains |= r.verdict == "incomplete";
  if (remains) {
    out << "\n## What the models still miss (verdict incomplete)\n\n";
    for (const FleetRow& r : t.rows) {
      if (r.verdict != "incomplete") continue;
      out << "- " << RowName(r) << ": " << (r.remains.empty() ? "s² above 1" : Join(r.remains, "; "))
          << "\n";
    }
  }
  return out.str();
}

nlohmann::ordered_json FleetTableToJson(const FleetTable& t) {
  Json j;
  j["title"] = t.title;
  j["manifest"] = t.manifest;
  j["ranks"] = t.ranks;
  j["threads"] = t.threads;
  j["wall_seconds"] = Number(t.wall_seconds);
  Json rows = Json::array();
  for (const FleetRow& r : t.rows) rows.push_back(FleetRowToJson(r));
  j["rows"] = rows;
  if (t.compared) {
    const FleetComparison& c = t.comparison;
    Json changes = Json::array();
    for (const FleetChange& ch : c.changes) {
      Json x = {{"axis", ch.axis},   {"log", ch.log},   {"baseline_log", ch.baseline_log},
                {"kind", ch.kind},   {"name", ch.name}, {"unit", ch.unit}};
      if (ch.kind == "parameter") {
        x["value"] = Number(ch.value);
        x["std_error"] = Number(ch.std_error);
        x["baseline_value"] = Number(ch.baseline_value);
        x["baseline_std_error"] = Number(ch.baseline_std_error);
        x["z"] = Number(ch.z);
        x["p_value"] = Number(ch.p_value);
      }
      x["text"] = ch.text;
      changes.push_back(x);
    }
    j["comparison"] = {{"baseline", c.baseline}, {"alpha", c.alpha},     {"tests", c.tests},
                       {"changes", changes},     {"not_compared", c.not_compared}};
  }
  return j;
}


}  // namespace axis
