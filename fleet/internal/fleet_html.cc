#include "fleet/internal/fleet_html.h"

#include <cmath>
#include <vector>

#include "common/format.h"
#include "report/html_report.h"

namespace axis {
namespace {

// A cell of ready HTML.
HtmlCell Raw(const std::string& html) {
  HtmlCell c;
  c.html = html;
  return c;
}

// "value ± se", right-aligned, sorted by the value; empty if absent.
HtmlCell ParameterCell(const FleetParameter* p) {
  if (p == nullptr) return Raw("");
  HtmlCell c = HtmlNumberCell(p->value);
  c.html += " ± " + HtmlEscape(FormatNumber(p->std_error, 2, "—"));
  if (!p->determined) c.html += " <em>(not determined)</em>";
  return c;
}

std::string StatusClass(const std::string& status) {
  if (status == "ok") return "explained";
  return "incomplete";
}

std::string Join(const std::vector<std::string>& items) {
  std::string out;
  for (size_t k = 0; k < items.size(); ++k) out += (k ? ", " : "") + items[k];
  return out;
}

std::string ChangesHtml(const FleetComparison& c) {
  std::string out =
      "<p class=\"note\">Against " + HtmlEscape(c.baseline) +
      ": each free parameter is compared with its baseline fit, z = (new − old)/√(se<sub>new</sub>² "
      "+ se<sub>old</sub>²), and flagged when its two-sided p-value is below " +
      HtmlEscape(FormatNumber(c.alpha)) + "/" + std::to_string(c.tests) +
      " (family-wise level over the fleet's " + std::to_string(c.tests) +
      " comparisons); an effect that appeared or disappeared is always flagged. Most significant "
      "first.</p>\n";
  if (c.changes.empty()) {
    out += "<p><span class=\"verdict explained\">no change</span></p>\n";
  } else {
    HtmlTable t;
    t.headers = {"axis", "log", "change", "now", "baseline", "relative", "z"};
    for (const FleetChange& ch : c.changes) {
      std::vector<HtmlCell> row = {HtmlTextCell(ch.axis), HtmlTextCell(ch.log),
                                   HtmlTextCell(ch.kind == "parameter" ? ch.name
                                                                       : ch.kind + ": " + ch.name)};
      if (ch.kind == "parameter") {
        HtmlCell now = HtmlNumberCell(ch.value);
        now.html += " ± " + HtmlEscape(FormatNumber(ch.std_error, 2) + " " + ch.unit);
        HtmlCell was = HtmlNumberCell(ch.baseline_value);
        was.html += " ± " + HtmlEscape(FormatNumber(ch.baseline_std_error, 2) + " " + ch.unit);
        const double relative = std::fabs(ch.baseline_value) > 2.0 * ch.baseline_std_error
                                    ? 100.0 * (ch.value - ch.baseline_value) /
                                          std::fabs(ch.baseline_value)
                                    : std::nan("");
        HtmlCell rel = HtmlNumberCell(relative, 3);
        if (std::isfinite(relative)) rel.html = (relative > 0 ? "+" : "") + rel.html + " %";
        row.insert(row.end(), {now, was, rel, HtmlNumberCell(ch.z, 3)});
      } else {
        row.insert(row.end(), {Raw(""), Raw(""), Raw(""), Raw("")});
      }
      t.rows.push_back(row);
    }
    out += RenderHtmlTable(t) + "<ul>\n";
    for (const FleetChange& ch : c.changes) out += "<li>" + HtmlEscape(ch.text) + "</li>\n";
    out += "</ul>\n";
  }
  if (!c.not_compared.empty()) {
    out += "<p>Not compared:</p>\n<ul>\n";
    for (const std::string& n : c.not_compared) out += "<li>" + HtmlEscape(n) + "</li>\n";
    out += "</ul>\n";
  }
  return out;
}

std::string AxesHtml(const FleetTable& table) {
  const auto params = FleetParameterColumns(table.rows);
  const auto fits = FleetFitColumns(table.rows);
  HtmlTable t;
  t.sortable = true;
  t.headers = {"axis", "log", "status", "verdict", "s²", "effects"};
  for (const auto& [name, unit] : params) t.headers.push_back(name + " (" + unit + ")");
  for (const std::string& f : fits) t.headers.push_back("fit % " + f);
  t.headers.push_back("time (s)");
  for (const FleetRow& r : table.rows) {
    // The axis links to its report.html, beside fleet.html in <axis>/<log>/.
    HtmlCell axis = HtmlTextCell(r.axis);
    if (r.status != "failed") {
      axis.html = "<a href=\"" + HtmlEscape(r.folder + "/report.html") + "\">" + axis.html + "</a>";
    }
    HtmlCell status = Raw("<span class=\"verdict " + StatusClass(r.status) + "\">" +
                          HtmlEscape(r.status) + "</span>");
    HtmlCell verdict = Raw(r.verdict.empty() ? "—"
                                             : "<span class=\"verdict " + HtmlEscape(r.verdict) +
                                                   "\">" + HtmlEscape(r.verdict) + "</span>");
    verdict.sort = r.verdict;
    std::vector<HtmlCell> row = {axis,    HtmlTextCell(r.log),      status,
                                 verdict, HtmlNumberCell(r.s2, 3), HtmlTextCell(Join(r.effects))};
    for (const auto& column : params) row.push_back(ParameterCell(r.FindParameter(column.first)));
    for (const std::string& f : fits) {
      const FleetChannelFit* c = r.FindFit(f);
      row.push_back(c ? HtmlNumberCell(c->fit_percent, 4) : Raw(""));
    }
    row.push_back(HtmlNumberCell(r.seconds, 3));
    t.rows.push_back(row);
  }
  return RenderHtmlTable(t) +
         "<p class=\"note\">Values ± standard error of each job's final fit; fit % = 100·(1 − "
         "‖y − ŷ‖/‖y − mean(y)‖) per experiment/channel; s² the residual variance in σ units. "
         "Click a column header to sort; an axis opens its own report.</p>\n";
}

}  // namespace

std::string RenderFleetHtml(const FleetTable& table) {
  int ok = 0, failed = 0;
  bool incomplete = false;
  for (const FleetRow& r : table.rows) {
    ok += r.status == "ok";
    failed += r.status == "failed";
    incomplete |= r.verdict == "incomplete";
  }
  std::vector<HtmlSection> sections;
  if (table.compared) {
    sections.push_back({"changes", "Changes (" + std::to_string(table.comparison.changes.size()) + ")",
                        ChangesHtml(table.comparison)});
  }
  sections.push_back({"axes", "Axes", AxesHtml(table)});
  if (failed > 0) {
    std::string body = "<ul>\n";
    for (const FleetRow& r : table.rows) {
      if (r.status != "failed") continue;
      body += "<li><strong>" + HtmlEscape(r.axis + " (" + r.log + ")") + "</strong>: <span class=\"mono\">" +
              HtmlEscape(r.error) + "</span></li>\n";
    }
    sections.push_back({"failed", "Failed jobs (" + std::to_string(failed) + ")", body + "</ul>\n"});
  }
  if (incomplete) {
    std::string body = "<ul class=\"remains\">\n";
    for (const FleetRow& r : table.rows) {
      if (r.verdict != "incomplete") continue;
      body += "<li><strong>" + HtmlEscape(r.axis + " (" + r.log + ")") + "</strong>: " +
              HtmlEscape(r.remains.empty() ? "s² above 1" : Join(r.remains)) + "</li>\n";
    }
    sections.push_back({"remains", "What the models still miss", body + "</ul>\n"});
  }
  const std::string intro =
      std::to_string(table.rows.size()) + " jobs, " + std::to_string(ok) + " ok, " +
      std::to_string(failed) + " failed; " + std::to_string(table.ranks) + " MPI rank(s), " +
      FormatNumber(table.wall_seconds, 3) + " s wall. Manifest " + table.manifest +
      ". Written by fit-fleet; self-contained: no file or network resource is loaded (the links "
      "open the axes' own reports).";
  return RenderHtmlPage(table.title + " — fleet", table.title, intro, sections);
}

}  // namespace axis
