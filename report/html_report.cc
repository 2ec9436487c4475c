#include "report/html_report.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "common/concurrency.h"
#include "common/format.h"
#include "common/gnuplot.h"
#include "design/experiment_design.h"
#include "discovery/diagnostics.h"
#include "discovery/discovery.h"
#include "discovery/force_map.h"
#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"
#include "report/published.h"
#include "report/report.h"
#include "report/tuning_report.h"
#include "sim/channels.h"
#include "io/csv.h"

namespace axis {
namespace {

namespace fs = std::filesystem;

// Samples kept per plotted trace at most (about; RenderHtmlReport).
constexpr size_t kPlotRows = 2000;
// p-values below this are set in bold in the diagnostics tables.
constexpr double kBoldP = 1e-3;

// ------------------------------------------------------------- text

// "%.*g"; "—" for NaN (not applicable or not computed), "inf"/"-inf".
std::string Number(double value, int digits = 6) {
  return FormatNumber(value, digits, "—");
}

std::string Interval(double low, double high) {
  return "[" + Number(low) + ", " + Number(high) + "]";
}

// Escaped text in an element: Tag("td", "a<b") = "<td>a&lt;b</td>".
std::string Tag(const std::string& tag, const std::string& text,
                const std::string& attributes = "") {
  return "<" + tag + (attributes.empty() ? "" : " " + attributes) + ">" + HtmlEscape(text) +
         "</" + tag + ">";
}

// An HTML id from a name: letters, digits, '-' and '_' kept, others '_'.
std::string Anchor(const std::string& prefix, const std::string& name) {
  std::string out = prefix;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                    (c >= '0' && c <= '9') || c == '-' || c == '_';
    out += ok ? c : '_';
  }
  return out;
}

// ------------------------------------------------------------- tables

using Cell = HtmlCell;
using Table = HtmlTable;

// A cell of ready HTML.
Cell Html(const std::string& html) {
  Cell c;
  c.html = html;
  return c;
}
Cell Text(const std::string& text) { return HtmlTextCell(text); }
Cell Num(double value, int digits = 6) { return HtmlNumberCell(value, digits); }
// A number with its unit, right-aligned, on one line.
Cell NumUnit(double value, int digits, const std::string& unit) {
  Cell c = Num(value, digits);
  c.html += " " + HtmlEscape(unit);
  return c;
}
// A p-value, bold below kBoldP.
Cell PValue(double p) {
  Cell c = Num(p, 3);
  if (p < kBoldP) c.html = "<strong>" + c.html + "</strong>";
  return c;
}

std::string Render(const Table& table) { return RenderHtmlTable(table); }

// ------------------------------------------------------------- plots

// Indices of the samples kept for plotting `fit`: all if at most kPlotRows,
// else in each of about kPlotRows/(1 + 2·series) equal stretches the first
// sample and the samples where each series (measured, simulated, residual
// of every channel) is smallest and largest.
std::vector<size_t> PlotSamples(const ExperimentFit& fit) {
  const size_t n = fit.t.size();
  std::vector<size_t> keep;
  const size_t series = 3 * fit.channels.size();
  if (n <= kPlotRows || series == 0) {
    for (size_t k = 0; k < n; ++k) keep.push_back(k);
    return keep;
  }
  const size_t stretches = std::max<size_t>(1, kPlotRows / (1 + 2 * series));
  for (size_t s = 0; s < stretches; ++s) {
    const size_t begin = s * n / stretches;
    const size_t end = (s + 1) * n / stretches;
    if (begin >= end) continue;
    keep.push_back(begin);
    for (const ChannelFit& c : fit.channels) {
      for (int which = 0; which < 3; ++which) {
        size_t low = begin, high = begin;
        double low_value = std::numeric_limits<double>::infinity();
        double high_value = -low_value;
        for (size_t k = begin; k < end; ++k) {
          const double v = which == 0   ? c.measured[k]
                           : which == 1 ? c.simulated[k]
                                        : c.simulated[k] - c.measured[k];
          if (!std::isfinite(v)) continue;
          if (v < low_value) low_value = v, low = k;
          if (v > high_value) high_value = v, high = k;
        }
        keep.push_back(low);
        keep.push_back(high);
      }
    }
  }
  std::sort(keep.begin(), keep.end());
  keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
  return keep;
}

// `fit` with only the samples PlotSamples keeps.
ExperimentFit Thinned(const ExperimentFit& fit) {
  const std::vector<size_t> keep = PlotSamples(fit);
  if (keep.size() == fit.t.size()) return fit;
  ExperimentFit out = fit;
  out.t.clear();
  for (size_t k : keep) out.t.push_back(fit.t[k]);
  for (size_t j = 0; j < fit.channels.size(); ++j) {
    out.channels[j].measured.clear();
    out.channels[j].simulated.clear();
    for (size_t k : keep) {
      out.channels[j].measured.push_back(fit.channels[j].measured[k]);
      out.channels[j].simulated.push_back(fit.channels[j].simulated[k]);
    }
  }
  return out;
}

// Draws the page's plots, numbering their ids, and notes what failed. Each
// figure is first a placeholder (an HTML comment, which no escaped text can
// contain) and its gnuplot run a task; Draw runs the tasks several at once
// (ProcessThreads: a plot of a long record takes 0.1–0.2 s) and puts each
// figure in its placeholder's place, the warnings in the order of the calls.
class Plotter {
 public:
  Plotter(const std::string& scratch_dir, std::vector<std::string>* warnings)
      : scratch_dir_(scratch_dir), warnings_(warnings) {}

  // A <figure> with the SVG of `fit`, or a note that it could not be drawn.
  std::string Experiment(const ExperimentFit& fit) {
    const auto thinned = std::make_shared<const ExperimentFit>(Thinned(fit));
    std::string caption = fit.name + " (" + fit.role + "): left the measured and simulated " +
                          "channels against time, right the residual (simulated − measured), " +
                          "channel units on the axes";
    if (thinned->t.size() < fit.t.size()) {
      caption += "; " + std::to_string(thinned->t.size()) + " of " +
                 std::to_string(fit.t.size()) +
                 " samples drawn (each stretch's extremes kept; every sample is in the CSV)";
    }
    return Later(
        caption + ".", [thinned](const std::string& csv) { WriteExperimentCsv(csv, *thinned); },
        [thinned](const std::string& csv, const std::string& prefix, std::string* svg,
                  std::string* warning) {
          return RenderExperimentSvg(csv, *thinned, prefix, svg, warning);
        });
  }

