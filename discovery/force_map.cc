#include "discovery/force_map.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "common/format.h"
#include "common/gnuplot.h"
#include "discovery/channel_changes.h"
#include "discovery/internal/force_map_step.h"
#include "discovery/internal/force_map_text.h"
#include "io/csv.h"

namespace axis {
namespace {

std::string Number(double x, int digits = 4) { return FormatNumber(x, digits); }

}  // namespace

ForceMapReport AddForceMap(const DiscoverySettings& settings, const DiscoveryReport& loop,
                           EstimationProblem* job, FitResult* result, std::ostream* progress) {
  ForceMapStep step(settings, loop, job, result, progress);
  return step.Run();
}

void ApplyRemovals(const ForceMapReport& report, DiscoveryReport* loop) {
  for (const ForceMapRemoval& r : report.removals) {
    if (!r.removed) continue;
    loop->selected.erase(std::remove(loop->selected.begin(), loop->selected.end(), r.effect),
                         loop->selected.end());
    loop->removed.push_back(r.effect);
  }
}

std::string FormatForceMap(const ForceMapReport& report) {
  std::ostringstream out;
  out << "Force map: " << report.reason << "\n";
  for (const std::string& s : report.structure) out << "  binned structure: " << s << "\n";
  if (!report.scores.empty()) {
    TextTable scores;
    scores.headers = {"form", "chi2", "dof", "p"};
    scores.right = {false, true, true, true};
    for (const Score& s : report.scores) {
      scores.rows.push_back({s.name, Number(s.chi2), std::to_string(s.dof), Number(s.p_value, 3)});
    }
    out << "\nScore tests of the map's forms:\n" << RenderText(scores);
  }
  if (!report.tried) return out.str();
  if (!report.forms.empty()) {
    TextTable forms;
    forms.headers = {"form", "BIC (edf)", "edf", "refit (s)"};
    forms.right = {false, true, true, true};
    for (const ForceMapForm& f : report.forms) {
      forms.rows.push_back({f.name, (f.stopped.empty() ? "" : ">= ") + Number(f.bic, 7),
                            f.stopped.empty() ? Number(f.edf) : "-", Number(f.seconds, 3)});
    }
    out << "\nThe significant forms refitted (little smoothing; the lowest BIC wins):\n"
        << RenderText(forms);
    for (const ForceMapForm& f : report.forms) {
      if (!f.stopped.empty()) out << f.name << ": stopped " << f.stopped << "\n";
    }
  }
  if (report.kind.empty()) return out.str();
  const ForceMap& map = report.map;
  out << "\nForce map " << FormText(map) << " (" << report.kind << "): " << map.knots.size()
      << " knots over [" << Number(map.knots.front()) << ", " << Number(map.knots.back()) << "] "
      << VariableUnit(map, report.rotary) << "\n";
  const std::string force_unit = MapForceUnit(report.rotary);
  const std::string lambda_unit =
      report.rotary ? "1/(" + force_unit + ")^2" : "1/" + force_unit + "^2";
  TextTable grid;
  grid.headers = {"lambda (" + lambda_unit + ")", "edf", "chi2 (linearised)", "BIC", ""};
  grid.right = {true, true, true, true, false};
  for (const SmoothingChoice& s : report.grid) {
    grid.rows.push_back({Number(s.lambda, 3), Number(s.edf), Number(s.chi2, 7), Number(s.bic, 7),
                         s.lambda == report.lambda ? "chosen" : ""});
  }
  out << "\nRoughness penalty, BIC with the effective number of parameters:\n"
      << RenderText(grid);
  TextTable values;
  values.headers = {"knot (" + std::string(VariableUnit(map, report.rotary)) + ")",
                    (report.rotary ? "torque (" : "force (") + force_unit + ")",
                    "std error (" + force_unit + ")"};
  values.right = {true, true, true};
  for (size_t k = 0; k < report.values.size(); ++k) {
    values.rows.push_back({Number(map.knots[k]), Number(report.values[k]),
                           Number(report.std_errors[k], 3)});
  }
  out << "\nLearned " << (report.rotary ? "torque" : "force")
      << " (values at the knots; 95 % band: +-1.96 std error):\n"
      << RenderText(values);
  out << "lambda " << Number(report.lambda, 3) << " " << lambda_unit << ", edf "
      << Number(report.edf) << ", s2 " << Number(report.s2) << "; BIC "
      << Number(report.bic_before, 7) << " -> " << Number(report.bic_after, 7)
      << (report.kept ? " (kept)" : " (not kept)") << "\n";
  for (const ForceMapRemoval& r : report.removals) {
    out << "without " << r.effect << ": BIC " << Number(r.bic_with, 7) << " -> "
        << Number(r.bic_without, 7) << (r.removed ? " (removed: a stand-in for the map)" : " (stays)")
        << "\n";
  }
  out << "significantly non-zero: "
      << (report.significant.empty() ? "nowhere" : Join(report.significant, "; ")) << "\n";
  TextTable channels;
  channels.headers = {"experiment", "channel", "RMS before", "RMS after", "fit % before",
                      "fit % after"};
  channels.right = {false, false, true, true, true, true};
  for (const ChannelChange& c : report.channels) {
    channels.rows.push_back({c.experiment, c.channel, Number(c.rms_before), Number(c.rms_after),
                             Number(c.fit_percent_before), Number(c.fit_percent_after)});
  }
  out << "\nBefore (library model) and after (with the map):\n" << RenderText(channels);
  if (report.kept) out << "\nWith the map: " << FormatVerdict(report.verdict);
  out << "(" << Number(report.seconds, 3) << " s)\n";
  return out.str();
}

nlohmann::json ForceMapToJson(const ForceMapReport& report) {
  nlohmann::json out;
  out["tried"] = report.tried;
  out["kept"] = report.kept;
  out["reason"] = report.reason;
  out["structure"] = report.structure;
  nlohmann::json scores = nlohmann::json::array();
  for (const Score& s : report.scores) {
    scores.push_back({{"effect", s.name},
                      {"chi2", JsonNumber(s.chi2)},
                      {"dof", s.dof},
                      {"p_value", JsonNumber(s.p_value)}});
  }
  out["scores"] = scores;
  nlohmann::json forms = nlohmann::json::array();
  for (const ForceMapForm& f : report.forms) {
    forms.push_back({{"effect", f.name},
                     {"bic", JsonNumber(f.bic)},
                     {"edf", JsonNumber(f.edf)},
                     {"stopped", f.stopped}});
  }
  out["forms"] = forms;
  nlohmann::json removals = nlohmann::json::array();
  for (const ForceMapRemoval& r : report.removals) {
    removals.push_back({{"effect", r.effect},
                        {"bic_with", JsonNumber(r.bic_with)},
                        {"bic_without", JsonNumber(r.bic_without)},
                        {"removed", r.removed}});
  }
  out["removals"] = removals;
  if (report.kind.empty()) return out;
  out["kind"] = report.kind;
  out["variable"] = VariableName(report.map);
  out["friction"] = report.map.friction;
  out["variable_unit"] = VariableUnit(report.map, report.rotary);
  out["value_unit"] = MapForceUnit(report.rotary);
  out["knots"] = report.map.knots;
  out["values"] = report.values;
  nlohmann::json se = nlohmann::json::array();
  for (double s : report.std_errors) se.push_back(JsonNumber(s));
  out["std_errors"] = se;
  out["lambda"] = JsonNumber(report.lambda);
  out["edf"] = JsonNumber(report.edf);
  out["s2"] = JsonNumber(report.s2);
  out["bic_before"] = JsonNumber(report.bic_before);
  out["bic_after"] = JsonNumber(report.bic_after);
  nlohmann::json grid = nlohmann::json::array();
  for (const SmoothingChoice& s : report.grid) {
    grid.push_back({{"lambda", JsonNumber(s.lambda)},
                    {"edf", JsonNumber(s.edf)},
                    {"chi2", JsonNumber(s.chi2)},
                    {"bic", JsonNumber(s.bic)}});
  }
  out["grid"] = grid;
  out["channels"] = ChannelChangesToJson(report.channels);
  out["verdict"] = report.verdict.verdict;
  out["remains"] = report.verdict.remains;
  out["significant"] = report.significant;
  out["seconds"] = JsonNumber(report.seconds);
  return out;
}

void WriteForceMapCsv(const std::string& path, const ForceMapReport& report) {
  std::ostringstream csv;
  csv << VariableName(report.map) << ",force,low,high\n" << std::setprecision(12);
  for (size_t q = 0; q < report.curve.z.size(); ++q) {
    csv << report.curve.z[q] << "," << report.curve.force[q] << "," << report.curve.low[q] << ","
        << report.curve.high[q] << "\n";
  }
  WriteFileAtomic(path, csv.str());
}

std::string ForceMapPlotScript(const ForceMapReport& report, const std::string& csv_path,
                               const std::string& output, bool svg) {
  std::ostringstream s;
  if (svg) {
    s << "set terminal svg size 1000,560 dynamic noenhanced font 'sans,12' background rgb "
         "'white'; ";
  } else {
    s << "set terminal pngcairo size 1000,600 noenhanced; ";
  }
  s << "set output '" << output
    << "'; set datafile separator ','; set grid; set key top left; set title 'learned "
    << (report.rotary ? "torque " : "force ")
    << FormText(report.map) << (report.kept ? "" : " (not kept)") << "'; set xlabel '"
    << VariableName(report.map) << " (" << VariableUnit(report.map, report.rotary)
    << ")'; set ylabel '" << (report.rotary ? "torque (" : "force (")
    << MapForceUnit(report.rotary) << ")'; plot '" << csv_path
    << "' every ::1 using 1:3:4 with filledcurves lc rgb '#c6dbef' title '95 % band', '"
    << csv_path << "' every ::1 using 1:2 with lines lw 2 lc rgb '#08519c' title 'f', 0 with "
    << "lines lc rgb 'gray' notitle";
  return s.str();
}

void WriteForceMap(const std::string& dir, const ForceMapReport& report,
                   std::vector<std::string>* warnings) {
  if (report.curve.z.empty()) return;
  const std::string csv_path = dir + "/force_map.csv";
  WriteForceMapCsv(csv_path, report);
  const auto script = [&](const std::string& png) {
    return ForceMapPlotScript(report, csv_path, png, false);
  };
  std::string warning;
  if (!RenderGnuplotPng(dir + "/force_map.png", script, "force map", &warning)) {
    if (warnings) warnings->push_back(warning);
  }
}

}  // namespace axis
