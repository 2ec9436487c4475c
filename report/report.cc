#include "report/report.h"

#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iterator>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <nlohmann/json.hpp>

#include "common/concurrency.h"
#include "common/format.h"
#include "common/gnuplot.h"
#include "estimation/fit_result.h"
#include "io/csv.h"

extern char** environ;

namespace axis {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// ---------------------------------------------------------------- numbers

// "%.*g" of `digits` significant digits; "nan", "inf", "-inf" if not finite.
std::string Num(double value, int digits = 6) { return FormatNumber(value, digits, "nan"); }

// The shortest "%.*g" text that reads back as `value` (non-finite as Num).
std::string Exact(double value) {
  if (!std::isfinite(value)) return Num(value);
  char buf[40];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof(buf), "%.*g", precision, value);
    if (std::strtod(buf, nullptr) == value) break;
  }
  return buf;
}

// ---------------------------------------------------------------- tables

// Indices of result.parameters, free ones first, each group in result order.
std::vector<size_t> ParameterOrder(const FitResult& result) {
  std::vector<size_t> order;
  for (int pass = 0; pass < 2; ++pass) {
    for (size_t k = 0; k < result.parameters.size(); ++k) {
      if (result.parameters[k].free == (pass == 0)) order.push_back(k);
    }
  }
  return order;
}

}  // namespace

namespace {

constexpr const char* kNotDetermined = "(not determined by the data)";

TextTable ParameterTable(const FitResult& result) {
  TextTable table;
  table.headers = {"name",     "unit",    "value", "std error",
                   "95 % interval", "initial", "free/fixed"};
  table.right = {false, false, true, true, false, true, false};
  for (size_t k : ParameterOrder(result)) {
    const ParameterEstimate& p = result.parameters[k];
    std::string status = p.free ? "free" : p.tied_to.empty() ? "fixed" : "tied to " + p.tied_to;
    if (!p.determined) status += std::string(" ") + kNotDetermined;
    // A parameter tied to a free one shares its errors and interval.
    const bool errors = p.free || std::isfinite(p.std_error);
    table.rows.push_back(
        {p.name, p.unit, Num(p.value), errors ? Num(p.std_error) : "-",
         errors ? "[" + Num(p.ci95_low) + ", " + Num(p.ci95_high) + "]" : "-",
         Num(p.initial), status});
  }
  return table;
}

TextTable FitTable(const FitResult& result) {
  TextTable table;
  table.headers = {"experiment", "role",    "channel", "unit",
                   "fitted",     "rms",     "fit %",   "max error",
                   "rel. err %", "LB p",    "xcorr u", "lag"};
  table.right = {false, false, false, false, false, true,
                 true,  true,  true,  true,  true,  true};
  for (const ExperimentFit& e : result.experiments) {
    for (const ChannelFit& c : e.channels) {
      table.rows.push_back(
          {e.name, e.role, c.channel, c.unit, c.fitted ? "yes" : "no",
           Num(c.rms, 4), Num(c.fit_percent, 4), Num(c.max_error, 4),
           Num(c.relative_error_percent, 4),
           Num(c.ljung_box_p, 3) + " (" + std::to_string(c.ljung_box_lags) + ")",
           Num(c.input_xcorr_peak, 3), std::to_string(c.input_xcorr_lag)});
    }
  }
  return table;
}

// The name of free parameter i of the correlation matrix.
std::string CorrelationName(const FitResult& result, Eigen::Index i) {
  if (i < static_cast<Eigen::Index>(result.free_names.size())) {
    return result.free_names[static_cast<size_t>(i)];
  }
  return "#" + std::to_string(i + 1);
}

// ---------------------------------------------------------------- CSV

// A CSV cell: quoted (quotes doubled) if it has a comma, quote, line break
// or leading/trailing blank.
std::string CsvCell(const std::string& s) {
  const bool quote =
      s.find_first_of(",\"\r\n") != std::string::npos ||
      (!s.empty() && (s.front() == ' ' || s.front() == '\t' ||
                      s.back() == ' ' || s.back() == '\t'));
  if (!quote) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

// ---------------------------------------------------------------- gnuplot

// `s` as a gnuplot single-quoted string: quotes doubled, control characters
// replaced by spaces (callers reject line breaks in paths beforehand).
std::string GnuplotString(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') {
      out += "''";
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += ' ';
    } else {
      out += c;
    }
  }
  return out + "'";
}