  // A <figure> with the binned mean residuals of `d`.
  std::string Diagnostics(const ChannelDiagnostics& d) {
    return Later(d.experiment + "/" + d.channel + ": mean residual (" + d.unit +
                     ") in bins of velocity, position, acceleration and motor angle "
                     "modulo one revolution, ±1 standard error.",
                 [&d](const std::string& csv) { WriteDiagnosticsCsv(csv, d); },
                 Gnuplot(d.experiment + " " + d.channel + " diagnostics",
                         [&d](const std::string& csv, const std::string& output) {
                           return DiagnosticsPlotScript(d, csv, output, true);
                         }));
  }

  // A <figure> with the Bode plot of channel `c` of `r`.
  std::string Bode(const ExperimentFrequencyResponse& r, const ChannelFrequencyResponse& c) {
    return Later(r.experiment + ": " + r.input + " to " + c.channel +
                     ": magnitude (dB), phase (deg) and coherence of the H1 estimate of the "
                     "data (points) and of the model at the estimate simulated on the same "
                     "input (line)" +
                     (c.linear.empty() ? std::string() : ", and the linear model (dashed)") +
                     ", over the input's band.",
                 [&r, &c](const std::string& csv) { WriteFrequencyResponseCsv(csv, r, c); },
                 Gnuplot(r.experiment + " " + c.channel + " frequency response",
                         [&r, &c](const std::string& csv, const std::string& output) {
                           return BodePlotScript(r, c, csv, output, true);
                         }));
  }

  // A <figure> with the learned force of `map` and its band.
  std::string ForceMap(const ForceMapReport& map) {
    const std::string what =
        map.rotary ? "The learned load torque (N*m)" : "The learned load force (N)";
    return Later(what + " with its pointwise 95 % band (Bayesian, of the penalised fit).",
                 [&map](const std::string& csv) { WriteForceMapCsv(csv, map); },
                 Gnuplot("force map", [&map](const std::string& csv, const std::string& output) {
                   return ForceMapPlotScript(map, csv, output, true);
                 }));
  }

  // A <figure> with the step of the analog tuning `t` (current, proposed,
  // the proposal's band).
  std::string TuningStep(const AnalogLoopTuning& t) {
    return Later("The step of the tuning: velocity and motor current of the current and the "
                 "proposed setting, the proposal's band over the fit's interval ends.",
                 [&t](const std::string& csv) { WriteTuneStepCsv(csv, t); },
                 Gnuplot("tuning step", [](const std::string& csv, const std::string& output) {
                   return TuneStepPlotScript(csv, output);
                 }));
  }

  // A <figure> with the move of the move tuning `t`.
  std::string TuningMove(const MoveTuning& t) {
    return Later("The move: position (with the proposal's reference, dashed) and motor "
                 "current of the current and the proposed setting, the proposal's band over "
                 "the fit's interval ends.",
                 [&t](const std::string& csv) { WriteTuneMoveCsv(csv, t); },
                 Gnuplot("tuning move", [](const std::string& csv, const std::string& output) {
                   return TuneMovePlotScript(csv, output);
                 }));
  }

  // Draws every figure asked for and replaces its placeholder in the
  // sections' bodies. The objects the calls were given must still exist.
  void Draw(std::vector<HtmlSection>* sections) {
    std::vector<std::string> figures(plots_.size());
    std::vector<std::string> warnings(plots_.size());
    ForEachConcurrently(plots_.size(), ProcessThreads(), [&](size_t k) {
      std::string svg;
      const bool ok = plots_[k].draw(&svg, &warnings[k]);
      figures[k] = Figure(ok, svg, warnings[k], plots_[k].caption);
      if (ok) warnings[k].clear();
    });
    for (const std::string& w : warnings) {
      if (!w.empty() && warnings_ != nullptr) warnings_->push_back("report.html: " + w);
    }
    for (HtmlSection& section : *sections) {
      std::string& body = section.body;
      for (size_t at = body.find(kPlaceholder); at != std::string::npos;
           at = body.find(kPlaceholder, at)) {
        // Only Later writes the text: "<!--plot " index "-->".
        const size_t from = at + kPlaceholder.size();
        const size_t end = body.find("-->", from);
        const size_t k = std::stoul(body.substr(from, end - from));
        const std::string& figure = figures.at(k);
        body.replace(at, end + 3 - at, figure);
        at += figure.size();
      }
    }
    plots_.clear();
  }

 private:
  // Draws into *svg; false with *warning set if it could not.
  using DrawFn = std::function<bool(std::string* svg, std::string* warning)>;
  // Writes a figure's data to the scratch CSV `csv`.
  using WriteFn = std::function<void(const std::string& csv)>;
  // Draws that CSV into *svg, the plot's ids prefixed with `prefix`
  // (RenderGnuplotSvg); false with *warning set if it could not.
  using RenderFn = std::function<bool(const std::string& csv, const std::string& prefix,
                                      std::string* svg, std::string* warning)>;
  struct Plot {
    std::string caption;
    DrawFn draw;
  };
  static constexpr std::string_view kPlaceholder = "<!--plot ";

  // Queues a figure drawn from a scratch CSV (write, then render, then the
  // CSV removed) and returns its placeholder. The CSV's name and the ids'
  // prefix are numbered here, in call order.
  std::string Later(const std::string& caption, WriteFn write, RenderFn render) {
    const std::string csv = Scratch("csv");
    const std::string prefix = NextPrefix();
    plots_.push_back({caption, [csv, prefix, write = std::move(write),
                                render = std::move(render)](std::string* svg,
                                                            std::string* warning) {
                        write(csv);
                        const bool ok = render(csv, prefix, svg, warning);
                        std::error_code ec;
                        fs::remove(csv, ec);
                        return ok;
                      }});
    return std::string(kPlaceholder) + std::to_string(plots_.size() - 1) + "-->";
  }
  // Renders with the gnuplot commands script(csv, output) (RenderGnuplotSvg
  // in the scratch folder), `what` naming the plot in a warning.
  RenderFn Gnuplot(const std::string& what,
                   std::function<std::string(const std::string& csv, const std::string& output)>
                       script) const {
    return [dir = scratch_dir_, what, script = std::move(script)](
               const std::string& csv, const std::string& prefix, std::string* svg,
               std::string* warning) {
      return RenderGnuplotSvg(
          dir, [&](const std::string& output) { return script(csv, output); }, what, prefix, svg,
          warning);
    };
  }
  std::string Scratch(const char* extension) {
    return (fs::path(scratch_dir_) /
            (".report." + std::to_string(static_cast<long>(::getpid())) + "." +
             std::to_string(count_) + "." + extension))
        .string();
  }
  std::string NextPrefix() { return "p" + std::to_string(++count_) + "-"; }
  static std::string Figure(bool ok, const std::string& svg, const std::string& warning,
                            const std::string& caption) {
    if (!ok) {
      return "<figure class=\"missing\">" + Tag("p", "No plot: " + warning) +
             Tag("figcaption", caption) + "</figure>\n";
    }
    return "<figure>\n" + svg + "\n" + Tag("figcaption", caption) + "</figure>\n";
  }

