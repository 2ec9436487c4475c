#include "discovery/discovery_report.h"

#include "sim/config.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "common/format.h"
#include "sim/config.h"

namespace axis {

const char* BoundMark(const DiscoveryStep& s) { return s.stopped.empty() ? "" : ">= "; }

namespace {

// The parts of FormatDiscovery, written in turn to its one stream (its
// precision and alignment carry from one part to the next).

// The ranking at the first step and its nearly parallel pairs.
void FormatRanking(const DiscoveryReport& report, std::ostream& out) {
  out << "Model discovery (score test, Bonferroni, BIC)\n";
  out << "Ranking at the first step:\n";
  out << "  candidate                 chi2      dof   p-value     log10 p\n";
  for (const Score& s : report.ranking.scores) {
    out << "  " << std::left << std::setw(22) << s.name << std::right
        << std::setw(12) << std::setprecision(4) << s.chi2 << std::setw(6)
        << s.dof << std::setw(12) << s.p_value << std::setw(12)
        << s.log_p_value / std::log(10.0) << "\n";
  }
  for (const ParallelPair& q : report.ranking.parallel) {
    out << "  nearly parallel: " << q.a << " ~ " << q.b << " (cos " << q.cosine
        << "; chi2 " << q.a << "|" << q.b << " " << q.chi2_a_given_b << ", "
        << q.b << "|" << q.a << " " << q.chi2_b_given_a << "): "
        << (q.separated ? "the residual separates them"
                        : "indistinguishable on this data")
        << "\n";
  }
}

// Step k (0-based) of the report: its figures, parameters and channels.
void FormatStep(size_t k, const DiscoveryStep& s, std::ostream& out) {
  if (s.removal) {
    out << "\nStep " << k + 1 << ": without " << s.effect
        << (s.kept ? " (removed)" : " (stays)") << "  BIC " << s.bic_before
        << " -> " << BoundMark(s) << s.bic_after << "  (refit "
        << s.seconds << " s)\n";
    if (!s.stopped.empty()) out << "  stopped " << s.stopped << "\n";
    if (!s.insignificant.empty()) out << "  not significant: " << s.insignificant << "\n";
    if (!s.negligible.empty()) out << "  negligible: " << s.negligible << "\n";
  } else {
    out << "\nStep " << k + 1 << ": " << s.effect << (s.kept ? " (kept)" : " (rejected)")
        << "  chi2 " << s.chi2 << " (dof " << s.dof << ", p " << s.p_value
        << ")  BIC " << s.bic_before << " -> " << BoundMark(s) << s.bic_after << "  (refit "
        << s.seconds << " s)\n";
    if (!s.stopped.empty()) out << "  stopped " << s.stopped << "\n";
    if (!s.implausible.empty()) out << "  not physical: " << s.implausible << "\n";
    if (!s.outranked.empty()) out << "  outranked: " << s.outranked << "\n";
    if (!s.starts.empty()) out << "  starts: " << s.starts << "\n";
    if (!s.retried.empty()) out << "  " << s.retried << "\n";
    if (!s.widened.empty()) out << "  " << s.widened << "\n";
    if (!s.realigned.empty()) out << "  " << s.realigned << "\n";
    if (!s.rule.empty()) out << "  rule: " << s.rule << "\n";
  }
  for (const ParameterEstimate& p : s.parameters) {
    out << "  " << p.name << " = " << p.value << " +- " << p.std_error << " "
        << p.unit << "  95% [" << p.ci95_low << ", " << p.ci95_high << "]\n";
  }
  size_t width = 11;
  for (const ChannelChange& c : s.channels) width = std::max(width, c.experiment.size() + 1);
  out << "  " << std::left << std::setw(static_cast<int>(width)) << "experiment"
      << "channel     RMS before   RMS after   fit% before  fit% after\n";
  for (const ChannelChange& c : s.channels) {
    out << "  " << std::left << std::setw(static_cast<int>(width)) << c.experiment << std::setw(8)
        << c.channel << std::right << std::setw(13) << c.rms_before
        << std::setw(12) << c.rms_after << std::setw(13) << c.fit_percent_before
        << std::setw(12) << c.fit_percent_after << "\n";
  }
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// The selected and removed effects, the stop, the times, the significance
// of the effects left and the final model's verdict.
void FormatOutcome(const DiscoveryReport& report, std::ostream& out) {
  out << "\nSelected: ";
  for (const std::string& s : report.selected) out << s << " ";
  if (report.selected.empty()) out << "none";
  // The plant's effects and the sensor front end's apart (MODEL.md §6–§7):
  // a front-end term explains how the record was made, not the axis.
  const SelectedParts parts = SplitSelected(report.selected);
  if (!parts.front_end.empty()) {
    out << "\n  plant: " << (parts.plant.empty() ? "none" : JoinNames(parts.plant))
        << "\n  front end: " << JoinNames(parts.front_end);
  }
  if (!report.removed.empty()) {
    out << "\nRemoved by the backward pass: ";
    for (const std::string& r : report.removed) out << r << " ";
  }
  out << "\nStopped: " << report.stop_reason << "\n";
  for (const std::string& note : report.notes) out << "Note: " << note << "\n";
  double refits = 0.0;
  for (const DiscoveryStep& s : report.steps) refits += s.seconds;
  out << "Time: base fit " << report.base_fit_seconds << " s, score tests "
      << report.score_seconds << " s (" << report.score_rankings << " ranking(s)), refits "
      << refits << " s (" << report.steps.size() << ")\n";
  if (!report.significance.empty()) {
    out << "Significance of the selected effects (Wald, against off, level " << report.level
        << "):\n";
    for (const EffectSignificance& w : report.significance) {
      out << "  " << std::left << std::setw(22) << w.effect << std::right << " chi2 "
          << w.chi2 << " (dof " << w.dof << "), p " << w.p_value << "\n";
    }
  }
  if (!report.verdict.verdict.empty()) {
    out << "\nFinal model: " << FormatVerdict(report.verdict);
    if (report.verdict.verdict == "incomplete" && !report.selected.empty()) {
      out << "The selected effects explain part of the residual; with the model "
             "incomplete their values may stand in for what is missing.\n";
    }
  }
}

}  // namespace

SelectedParts SplitSelected(const std::vector<std::string>& selected) {
  SelectedParts parts;
  for (const std::string& name : selected) {
    (IsFrontEndEffect(name) ? parts.front_end : parts.plant).push_back(name);
  }
  return parts;
}

std::string FormatDiscovery(const DiscoveryReport& report) {
  std::ostringstream out;
  FormatRanking(report, out);
  for (size_t k = 0; k < report.steps.size(); ++k) FormatStep(k, report.steps[k], out);
  FormatOutcome(report, out);
  return out.str();
}

nlohmann::json DiscoveryToJson(const DiscoveryReport& report) {
  nlohmann::json out;
  out["selected"] = report.selected;
  const SelectedParts parts = SplitSelected(report.selected);
  out["selected_plant"] = parts.plant;
  out["selected_front_end"] = parts.front_end;
  out["removed"] = report.removed;
  out["base_fit_seconds"] = JsonNumber(report.base_fit_seconds);
  out["score_seconds"] = JsonNumber(report.score_seconds);
  out["score_rankings"] = report.score_rankings;
  out["steps"] = nlohmann::json::array();
  for (const DiscoveryStep& s : report.steps) {
    nlohmann::json step;
    step["effect"] = s.effect;
    step["parameters"] = nlohmann::json::object();
    for (const ParameterEstimate& p : s.parameters) {
      step["parameters"][p.name] = {{"value", JsonNumber(p.value)},
                                    {"std_error", JsonNumber(p.std_error)},
                                    {"ci95_low", JsonNumber(p.ci95_low)},
                                    {"ci95_high", JsonNumber(p.ci95_high)}};
    }
    step["chi2"] = JsonNumber(s.chi2);
    step["dof"] = s.dof;
    step["p_value"] = JsonNumber(s.p_value);
    step["bic_before"] = JsonNumber(s.bic_before);
    step["bic_after"] = JsonNumber(s.bic_after);
    step["kept"] = s.kept;
    step["removal"] = s.removal;
    step["seconds"] = JsonNumber(s.seconds);
    if (!s.implausible.empty()) step["implausible"] = s.implausible;
    if (!s.insignificant.empty()) step["insignificant"] = s.insignificant;
    if (!s.negligible.empty()) step["negligible"] = s.negligible;
    if (!s.rule.empty()) step["rule"] = s.rule;
    if (!s.outranked.empty()) step["outranked"] = s.outranked;
    if (!s.starts.empty()) step["starts"] = s.starts;
    if (!s.retried.empty()) step["retried"] = s.retried;
    if (!s.widened.empty()) step["widened"] = s.widened;
    if (!s.realigned.empty()) step["realigned"] = s.realigned;
    if (!s.stopped.empty()) step["stopped"] = s.stopped;
    step["channels"] = ChannelChangesToJson(s.channels);
    out["steps"].push_back(step);
  }
  out["ranking"] = nlohmann::json::array();
  for (const Score& s : report.ranking.scores) {
    out["ranking"].push_back({{"effect", s.name}, {"chi2", JsonNumber(s.chi2)},
                              {"dof", s.dof}, {"p_value", JsonNumber(s.p_value)},
                              {"log10_p_value", JsonNumber(s.log_p_value / std::log(10.0))}});
  }
  out["indistinguishable"] = nlohmann::json::array();
  for (const auto& [a, b] : report.ranking.indistinguishable) {
    out["indistinguishable"].push_back({a, b});
  }
  out["nearly_parallel"] = nlohmann::json::array();
  for (const ParallelPair& q : report.ranking.parallel) {
    out["nearly_parallel"].push_back({{"a", q.a}, {"b", q.b}, {"cosine", JsonNumber(q.cosine)},
                                      {"chi2_a_given_b", JsonNumber(q.chi2_a_given_b)},
                                      {"chi2_b_given_a", JsonNumber(q.chi2_b_given_a)},
                                      {"separated", q.separated}});
  }
  out["stop_reason"] = report.stop_reason;
  out["notes"] = report.notes;
  out["level"] = JsonNumber(report.level);
  out["significance"] = nlohmann::json::array();
  for (const EffectSignificance& w : report.significance) {
    out["significance"].push_back({{"effect", w.effect}, {"chi2", JsonNumber(w.chi2)},
                                   {"dof", w.dof}, {"p_value", JsonNumber(w.p_value)}});
  }
  const ResidualVerdict& v = report.verdict;
  out["verdict"] = v.verdict;
  out["verdict_detail"] = {{"s2", JsonNumber(v.s2)},
                           {"s2_p_value", JsonNumber(v.s2_p_value)},
                           {"tests", v.tests},
                           {"threshold", JsonNumber(v.threshold)},
                           {"channels", v.channels},
                           {"remains", v.remains},
                           {"stand_ins_possible", v.verdict == "incomplete" &&
                                                      !report.selected.empty()}};
  return out;
}

}  // namespace axis