std::string WithUnit(const std::string& text, const std::string& unit) {
  return unit.empty() ? text : text + " [" + unit + "]";
}

bool AnyFinite(const std::vector<double>& x) {
  for (double v : x) {
    if (std::isfinite(v)) return true;
  }
  return false;
}

// Whether simulated − measured is finite at some sample.
bool AnyFiniteDifference(const ChannelFit& c) {
  for (size_t k = 0; k < c.measured.size() && k < c.simulated.size(); ++k) {
    if (std::isfinite(c.simulated[k] - c.measured[k])) return true;
  }
  return false;
}

// The gnuplot commands (joined by "; " for -e) that draw `fit` from the CSV
// `csv_path` into the PNG `output`. A series with no finite value is left
// out (gnuplot refuses to plot it); a panel with none is drawn empty with
// the note "no finite values".
// `svg`: gnuplot's svg terminal (scalable, no fixed size: `dynamic`; no
// `mouse`, which would load gnuplot_svg.js), else PNG.
std::string PlotScript(const std::string& output, const std::string& csv_path,
                       const ExperimentFit& fit, bool svg = false) {
  const size_t n = fit.channels.size();
  std::vector<std::string> cmd;
  if (svg) {
    const int height = static_cast<int>(std::max<size_t>(320, 270 * n + 40));
    cmd.push_back("set terminal svg size 1000," + std::to_string(height) +
                  " dynamic noenhanced font 'sans,12' background rgb 'white'");
  } else {
    const int width = 1400;
    const int height = static_cast<int>(std::max<size_t>(400, 300 * n));
    const std::string size = " size " + std::to_string(width) + "," +
                             std::to_string(height);
    cmd.push_back(
        "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) { set terminal pngcairo "
        "noenhanced" + size + " font ',9' } else { set terminal png noenhanced" +
        size + " }");
  }
  cmd.push_back("set output " + GnuplotString(output));
  cmd.push_back("set datafile separator ','");
  cmd.push_back("set grid");
  // SVG: the key below the panel, where it hides no trace.
  cmd.push_back(svg ? "set key below" : "set key top right");
  cmd.push_back("set multiplot layout " + std::to_string(n) + ",2 title " +
                GnuplotString(fit.name + " (" + fit.role + ")"));
  const std::string data = GnuplotString(csv_path) + " skip 1";
  // One panel: the series (column, title, line width) with finite values.
  struct Series {
    size_t column;
    const char* title;
    const char* style;  // line width and colour
    bool finite;
  };
  auto panel = [&](const std::vector<Series>& series) {
    std::string plot;
    for (const Series& s : series) {
      if (!s.finite) continue;
      plot += (plot.empty() ? "plot " : ", ") + data + " using 1:" +
              std::to_string(s.column) + " with lines " + s.style +
              " title '" + s.title + "'";
    }
    if (plot.empty()) {
      cmd.push_back("set label 1 'no finite values' at graph 0.5,0.5 center");
      cmd.push_back("plot [0:1] [0:1] -1 notitle");
      cmd.push_back("unset label 1");
    } else {
      cmd.push_back(plot);
    }
  };
  for (size_t j = 0; j < n; ++j) {
    const ChannelFit& c = fit.channels[j];
    const std::string name = WithUnit(fit.name + ": " + c.channel, c.unit);
    cmd.push_back(j + 1 == n ? "set xlabel 't [s]'" : "unset xlabel");
    cmd.push_back("set title " + GnuplotString(name + ", measured and simulated"));
    cmd.push_back("set ylabel " + GnuplotString(WithUnit(c.channel, c.unit)));
    // Measured broad and light underneath, simulated narrow and dark on
    // top: both stay visible where they agree.
    panel({{2 + 3 * j, "measured", "lw 2.5 lc rgb '#8fb8de'", AnyFinite(c.measured)},
           {3 + 3 * j, "simulated", "lw 1.2 lc rgb '#c0392b'", AnyFinite(c.simulated)}});
    cmd.push_back("set title " +
                  GnuplotString(name + ", residual (simulated - measured)"));
    cmd.push_back("set ylabel " +
                  GnuplotString(WithUnit(c.channel + " residual", c.unit)));
    panel({{4 + 3 * j, "residual", "lw 1 lc rgb '#4d4d4d'", AnyFiniteDifference(c)}});
  }
  cmd.push_back("unset multiplot");
  cmd.push_back("unset output");
  std::string script;
  for (const std::string& c : cmd) script += (script.empty() ? "" : "; ") + c;
  return script;
}

}  // namespace