  std::string scratch_dir_;
  std::vector<std::string>* warnings_;
  int count_ = 0;
  std::vector<Plot> plots_;
};

// ------------------------------------------------------------- page

constexpr const char* kStyle = R"(
body { font-family: "DejaVu Sans", "Helvetica Neue", Arial, sans-serif; font-size: 15px;
       line-height: 1.45; color: #1d1d1f; max-width: 1180px; margin: 0 auto; padding: 1em 1.5em 4em; }
h1 { font-size: 1.7em; margin-bottom: 0.2em; }
h2 { font-size: 1.3em; border-bottom: 2px solid #d0d4da; padding-bottom: 0.2em; margin-top: 2em; }
h3 { font-size: 1.08em; margin-top: 1.5em; }
nav { background: #f3f5f8; border: 1px solid #d9dee5; padding: 0.5em 1em; border-radius: 4px; }
nav a { margin-right: 1.1em; white-space: nowrap; }
a { color: #1a56a8; }
table { border-collapse: collapse; margin: 0.6em 0 1em; font-size: 0.92em; }
div.scroll { max-width: 100%; overflow-x: auto; }
th, td { border: 1px solid #d4d8de; padding: 0.25em 0.6em; text-align: left; vertical-align: top; }
th { background: #eef1f5; font-weight: 600; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
table.sortable th { cursor: pointer; }
table.sortable th[data-dir="asc"]::after { content: " \25B2"; }
table.sortable th[data-dir="desc"]::after { content: " \25BC"; }
table.heat td { text-align: center; min-width: 4.5em; font-variant-numeric: tabular-nums; }
figure { margin: 1em 0 2em; }
figure svg { width: 100%; height: auto; display: block; border: 1px solid #e1e4e8; }
figcaption { font-size: 0.88em; color: #555; margin-top: 0.3em; }
figure.missing p { color: #a33; }
.summary { display: grid; grid-template-columns: max-content 1fr; gap: 0.15em 1.2em;
           background: #f7f8fa; border: 1px solid #e1e4e8; padding: 0.8em 1em; border-radius: 4px; }
.summary dt { font-weight: 600; }
.summary dd { margin: 0; }
.verdict { font-weight: 700; padding: 0.1em 0.5em; border-radius: 3px; }
.explained { background: #dcf2e0; color: #17612b; }
.incomplete { background: #fde8cc; color: #8a4b00; }
.kept { color: #17612b; font-weight: 600; }
.rejected { color: #8a4b00; font-weight: 600; }
.note { color: #555; font-size: 0.9em; }
details { margin: 0.5em 0 1em; }
summary { cursor: pointer; color: #1a56a8; }
ul.remains li { margin-bottom: 0.2em; }
code, .mono { font-family: "DejaVu Sans Mono", monospace; font-size: 0.9em; }
)";

// Sorts a table.sortable by the clicked column (numbers by data-v or their
// value, text otherwise); a second click reverses.
constexpr const char* kScript = R"(
document.querySelectorAll('table.sortable th').forEach(function (th) {
  th.addEventListener('click', function () {
    var table = th.closest('table'), body = table.tBodies[0];
    var column = Array.prototype.indexOf.call(th.parentNode.children, th);
    var ascending = th.getAttribute('data-dir') !== 'asc';
    th.parentNode.querySelectorAll('th').forEach(function (h) { h.removeAttribute('data-dir'); });
    th.setAttribute('data-dir', ascending ? 'asc' : 'desc');
    var key = function (row) {
      var cell = row.cells[column];
      return cell ? (cell.getAttribute('data-v') || cell.textContent) : '';
    };
    Array.prototype.slice.call(body.rows).sort(function (a, b) {
      var x = key(a), y = key(b), nx = parseFloat(x), ny = parseFloat(y);
      var order = (!isNaN(nx) && !isNaN(ny)) ? nx - ny : x.localeCompare(y);
      return ascending ? order : -order;
    }).forEach(function (row) { body.appendChild(row); });
  });
});
)";

// Background colour of a correlation r: blue (−1) through white (0) to red
// (+1).
std::string HeatColour(double r) {
  if (!std::isfinite(r)) return "#dddddd";
  r = std::clamp(r, -1.0, 1.0);
  const int blue[3] = {33, 102, 172}, red[3] = {178, 24, 43};
  const int* end = r < 0.0 ? blue : red;
  const double f = std::abs(r);
  char buf[16];
  std::snprintf(buf, sizeof(buf), "#%02x%02x%02x",
                static_cast<int>(std::lround(255 + f * (end[0] - 255))),
                static_cast<int>(std::lround(255 + f * (end[1] - 255))),
                static_cast<int>(std::lround(255 + f * (end[2] - 255))));
  return buf;
}

const FreeParameter* FindFree(const EstimationProblem* job, const std::string& name) {
  if (job == nullptr) return nullptr;
  for (const FreeParameter& f : job->free) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

// The free (`free`) or the fixed parameters, in result order: value,
// standard error, 95 % interval, initial value, bounds (from the job),
// free/fixed ("—" where a fixed parameter has no such figure).
Table ParameterTable(const FitResult& result, const EstimationProblem* job, bool free) {
  Table t;
  t.sortable = true;
  t.headers = {"name",    "unit",        "value",       "std error", "95 % interval",
               "initial", "lower bound", "upper bound", "free/fixed"};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const ParameterEstimate& p : result.parameters) {
    if (p.free != free) continue;
    const FreeParameter* f = free ? FindFree(job, p.name) : nullptr;
    std::string status = free ? "free" : p.tied_to.empty() ? "fixed" : "tied to " + p.tied_to;
    if (!p.determined) status += " (not determined by the data)";
    // A parameter tied to a free one shares its errors and interval.
    const bool errors = free || std::isfinite(p.std_error);
    t.rows.push_back({Text(p.name), Text(p.unit), Num(p.value), Num(errors ? p.std_error : nan),
                      Text(errors ? Interval(p.ci95_low, p.ci95_high) : "—"), Num(p.initial),
                      Num(f != nullptr ? f->lower : nan), Num(f != nullptr ? f->upper : nan),
                      Text(status)});
  }
  return t;
}

std::string CorrelationHeatMap(const FitResult& result) {
  const Eigen::MatrixXd& r = result.correlation;
  if (r.rows() == 0) return Tag("p", "No free parameters.");
  const auto name = [&](Eigen::Index i) {
    return i < static_cast<Eigen::Index>(result.free_names.size())
               ? result.free_names[static_cast<size_t>(i)]
               : "#" + std::to_string(i + 1);
  };
  std::string out = "<table class=\"heat\">\n<thead><tr><th></th>";
  for (Eigen::Index j = 0; j < r.cols(); ++j) out += Tag("th", name(j));
  out += "</tr></thead>\n<tbody>\n";
  for (Eigen::Index i = 0; i < r.rows(); ++i) {
    out += "<tr>" + Tag("th", name(i));
    for (Eigen::Index j = 0; j < r.cols(); ++j) {
      const double v = r(i, j);
      char text[32];
      std::snprintf(text, sizeof(text), "%.3f", v);
      const bool dark = std::isfinite(v) && std::abs(v) > 0.6;
      out += "<td style=\"background:" + HeatColour(v) + (dark ? ";color:#fff" : "") +
             "\" title=\"" + HtmlEscape(name(i) + " / " + name(j)) + "\">" +
             HtmlEscape(std::isfinite(v) ? text : Number(v)) + "</td>";
    }
    out += "</tr>\n";
  }
  out += "</tbody></table>\n";
  out += "<p class=\"note\">Correlation of the free parameters' estimates (the covariance "
         "scaled by the residual variance): blue −1, white 0, red +1. |r| above 0.99 marks "
         "a pair the data cannot separate.</p>\n";
  return out;
}

// One row per channel of `experiments` with `role` ("" for all).
Table FitTable(const std::vector<ExperimentFit>& experiments, const std::string& role) {
  Table t;
  t.sortable = true;
  t.headers = {"experiment", "role",  "channel",    "unit",   "fitted (σ)",    "RMS",
               "fit %",      "max error", "rel. error %", "Ljung–Box p", "xcorr u (lag)"};
  for (const ExperimentFit& e : experiments) {
    if (!role.empty() && e.role != role) continue;
    for (const ChannelFit& c : e.channels) {
      Cell xcorr = Num(c.input_xcorr_peak, 3);
      xcorr.html += " (" + std::to_string(c.input_xcorr_lag) + ")";
      t.rows.push_back({Text(e.name), Text(e.role), Text(c.channel), Text(c.unit),
                        Text(c.fitted ? "yes (" + Number(c.sigma, 4) + ")" : "no"),
                        Num(c.rms, 4), Num(c.fit_percent, 4), Num(c.max_error, 4),
                        Num(c.relative_error_percent, 4), PValue(c.ljung_box_p), xcorr});
    }
  }
  return t;
}

std::string DiagnosticsTable(const std::vector<ChannelDiagnostics>& diagnostics) {
  if (diagnostics.empty()) return Tag("p", "No fitted channel to diagnose.");
  Table t;
  t.headers = {"experiment", "channel", "RMS", "RMS / σ", "Ljung–Box p", "xcorr u (lag)"};
  for (const BinnedResidual& b : diagnostics.front().bins) {
    t.headers.push_back("vs " + b.variable + ": p");
    t.headers.push_back("largest |mean|");
  }
  for (const ChannelDiagnostics& d : diagnostics) {
    Cell xcorr = Num(d.xcorr_peak, 3);
    xcorr.html += " (" + std::to_string(d.xcorr_lag) + ")";
    std::vector<Cell> row = {Text(d.experiment), Text(d.channel),
                             NumUnit(d.rms, 4, d.unit),
                             Num(d.sigma > 0.0 ? d.rms / d.sigma
                                               : std::numeric_limits<double>::quiet_NaN(),
                                 3),
                             PValue(d.ljung_box_p), xcorr};
    for (const BinnedResidual& b : d.bins) {
      double largest = 0.0;
      for (double m : b.mean) largest = std::max(largest, std::abs(m));
      row.push_back(b.dof > 0 ? PValue(b.p_value) : Text("—"));
      row.push_back(Num(largest, 3));
    }
    t.rows.push_back(row);
  }
  return Render(t) +
         "<p class=\"note\">Ljung–Box: whiteness of the residual (20 lags); xcorr u: peak "
         "normalised cross-correlation of the residual with the input, at its lag in "
         "samples; vs v, x, a, θ mod rev: χ² test that the mean residual does not depend on "
         "the variable (12 bins), and the largest bin mean (the unit of the RMS). p-values "
         "below 0.001 in bold.</p>\n";
}

std::string VerdictHtml(const DiscoveryReport& d) {
  const ResidualVerdict& v = d.verdict;
  std::string out = "<p>Verdict: <span class=\"verdict " + HtmlEscape(v.verdict) + "\">" +
                    HtmlEscape(v.verdict) + "</span> " +
                    HtmlEscape("(s² = " + Number(v.s2, 4) + ", p " + Number(v.s2_p_value, 3) +
                               "; " + std::to_string(v.tests) + " tests at " +
                               Number(v.threshold, 3) + " each, Bonferroni)") +
                    "</p>\n<ul>\n";
  for (const std::string& c : v.channels) out += Tag("li", c) + "\n";
  out += "</ul>\n";
  if (!v.remains.empty()) {
    out += "<p>What remains:</p>\n<ul class=\"remains\">\n";
    for (const std::string& r : v.remains) out += Tag("li", r) + "\n";
    out += "</ul>\n";
    if (!d.selected.empty()) {
      out += Tag("p", "The selected effects explain part of the residual; with the model "
                      "incomplete their values may stand in for what is missing.",
                 "class=\"note\"");
    }
  }
  return out;
}

std::string StepHtml(size_t index, const DiscoveryStep& s) {
  std::string head = "Step " + std::to_string(index + 1) + ": ";
  std::string label;
  if (s.removal) {
    head += "without " + s.effect;
    label = s.kept ? "removed" : "stays";
  } else {
    head += s.effect;
    label = s.kept ? "kept" : "rejected";
  }
  const bool good = s.removal ? !s.kept : s.kept;
  std::string out = "<h4>" + HtmlEscape(head) + " <span class=\"" +
                    (good ? "kept" : "rejected") + "\">(" + label + ")</span></h4>\n<ul>\n";
  if (!s.removal) {
    out += Tag("li", "score test: χ² " + Number(s.chi2, 4) + " (dof " + std::to_string(s.dof) +
                         ", p " + Number(s.p_value, 3) + ")");
  }
  out += Tag("li", "BIC " + Number(s.bic_before, 6) + " → " +
                       (s.stopped.empty() ? "" : "≥ ") + Number(s.bic_after, 6) +
                       " (refit " + Number(s.seconds, 3) + " s)");
  if (!s.stopped.empty()) out += Tag("li", "stopped " + s.stopped);
  if (!s.rule.empty()) out += Tag("li", "rule: " + s.rule);
  if (!s.outranked.empty()) out += Tag("li", "outranked: " + s.outranked);
  if (!s.starts.empty()) out += Tag("li", "starts: " + s.starts);
  if (!s.implausible.empty()) out += Tag("li", "not physical: " + s.implausible);
  if (!s.insignificant.empty()) out += Tag("li", "not significant: " + s.insignificant);
  out += "</ul>\n";
  if (!s.parameters.empty()) {
    Table p;
    p.headers = {"parameter", "unit", "value", "std error", "95 % interval"};
    for (const ParameterEstimate& e : s.parameters) {
      p.rows.push_back({Text(e.name), Text(e.unit), Num(e.value), Num(e.std_error),
                        Text(Interval(e.ci95_low, e.ci95_high))});
    }
    out += Render(p);
  }
  if (!s.channels.empty()) {
    Table c;
    c.headers = {"experiment", "channel", "RMS before", "RMS after", "fit % before",
                 "fit % after"};
    for (const ChannelChange& x : s.channels) {
      c.rows.push_back({Text(x.experiment), Text(x.channel), Num(x.rms_before, 4),
                        Num(x.rms_after, 4), Num(x.fit_percent_before, 4),
                        Num(x.fit_percent_after, 4)});
    }
    out += Render(c);
  }
  return out;
}

std::string DiscoveryHtml(const DiscoveryReport& d, Plotter* plotter) {
  std::string out;
  out += Tag("p", "After the fit of the declared model, every effect of MODEL.md §7 it lacks "
                  "was tested with a score test; the most significant were added and refitted "
                  "and kept if BIC improved; a backward pass and a Wald test of each effect "
                  "left followed (README, model discovery).",
             "class=\"note\"");
  out += "<h3>Ranking at the first step</h3>\n";
  Table r;
  r.sortable = true;
  r.headers = {"candidate", "χ²", "dof", "p-value", "log10 p"};
  for (const Score& s : d.ranking.scores) {
    r.rows.push_back({Text(s.name), Num(s.chi2, 4), Num(s.dof), PValue(s.p_value),
                      Num(s.log_p_value / std::log(10.0), 4)});
  }
  out += Render(r);
  for (const ParallelPair& q : d.ranking.parallel) {
    out += Tag("p", "nearly parallel: " + q.a + " ~ " + q.b + " (cos " + Number(q.cosine, 3) +
                        "): " +
                        (q.separated ? "the residual separates them"
                                     : "indistinguishable on this data"),
               "class=\"note\"");
  }
  out += "<h3>Steps (before → after each refit)</h3>\n";
  for (size_t k = 0; k < d.steps.size(); ++k) out += StepHtml(k, d.steps[k]);
  const SelectedParts parts = SplitSelected(d.selected);
  std::string plant, front_end, removed;
  for (const std::string& s : parts.plant) plant += (plant.empty() ? "" : ", ") + s;
  for (const std::string& s : parts.front_end) front_end += (front_end.empty() ? "" : ", ") + s;
  for (const std::string& s : d.removed) removed += (removed.empty() ? "" : ", ") + s;
  out += "<h3>Result</h3>\n<ul>\n";
  out += Tag("li", "selected, plant: " + (plant.empty() ? std::string("none") : plant));
  out += Tag("li", "selected, sensor front end: " +
                       (front_end.empty() ? std::string("none") : front_end));
  if (!removed.empty()) out += Tag("li", "removed again: " + removed);
  out += Tag("li", "stopped: " + d.stop_reason);
  double refits = 0.0;
  for (const DiscoveryStep& s : d.steps) refits += s.seconds;
  out += Tag("li", "time: base fit " + Number(d.base_fit_seconds, 3) + " s, score tests " +
                       Number(d.score_seconds, 3) + " s (" + std::to_string(d.score_rankings) +
                       " ranking(s)), refits " + Number(refits, 3) + " s");
  out += "</ul>\n";
  if (!d.significance.empty()) {
    out += "<h3>Significance of the selected effects</h3>\n";
    Table w;
    w.headers = {"effect", "Wald χ² (against off)", "dof", "p-value"};
    for (const EffectSignificance& e : d.significance) {
      w.rows.push_back({Text(e.effect), Num(e.chi2, 4), Num(e.dof), Num(e.p_value, 3)});
    }
    out += Render(w) + Tag("p", "Level " + Number(d.level, 4) +
                                    " (α divided by the number of candidates).",
                           "class=\"note\"");
  }
  out += "<h3>Residual diagnostics of the final model</h3>\n";
  out += DiagnosticsTable(d.final_diagnostics);
  for (const ChannelDiagnostics& c : d.final_diagnostics) out += plotter->Diagnostics(c);
  out += "<h3 id=\"verdict\">Verdict</h3>\n" + VerdictHtml(d);
  return out;
}

std::string PublishedHtml(const PublishedComparison& c) {
  std::string out = Tag("p", "Source: " + c.source);
  Table p;
  p.headers = {"parameter", "unit", "this fit", "std error", "published", "difference %"};
  for (const ParameterComparison& x : c.parameters) {
    Cell name = Text(x.name);
    if (!x.free) name.html += " <span class=\"note\">(not estimated: effect not in the model)</span>";
    p.rows.push_back({name, Text(x.unit), Num(x.fitted), Num(x.std_error), Num(x.published),
                      Num(100.0 * (x.fitted - x.published) / std::abs(x.published), 3)});
  }
  out += Render(p);
  Table r;
  r.headers = {"experiment", "channel", "this fit %", "published model here %",
               "published (quoted) %", "RMS this fit", "RMS published here"};
  for (const ChannelComparison& x : c.channels) {
    r.rows.push_back({Text(x.experiment), Text(x.channel), Num(x.fitted_percent, 4),
                      Num(x.published_percent, 4), Num(x.quoted_percent, 4),
                      Num(x.fitted_rms, 4), Num(x.published_rms, 4)});
  }
  out += Render(r);
  out += Tag("p", "Relative error 100·‖ŷ − y‖/‖y‖; the published model is simulated here with "
                  "the job's experiments and controller.",
             "class=\"note\"");
  return out;
}

std::string DataHtml(const HtmlReportInput& input) {
  std::string out;
  if (input.job != nullptr) {
    Table t;
    t.headers = {"experiment", "role", "data file", "window (file time, s)", "samples",
                 "measured channels", "fitted (σ)"};
    for (const std::vector<FitExperiment>* list : {&input.job->experiments, &input.job->validate}) {
      for (const FitExperiment& e : *list) {
        std::string measured, fitted;
        for (Channel c : e.measured_channels) {
          measured += (measured.empty() ? "" : ", ") + std::string(ChannelName(c));
        }
        for (const FittedChannel& f : e.fitted) {
          fitted += (fitted.empty() ? "" : ", ") + std::string(ChannelName(f.channel)) + " (" +
                    Number(f.sigma, 4) + " " +
                    ChannelUnit(f.channel, input.job->model.structure.motion == Motion::kRotary) +
                    ")";
        }
        const double end = e.t.empty() ? e.t_offset : e.t_offset + e.t.back();
        t.rows.push_back({Text(e.name), Text(e.role), Html("<span class=\"mono\">" +
                                                            HtmlEscape(fs::path(e.data_path).lexically_normal().string()) +
                                                            "</span>"),
                          Text(Interval(e.t_offset, end)), Num(static_cast<double>(e.t.size())),
                          Text(measured), Text(fitted.empty() ? "—" : fitted)});
      }
    }
    out += Render(t);
  }
  if (!input.input_notes.empty()) {
    out += "<p>How drive columns were read where the job did not say:</p>\n<ul>\n";
    for (const std::string& n : input.input_notes) out += Tag("li", n) + "\n";
    out += "</ul>\n";
  }
  return out;
}

std::string SummaryHtml(const HtmlReportInput& input) {
  const FitResult& r = *input.result;
  std::string out = "<dl class=\"summary\">\n";
  const auto item = [&](const std::string& key, const std::string& html) {
    out += Tag("dt", key) + "<dd>" + html + "</dd>\n";
  };
  if (input.discovery != nullptr && !input.discovery->verdict.verdict.empty()) {
    const std::string& v = input.discovery->verdict.verdict;
    item("verdict", "<a href=\"#verdict\"><span class=\"verdict " + HtmlEscape(v) + "\">" +
                        HtmlEscape(v) + "</span></a>");
    std::string effects;
    for (const std::string& s : input.discovery->selected) {
      effects += (effects.empty() ? "" : ", ") + s;
    }
    item("effects added", HtmlEscape(effects.empty() ? "none" : effects));
  }
  item("cost ½Σr²", HtmlEscape(Number(r.initial_cost, 8) + " → " + Number(r.final_cost, 8) +
                              (r.converged ? " (converged)" : " (NOT converged)")));
  item("s² (residual variance)", HtmlEscape(Number(r.residual_variance, 4) + " in units of " +
                                           "the declared noise, " +
                                           std::to_string(r.num_residuals) + " residuals"));
  item("AIC, BIC", HtmlEscape(Number(r.aic, 8) + ", " + Number(r.bic, 8)));
  item("optimum", HtmlEscape(r.optimum_check.empty() ? "not checked" : r.optimum_check));
  if (!r.model_note.empty()) item("note", HtmlEscape(r.model_note));
  if (!r.auto_starts_note.empty()) item("starts", HtmlEscape(r.auto_starts_note));
  if (!r.sample_sigma_note.empty()) item("weights", HtmlEscape(r.sample_sigma_note));
  if (!r.residual_note.empty()) item("warning", HtmlEscape(r.residual_note));
  item("uncertainty", HtmlEscape((r.uncertainty_method.empty() ? "-" : r.uncertainty_method) +
                                 ": " + r.uncertainty_note));
  if (!r.misspecification_note.empty()) {
    item("misspecification", HtmlEscape(r.misspecification_note));
  }
  // FormatPhases: "time: 41.2 s (…)". With discovery the result is the
  // last refit's; the loop's own times are in its section.
  std::string phases = FormatPhases(r);
  if (phases.rfind("time: ", 0) == 0) phases.erase(0, 6);
  item(input.discovery != nullptr ? "time (final refit)" : "time", HtmlEscape(phases));
  if (!input.run_phases.empty()) {
    item("run (phase: wall time, simulations)", HtmlEscape(FormatPhaseLog(input.run_phases)));
  }
  return out + "</dl>\n";
}

std::string SolverHtml(const FitResult& r) {
  std::string out = "<ul>\n";
  out += Tag("li", "final cost of each start: " + HtmlEscape(FormatStartCosts(r)));
  out += Tag("li", "iterations " + std::to_string(r.iterations) + ", simulations " +
                       std::to_string(r.simulations) + ", Jacobian evaluations " +
                       std::to_string(r.jacobian_evaluations));
  out += Tag("li", "termination: " + (r.termination.empty() ? "-" : r.termination));
  std::string undetermined;
  for (const std::string& u : r.undetermined) undetermined += (undetermined.empty() ? "" : ", ") + u;
  out += Tag("li", "not determined by the data: " +
                       (undetermined.empty() ? std::string("none") : undetermined));
  out += "</ul>\n";
  const std::string bootstrap = FormatBootstrap(r);
  if (!bootstrap.empty()) out += "<pre>" + HtmlEscape(bootstrap) + "</pre>\n";
  return out;
}

// The proposal's text, then its ten best feasible inputs by the criterion
// (T: the smaller predicted χ² of the two directions; D: log det JᵀJ).
std::string ProposalHtml(const ExperimentProposal& p) {
  std::string body = "<pre>" + HtmlEscape(FormatProposal(p)) + "</pre>\n";
  if (!p.proposed) return body;
  std::vector<const DesignCandidate*> best;
  for (const DesignCandidate& c : p.candidates) {
    if (c.feasible) best.push_back(&c);
  }
  std::stable_sort(best.begin(), best.end(),
                   [](const DesignCandidate* a, const DesignCandidate* b) {
                     return a->criterion > b->criterion;
                   });
  if (best.size() > 10) best.resize(10);
  const bool t_optimal = p.criterion == "T-optimal";
  HtmlTable table;
  table.sortable = true;
  table.headers = {"input", "x min (m)", "x max (m)"};
  if (t_optimal) {
    table.headers.push_back("chi2 " + p.a + " beyond " + p.b);
    table.headers.push_back("chi2 " + p.b + " beyond " + p.a);
  } else {
    table.headers.push_back("log det information");
  }
  for (const DesignCandidate* c : best) {
    std::vector<HtmlCell> row = {HtmlTextCell(c->description), HtmlNumberCell(c->x_min, 4),
                                 HtmlNumberCell(c->x_max, 4)};
    if (t_optimal) {
      row.push_back(HtmlNumberCell(c->chi2_a_given_b, 4));
      row.push_back(HtmlNumberCell(c->chi2_b_given_a, 4));
    } else {
      row.push_back(HtmlNumberCell(c->criterion, 6));
    }
    table.rows.push_back(row);
  }
  return body + Tag("p", "The best feasible inputs of the family (" +
                             std::to_string(best.size()) + " shown), by " +
                             HtmlEscape(p.criterion) + " criterion:") +
         RenderHtmlTable(table);
}

// The frequency response's table and notes, and a Bode plot per
// experiment and channel.
std::string FrequencyResponseHtml(const std::vector<ExperimentFrequencyResponse>& responses,
                                  Plotter* plotter) {
  std::string body = "<pre>" + HtmlEscape(FormatFrequencyResponse(responses)) + "</pre>\n" +
                     Tag("p",
                         "H1 = G_uy/G_uu with Welch averaging (Hann, 50 % overlap) from the "
                         "experiment's input to each fitted channel, on the bins of the input's "
                         "band; the model's H1 is of its simulation at the estimate on the same "
                         "input (docs/frequency-response.md).",
                         "class=\"note\"");
  for (const ExperimentFrequencyResponse& r : responses) {
    for (const ChannelFrequencyResponse& c : r.channels) body += plotter->Bode(r, c);
  }
  return body;
}

}  // namespace

std::string HtmlEscape(const std::string& text) {
  std::string out;
  out.reserve(text.size() + text.size() / 8);
  for (size_t k = 0; k < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[k]);
    // Length of a valid UTF-8 sequence starting at k (0 if invalid).
    size_t length = 0;
    if (c < 0x80) {
      length = 1;
    } else if (c >= 0xC2 && c <= 0xF4) {
      length = c < 0xE0 ? 2 : (c < 0xF0 ? 3 : 4);
      if (k + length > text.size()) length = 0;
      for (size_t m = 1; m < length; ++m) {
        if ((static_cast<unsigned char>(text[k + m]) & 0xC0) != 0x80) length = 0;
      }
      // Overlong, surrogate or beyond U+10FFFF forms.
      if (length == 3) {
        const unsigned char d = static_cast<unsigned char>(text[k + 1]);
        if ((c == 0xE0 && d < 0xA0) || (c == 0xED && d >= 0xA0)) length = 0;
      } else if (length == 4) {
        const unsigned char d = static_cast<unsigned char>(text[k + 1]);
        if ((c == 0xF0 && d < 0x90) || (c == 0xF4 && d >= 0x90)) length = 0;
      }
    }
    if (length == 0) {
      out += "\xEF\xBF\xBD";  // U+FFFD
      ++k;
      continue;
    }
    if (length == 1) {
      switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&#39;"; break;
        default:
          // Control characters other than tab and line breaks are not text.
          if (c < 0x20 && c != '\t' && c != '\n' && c != '\r') {
            out += "\xEF\xBF\xBD";
          } else {
            out += static_cast<char>(c);
          }
      }
    } else {
      out.append(text, k, length);
    }
    k += length;
  }
  return out;
}

std::string RenderHtmlTable(const HtmlTable& table) {
  std::string classes = table.css_class;
  if (table.sortable) classes += (classes.empty() ? "" : " ") + std::string("sortable");
  // In a box of the page's width that scrolls sideways if the table is wider.
  std::string out = "<div class=\"scroll\"><table" +
                    (classes.empty() ? "" : " class=\"" + classes + "\"") + ">\n<thead><tr>";
  for (const std::string& h : table.headers) {
    out += table.sortable ? Tag("th", h, "title=\"sort by this column\"") : Tag("th", h);
  }
  out += "</tr></thead>\n<tbody>\n";
  for (const std::vector<HtmlCell>& row : table.rows) {
    out += "<tr>";
    for (const HtmlCell& c : row) {
      std::string attributes;
      if (c.number) attributes += " class=\"num\"";
      if (!c.sort.empty()) attributes += " data-v=\"" + HtmlEscape(c.sort) + "\"";
      out += "<td" + attributes + ">" + c.html + "</td>";
    }
    out += "</tr>\n";
  }
  return out + "</tbody></table></div>\n";
}

HtmlCell HtmlTextCell(const std::string& text) {
  HtmlCell c;
  c.html = HtmlEscape(text);
  return c;
}

HtmlCell HtmlNumberCell(double value, int digits) {
  HtmlCell c = HtmlTextCell(Number(value, digits));
  c.number = true;
  if (std::isfinite(value)) c.sort = Number(value, 17);
  return c;
}

std::string RenderHtmlPage(const std::string& document_title, const std::string& heading,
                           const std::string& intro, const std::vector<HtmlSection>& sections) {
  std::string page =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n" +
      Tag("title", document_title) + "\n<style>" + kStyle + "</style>\n</head>\n<body>\n" +
      Tag("h1", heading) + "\n" + Tag("p", intro, "class=\"note\"") + "\n<nav>";
  for (const HtmlSection& s : sections) {
    page += "\n<a href=\"#" + s.id + "\">" + HtmlEscape(s.heading) + "</a>";
  }
  page += "</nav>\n";
  for (const HtmlSection& s : sections) {
    page += "<section id=\"" + s.id + "\">\n" + Tag("h2", s.heading) + "\n" + s.body +
            "</section>\n";
  }
  page += "<script>" + std::string(kScript) + "</script>\n</body>\n</html>\n";
  return page;
}

int HtmlReportPlotCount(const HtmlReportInput& input) {
  size_t n = input.result != nullptr ? input.result->experiments.size() : 0;
  if (input.diagnostics != nullptr) n += input.diagnostics->size();
  if (input.discovery != nullptr) n += input.discovery->final_diagnostics.size();
  if (input.force_map != nullptr && !input.force_map->curve.z.empty()) ++n;
  if (input.frequency_response != nullptr) {
    for (const ExperimentFrequencyResponse& r : *input.frequency_response) n += r.channels.size();
  }
  return static_cast<int>(n);
}

std::string RenderHtmlReport(const HtmlReportInput& input, const std::string& scratch_dir,
                             std::vector<std::string>* warnings) {
  if (input.result == nullptr) {
    throw std::invalid_argument("RenderHtmlReport: expected a fit result, got none");
  }
  const FitResult& result = *input.result;
  const std::string title = input.title.empty() ? "Fit report" : input.title;
  Plotter plotter(scratch_dir, warnings);

  // Sections in page order: id, heading, body.
  std::vector<HtmlSection> sections;
  sections.push_back({"summary", "Summary", SummaryHtml(input)});
  sections.push_back({"data", "Data", DataHtml(input)});

  std::string parameters = Render(ParameterTable(result, input.job, true));
  parameters += Tag("p", "Standard errors from the covariance of the reported method scaled by "
                         "the residual variance; 95 % interval of that method (" +
                             (result.uncertainty_method.empty() ? std::string("-")
                                                                : result.uncertainty_method) +
                             "). Positive parameters are fitted as their logarithm.",
                    "class=\"note\"");
  const Table fixed = ParameterTable(result, input.job, false);
  if (!fixed.rows.empty()) {
    parameters += "<details><summary>" + std::to_string(fixed.rows.size()) +
                  " fixed parameters (the model's values)</summary>\n" + Render(fixed) +
                  "</details>\n";
  }
  sections.push_back({"parameters", "Parameters", parameters});
  sections.push_back({"correlation", "Correlation of the estimates", CorrelationHeatMap(result)});

  std::string experiments = Render(FitTable(result.experiments, "")) +
                            Tag("p", "RMS and max error in the channel unit; fit % = 100·(1 − "
                                     "‖y − ŷ‖/‖y − mean(y)‖); rel. error % = 100·‖ŷ − y‖/‖y‖. "
                                     "Click a column header to sort.",
                                "class=\"note\"");
  for (const ExperimentFit& e : result.experiments) {
    experiments += "<h3 id=\"" + Anchor("experiment-", e.name) + "\">" +
                   HtmlEscape(e.name + " (" + (e.role == "fit" ? "fitted" : "validation") + ")") +
                   "</h3>\n" + plotter.Experiment(e);
  }
  sections.push_back({"experiments", "Experiments: measured, simulated, residual", experiments});

  bool any_validation = false;
  for (const ExperimentFit& e : result.experiments) any_validation |= e.role == "validate";
  if (any_validation) {
    std::string validation =
        Tag("p", "Experiments not fitted, simulated with the estimates:") +
        Render(FitTable(result.experiments, "validate")) + "<p>Plots: ";
    for (const ExperimentFit& e : result.experiments) {
      if (e.role != "validate") continue;
      validation += "<a href=\"#" + Anchor("experiment-", e.name) + "\">" + HtmlEscape(e.name) +
                    "</a> ";
    }
    sections.push_back({"validation", "Validation", validation + "</p>\n"});
  }

  if (input.diagnostics != nullptr) {
    std::string diagnostics =
        Tag("p", input.discovery != nullptr
                     ? "Residuals of the model as declared, fitted, before discovery."
                     : "Residuals of the fitted model.",
            "class=\"note\"") +
        DiagnosticsTable(*input.diagnostics);
    for (const ChannelDiagnostics& d : *input.diagnostics) diagnostics += plotter.Diagnostics(d);
    sections.push_back({"diagnostics", "Residual diagnostics", diagnostics});
  }
  if (input.frequency_response != nullptr && !input.frequency_response->empty()) {
    sections.push_back({"frequency-response", "Frequency response",
                        FrequencyResponseHtml(*input.frequency_response, &plotter)});
  }
  if (input.discovery != nullptr) {
    sections.push_back({"discovery", "Model discovery", DiscoveryHtml(*input.discovery, &plotter)});
  }
  if (input.force_map != nullptr) {
    std::string body = "<pre>" + HtmlEscape(FormatForceMap(*input.force_map)) + "</pre>\n";
    if (!input.force_map->curve.z.empty()) body += plotter.ForceMap(*input.force_map);
    sections.push_back({"force-map", "Force map", body});
  }
  if (input.published != nullptr) {
    sections.push_back({"published", "Published reference", PublishedHtml(*input.published)});
  }
  if (input.proposal != nullptr) {
    sections.push_back({"next-experiment", "Next experiment", ProposalHtml(*input.proposal)});
  }
  if (input.tuning != nullptr) {
    sections.push_back(
        {"tuning", "Tuning",
         "<pre>" + HtmlEscape(FormatTuning(*input.tuning)) + "</pre>\n" +
             (input.tuning->ran ? plotter.TuningStep(*input.tuning) : std::string())});
  }
  if (input.move_tuning != nullptr) {
    sections.push_back({"move-tuning", "Move tuning",
                        "<pre>" + HtmlEscape(FormatMoveTuning(*input.move_tuning)) + "</pre>\n" +
                            (input.move_tuning->ran ? plotter.TuningMove(*input.move_tuning)
                                                    : std::string())});
  }
  std::string solver = SolverHtml(result);
  if (!input.files.empty()) {
    solver += "<p>Other files of this run (beside this page):</p>\n<ul>\n";
    for (const std::string& f : input.files) {
      solver += "<li><span class=\"mono\">" + HtmlEscape(f) + "</span></li>\n";
    }
    solver += "</ul>\n";
  }
  sections.push_back({"solver", "Solver", solver});
  plotter.Draw(&sections);

  return RenderHtmlPage(title + " — fit report", title,
                        "Written by fit-params: the fit, its uncertainty and what the residuals "
                        "say. Self-contained: no file or network resource is loaded.",
                        sections);
}

void WriteHtmlReport(const std::string& path, const HtmlReportInput& input,
                     std::vector<std::string>* warnings) {
  fs::path dir = fs::path(path).parent_path();
  if (dir.empty()) dir = ".";
  WriteFileAtomic(path, RenderHtmlReport(input, dir.string(), warnings));
}

}  // namespace axis