std::string FormatBootstrap(const FitResult& result) {
  if (result.bootstrap_replicates <= 0) return "";
  std::string out = "residual bootstrap, " + std::to_string(result.bootstrap_replicates) +
                    " refits from the estimate (std errors: reported (" +
                    result.uncertainty_method + "), Gauss–Newton, bootstrap; bootstrap 95 %):\n";
  for (const ParameterEstimate& p : result.parameters) {
    if (!p.free) continue;
    out += "  " + p.name + ": " + Num(p.std_error) + ", " + Num(p.std_error_gauss_newton) +
           ", " + Num(p.std_error_bootstrap) + "; [" + Num(p.bootstrap_low) + ", " +
           Num(p.bootstrap_high) + "] " + p.unit + "\n";
  }
  return out;
}

std::string FormatParameterTable(const FitResult& result) {
  return RenderText(ParameterTable(result));
}

std::string FormatFitTable(const FitResult& result) {
  return RenderText(FitTable(result));
}

std::string FormatStartCosts(const FitResult& result) {
  if (result.start_costs.empty()) return "none";
  std::string out;
  for (size_t k = 0; k < result.start_costs.size(); ++k) {
    if (k > 0) out += ", ";
    if (k < result.start_joined.size() && result.start_joined[k] >= 0) {
      out += "joined start " + std::to_string(result.start_joined[k]) + " after " +
             Num(result.start_joined_horizon[k], 4) + " s";
    } else if (std::isnan(result.start_costs[k]) && k < result.start_screen_costs.size()) {
      out += "not continued (" + Num(result.start_screen_costs[k], 10) + " on the first " +
             Num(result.screen_horizon, 4) + " s)";
    } else {
      out += Num(result.start_costs[k], 10);
    }
  }
  return out;
}

std::string FormatPhases(const FitResult& result) {
  double total = 0.0;
  for (const FitPhase& f : result.phases) total += f.seconds;
  std::ostringstream out;
  out << std::setprecision(3) << "time: " << total << " s (";
  for (size_t k = 0; k < result.phases.size(); ++k) {
    const FitPhase& f = result.phases[k];
    out << (k == 0 ? "" : ", ") << f.name << " " << f.seconds << " s: "
        << f.simulations << " simulations, " << f.jacobians << " Jacobians";
  }
  out << ")";
  return out.str();
}

std::vector<std::string> ExperimentFileStems(const FitResult& result) {
  std::vector<std::string> stems;
  std::set<std::string> used;
  for (size_t i = 0; i < result.experiments.size(); ++i) {
    std::string name = result.experiments[i].name;
    for (char& c : name) {
      const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                      (c >= '0' && c <= '9') || c == '.' || c == '-' ||
                      c == '_';
      if (!ok) c = '_';
    }
    if (name.empty()) name = "experiment" + std::to_string(i + 1);
    std::string stem = "fit_" + name;
    for (int n = 2; used.count(stem) != 0; ++n) {
      stem = "fit_" + name + "_" + std::to_string(n);
    }
    used.insert(stem);
    stems.push_back(stem);
  }
  return stems;
}

void WriteParamsCsv(const std::string& path, const FitResult& result) {
  std::string out = "name,unit,value,std_error,ci95_low,ci95_high,initial,free\n";
  for (size_t k : ParameterOrder(result)) {
    const ParameterEstimate& p = result.parameters[k];
    out += CsvCell(p.name) + "," + CsvCell(p.unit) + "," + Exact(p.value) + ",";
    // A parameter tied to another carries its source's errors where that
    // is free; its `free` cell says "tied to <source>".
    if (p.free || std::isfinite(p.std_error)) {
      out += Exact(p.std_error) + "," + Exact(p.ci95_low) + "," +
             Exact(p.ci95_high);
    } else {
      out += ",,";
    }
    const std::string status =
        p.free ? "free" : p.tied_to.empty() ? "fixed" : "tied to " + p.tied_to;
    out += "," + Exact(p.initial) + "," + CsvCell(status) + "\n";
  }
  WriteFileAtomic(path, out);
}

void WriteParamsMarkdown(const std::string& path, const FitResult& result,
                         const std::string& title, const ReportSections& extra) {
  std::string out = "# " + OneLine(title.empty() ? "Fit report" : title) + "\n\n";

  out += "## Parameters\n\n";
  if (result.parameters.empty()) {
    out += "No parameters.\n\n";
  } else {
    out += RenderMarkdown(ParameterTable(result)) + "\n";
    out += "Std errors from the covariance scaled by the residual variance; "
           "95 % interval value ± t(0.975, m − n)·std error.\n\n";
  }

  out += "## Correlation of the free parameters\n\n";
  const Eigen::MatrixXd& r = result.correlation;
  if (r.rows() == 0 || r.cols() == 0) {
    out += "No free parameters.\n\n";
  } else {
    TextTable table;
    table.headers.push_back("");
    table.right.push_back(false);
    for (Eigen::Index j = 0; j < r.cols(); ++j) {
      table.headers.push_back(CorrelationName(result, j));
      table.right.push_back(true);
    }
    for (Eigen::Index i = 0; i < r.rows(); ++i) {
      std::vector<std::string> row = {CorrelationName(result, i)};
      for (Eigen::Index j = 0; j < r.cols(); ++j) {
        if (!std::isfinite(r(i, j))) {
          row.push_back(Num(r(i, j)));
        } else {
          char buf[32];
          std::snprintf(buf, sizeof(buf), "%.3f", r(i, j));
          row.push_back(buf);
        }
      }
      table.rows.push_back(row);
    }
    out += RenderMarkdown(table) + "\n";
  }

  out += "## Not determined by the data\n\n";
  if (result.undetermined.empty()) {
    out += "none\n\n";
  } else {
    for (const std::string& name : result.undetermined) {
      out += "- " + OneLine(name) + "\n";
    }
    out += "\n";
  }

  out += "## Fit\n\n";
  if (result.experiments.empty()) {
    out += "No experiments.\n\n";
  } else {
    out += RenderMarkdown(FitTable(result)) + "\n";
    out += "rms and max error in the channel unit; fit % = 100·(1 − ‖y − ŷ‖/"
           "‖y − mean(y)‖); rel. err % = 100·‖ŷ − y‖/‖y‖; LB p: Ljung–Box "
           "p-value of the residual (lags); xcorr u: peak normalised "
           "cross-correlation of the residual with the input u, at lag "
           "samples (> 0: the residual follows u).\n\n";
  }

  out += "## Solver\n\n";
  out += "- cost (½Σr²): initial " + Num(result.initial_cost, 10) + ", final " +
         Num(result.final_cost, 10) + "\n";
  out += std::string("- converged: ") + (result.converged ? "yes" : "no") + "\n";
  out += "- final cost of each start: " + FormatStartCosts(result) + "\n";
  out += "- AIC: " + Num(result.aic, 10) + ", BIC: " + Num(result.bic, 10) + "\n";
  out += "- residuals: " + std::to_string(result.num_residuals) +
         ", residual variance: " + Num(result.residual_variance, 6) + "\n";
  out += "- iterations: " + std::to_string(result.iterations) +
         ", simulations: " + std::to_string(result.simulations) +
         ", Jacobian evaluations: " +
         std::to_string(result.jacobian_evaluations) + "\n";
  out += "- " + FormatPhases(result) + "\n";
  out += "- termination: " +
         (result.termination.empty() ? std::string("-")
                                     : OneLine(result.termination)) +
         "\n";
  if (!result.stop_note.empty()) out += "- note: " + result.stop_note + "\n";
  if (!result.model_note.empty()) out += "- note: " + result.model_note + "\n";
  if (!result.auto_starts_note.empty()) out += "- starts: " + result.auto_starts_note + "\n";
  if (!result.sample_sigma_note.empty()) out += "- weights: " + result.sample_sigma_note + "\n";
  if (!result.residual_note.empty()) out += "- warning: " + result.residual_note + "\n";
  if (!result.misspecification_note.empty()) {
    out += "- misspecification: " + result.misspecification_note + "\n";
  }
  if (!result.integration.empty()) out += "- integration: " + result.integration + "\n";
  out += "- " + (result.optimum_check.empty() ? std::string("optimum not checked")
                                             : result.optimum_check) +
         "\n";
  out += "- uncertainty (" +
         (result.uncertainty_method.empty() ? std::string("-") : result.uncertainty_method) +
         "): " + result.uncertainty_note + "\n";
  const std::string bootstrap = FormatBootstrap(result);
  if (!bootstrap.empty()) out += "- " + bootstrap;
  out += extra.markdown;
  WriteFileAtomic(path, out);
}

namespace {

// ---------------------------------------------------------------- report.json sections

// "parameters": free ones first (ParameterOrder).
Json ParameterJson(const FitResult& result, const ParameterEstimate& p) {
  Json e = Json::object();
  e["name"] = p.name;
  e["unit"] = p.unit;
  e["value"] = JsonNumber<Json>(p.value);
  // A parameter tied to another (ParameterEstimate::tied_to) carries the
  // errors of its source where that is free.
  const bool errors = p.free || !p.tied_to.empty();
  e["std_error"] = errors ? JsonNumber<Json>(p.std_error) : Json(nullptr);
  e["ci95_low"] = errors ? JsonNumber<Json>(p.ci95_low) : Json(nullptr);
  e["ci95_high"] = errors ? JsonNumber<Json>(p.ci95_high) : Json(nullptr);
  e["std_error_gauss_newton"] =
      errors ? JsonNumber<Json>(p.std_error_gauss_newton) : Json(nullptr);
  e["interval_method"] = errors ? Json(p.interval_method) : Json(nullptr);
  if (errors && !result.misspecification_note.empty()) {
    e["std_error_sandwich"] = JsonNumber<Json>(p.std_error_sandwich);
  }
  if (!p.tied_to.empty()) e["tied_to"] = p.tied_to;
  if (errors && result.bootstrap_replicates > 0) {
    e["bootstrap"] = {{"std_error", JsonNumber<Json>(p.std_error_bootstrap)},
                      {"low", JsonNumber<Json>(p.bootstrap_low)},
                      {"high", JsonNumber<Json>(p.bootstrap_high)}};
  }
  e["initial"] = JsonNumber<Json>(p.initial);
  e["free"] = p.free;
  e["determined"] = p.determined;
  return e;
}

Json ParametersJson(const FitResult& result) {
  Json parameters = Json::array();
  for (size_t k : ParameterOrder(result)) {
    parameters.push_back(ParameterJson(result, result.parameters[k]));
  }
  return parameters;
}

// "experiments": each with its CSV's name and its channels.
Json ChannelJson(const ChannelFit& c) {
  Json ch = Json::object();
  ch["channel"] = c.channel;
  ch["unit"] = c.unit;
  ch["rms"] = JsonNumber<Json>(c.rms);
  ch["fit_percent"] = JsonNumber<Json>(c.fit_percent);
  ch["max_error"] = JsonNumber<Json>(c.max_error);
  ch["mae"] = JsonNumber<Json>(c.mae);
  ch["relative_error_percent"] = JsonNumber<Json>(c.relative_error_percent);
  ch["ljung_box_q"] = JsonNumber<Json>(c.ljung_box_q);
  ch["ljung_box_lags"] = c.ljung_box_lags;
  ch["ljung_box_p"] = JsonNumber<Json>(c.ljung_box_p);
  ch["input_xcorr_peak"] = JsonNumber<Json>(c.input_xcorr_peak);
  ch["input_xcorr_lag"] = c.input_xcorr_lag;
  ch["sigma"] = JsonNumber<Json>(c.sigma);
  ch["fitted"] = c.fitted;
  return ch;
}

Json ExperimentsJson(const FitResult& result) {
  const std::vector<std::string> stems = ExperimentFileStems(result);
  Json experiments = Json::array();
  for (size_t i = 0; i < result.experiments.size(); ++i) {
    const ExperimentFit& x = result.experiments[i];
    Json e = Json::object();
    e["name"] = x.name;
    e["role"] = x.role;
    e["csv"] = stems[i] + ".csv";
    Json channels = Json::array();
    for (const ChannelFit& c : x.channels) channels.push_back(ChannelJson(c));
    e["channels"] = channels;
    experiments.push_back(e);
  }
  return experiments;
}

// "cost", "converged" and the starts: "starts", "start_screen_costs",
// "start_joined", "start_joined_horizon", "screen_horizon".
void AddCostAndStarts(const FitResult& result, Json* out) {
  Json& j = *out;
  j["cost"] = {{"initial", JsonNumber<Json>(result.initial_cost)},
               {"final", JsonNumber<Json>(result.final_cost)}};
  j["converged"] = result.converged;
  Json starts = Json::array();
  for (double c : result.start_costs) starts.push_back(JsonNumber<Json>(c));
  j["starts"] = starts;
  Json screen = Json::array();
  for (double c : result.start_screen_costs) screen.push_back(JsonNumber<Json>(c));
  j["start_screen_costs"] = screen;
  j["start_joined"] = result.start_joined;
  Json joined_horizon = Json::array();
  for (double h : result.start_joined_horizon) joined_horizon.push_back(JsonNumber<Json>(h));
  j["start_joined_horizon"] = joined_horizon;
  j["screen_horizon"] = JsonNumber<Json>(result.screen_horizon);
}

// The fit's figures and notes, "aic" to "integration".
void AddFigures(const FitResult& result, Json* out) {
  Json& j = *out;
  j["aic"] = JsonNumber<Json>(result.aic);
  j["bic"] = JsonNumber<Json>(result.bic);
  j["num_residuals"] = result.num_residuals;
  j["residual_variance"] = JsonNumber<Json>(result.residual_variance);
  j["iterations"] = result.iterations;
  j["simulations"] = result.simulations;
  j["jacobian_evaluations"] = result.jacobian_evaluations;
  j["termination"] = result.termination;
  j["stop_note"] = result.stop_note;
  j["model_note"] = result.model_note;
  j["auto_starts_note"] = result.auto_starts_note;
  j["sample_sigma_note"] = result.sample_sigma_note;
  j["residual_note"] = result.residual_note;
  j["integration"] = result.integration;
}

// "phases", "uncertainty" and "optimum".
void AddPhasesAndChecks(const FitResult& result, Json* out) {
  Json& j = *out;
  Json phases = Json::array();
  for (const FitPhase& f : result.phases) {
    phases.push_back({{"name", f.name},
                      {"seconds", JsonNumber<Json>(f.seconds)},
                      {"simulations", f.simulations},
                      {"jacobians", f.jacobians}});
  }
  j["phases"] = phases;
  j["uncertainty"] = {{"method", result.uncertainty_method},
                      {"note", result.uncertainty_note},
                      {"misspecification", result.misspecification_note},
                      {"bootstrap_replicates", result.bootstrap_replicates}};
  j["optimum"] = {{"verified", result.optimum_verified},
                  {"check", result.optimum_check},
                  {"probe_rounds", result.probe_rounds},
                  {"probe_decrease", JsonNumber<Json>(result.probe_decrease)},
                  {"local_starts", result.local_starts},
                  {"local_decrease", JsonNumber<Json>(result.local_decrease)}};
}

// "correlation": {"names", "matrix"}.
void AddCorrelation(const FitResult& result, Json* out) {
  Json& j = *out;
  const Eigen::MatrixXd& r = result.correlation;
  Json names = Json::array();
  for (Eigen::Index i = 0; i < r.rows(); ++i) {
    names.push_back(CorrelationName(result, i));
  }
  Json matrix = Json::array();
  for (Eigen::Index i = 0; i < r.rows(); ++i) {
    Json row = Json::array();
    for (Eigen::Index k = 0; k < r.cols(); ++k) row.push_back(JsonNumber<Json>(r(i, k)));
    matrix.push_back(row);
  }
  j["correlation"] = {{"names", names}, {"matrix", matrix}};
}

}  // namespace

nlohmann::ordered_json ReportJson(const FitResult& result, const ReportSections& extra) {
  Json j = Json::object();
  j["parameters"] = ParametersJson(result);
  j["experiments"] = ExperimentsJson(result);
  AddCostAndStarts(result, &j);
  AddFigures(result, &j);
  AddPhasesAndChecks(result, &j);
  AddCorrelation(result, &j);
  j["undetermined"] = result.undetermined;
  for (const auto& [key, value] : extra.json.items()) j[key] = value;
  return j;
}

void WriteReportJson(const std::string& path, const FitResult& result,
                     const ReportSections& extra) {
  WriteFileAtomic(path, ReportJson(result, extra).dump(2, ' ', false,
                                                       Json::error_handler_t::replace) +
                            "\n");
}

void WriteExperimentCsv(const std::string& path, const ExperimentFit& fit) {
  const size_t rows = fit.t.size();
  for (const ChannelFit& c : fit.channels) {
    if (c.measured.size() != rows || c.simulated.size() != rows) {
      throw std::invalid_argument(
          path + ": expected " + std::to_string(rows) +
          " samples (the length of t) in the measured and simulated channel '" +
          c.channel + "' of experiment '" + fit.name + "', got " +
          std::to_string(c.measured.size()) + " and " +
          std::to_string(c.simulated.size()));
    }
  }
  std::string out = "t";
  for (const ChannelFit& c : fit.channels) {
    out += "," + CsvCell(c.channel + "_measured") + "," +
           CsvCell(c.channel + "_simulated") + "," +
           CsvCell(c.channel + "_residual");
  }
  out += "\n";
  out.reserve(out.size() + rows * (1 + 3 * fit.channels.size()) * 20);
  for (size_t k = 0; k < rows; ++k) {
    out += Num(fit.t[k], 12);
    for (const ChannelFit& c : fit.channels) {
      out += "," + Num(c.measured[k], 12) + "," + Num(c.simulated[k], 12) +
             "," + Num(c.simulated[k] - c.measured[k], 12);
    }
    out += "\n";
  }
  WriteFileAtomic(path, out);
}

bool RenderExperimentSvg(const std::string& csv_path, const ExperimentFit& fit,
                         const std::string& id_prefix, std::string* svg,
                         std::string* warning) {
  std::string ignored;
  if (warning == nullptr) warning = &ignored;
  if (fit.channels.empty() || fit.t.empty()) {
    *warning = "nothing to plot (no channels or no samples): no plot for " + fit.name;
    return false;
  }
  if (HasLineBreak(csv_path)) {
    *warning = "a path contains a line break: no plot for " + fit.name;
    return false;
  }
  return RenderGnuplotSvg(
      fs::path(csv_path).parent_path().string(),
      [&](const std::string& temp) { return PlotScript(temp, csv_path, fit, true); },
      fit.name, id_prefix, svg, warning);
}

bool WriteExperimentPlot(const std::string& png_path,
                         const std::string& csv_path, const ExperimentFit& fit,
                         std::string* warning) {
  std::string ignored;
  if (warning == nullptr) warning = &ignored;
  if (fit.channels.empty() || fit.t.empty()) {
    *warning = "nothing to plot (no channels or no samples): no plot written "
               "for " + fit.name;
    return false;
  }
  if (HasLineBreak(csv_path)) {
    *warning = "a path contains a line break: no plot written for " + fit.name;
    return false;
  }
  return RenderGnuplotPng(
      png_path,
      [&](const std::string& temp) { return PlotScript(temp, csv_path, fit); },
      fit.name, warning);
}

void WriteFitOutputs(const std::string& dir, const FitResult& result,
                     const std::string& title,
                     std::vector<std::string>* warnings,
                     const ReportSections& extra) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    throw std::runtime_error(
        dir + ": cannot create the output directory: " +
        (ec ? ec.message() : std::string("exists and is not a directory")));
  }
  const fs::path base(dir);
  WriteParamsCsv((base / "params.csv").string(), result);
  WriteParamsMarkdown((base / "params.md").string(), result, title, extra);
  WriteReportJson((base / "report.json").string(), result, extra);
  const std::vector<std::string> stems = ExperimentFileStems(result);
  // One gnuplot per experiment, several at once (each writes its own files),
  // the warnings in experiment order. A PNG is the longest plot a run draws
  // (a 1400-pixel cairo raster: 0.3–0.4 s of CPU against 0.05–0.1 s for one
  // of report.html's SVGs, which WriteJobRun draws at the same time): up to
  // twice the cores start at once, so that they share the cores with the
  // SVGs rather than the last of them starting when everything else has
  // finished (the paper job's three: writing 1.2 → 0.9 s on 2 cores).
  std::vector<std::string> plot_warnings(result.experiments.size());
  const int plots_at_once = static_cast<int>(std::min<size_t>(
      std::max<size_t>(result.experiments.size(), 1), 2 * static_cast<size_t>(ProcessThreads())));
  ForEachConcurrently(result.experiments.size(), plots_at_once, [&](size_t i) {
    const std::string csv = (base / (stems[i] + ".csv")).string();
    const std::string png = (base / (stems[i] + ".png")).string();
    WriteExperimentCsv(csv, result.experiments[i]);
    if (WriteExperimentPlot(png, csv, result.experiments[i], &plot_warnings[i])) {
      plot_warnings[i].clear();
    }
  });
  for (const std::string& warning : plot_warnings) {
    if (!warning.empty() && warnings != nullptr) warnings->push_back(warning);
  }
}

}  // namespace axis
