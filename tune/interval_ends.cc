#include "tune/interval_ends.h"

#include <algorithm>
#include <cmath>

#include "estimation/parameter_tie.h"

namespace axis {

std::vector<IntervalEnd> IntervalEnds(const FitResult& result, const AxisConfig& model,
                                      const std::vector<std::string>& skip) {
  std::vector<IntervalEnd> out;
  for (const ParameterEstimate& e : result.parameters) {
    if (!e.free || std::find(skip.begin(), skip.end(), e.name) != skip.end()) continue;
    for (const bool high : {false, true}) {
      const double end = high ? e.ci95_high : e.ci95_low;
      if (!std::isfinite(end)) continue;
      IntervalEnd ie{e.name, high, model};
      double* p = FindParam(&ie.model.params, e.name);
      if (p == nullptr) continue;
      *p = end;
      ApplyResultTies(result, &ie.model.params);
      out.push_back(std::move(ie));
    }
  }
  return out;
}

std::vector<FigureSpread> StartSpread(const std::vector<std::string>& figures,
                                      const std::vector<double>& at_estimate) {
  std::vector<FigureSpread> out;
  for (size_t f = 0; f < figures.size(); ++f) {
    out.push_back({figures[f], at_estimate[f], at_estimate[f], at_estimate[f], ""});
  }
  return out;
}

void WidenSpread(const std::string& parameter, const std::vector<double>& values,
                 std::vector<double>* moved, std::vector<FigureSpread>* spread) {
  for (size_t f = 0; f < spread->size() && f < values.size(); ++f) {
    const double x = values[f];
    FigureSpread& fs = (*spread)[f];
    if (!std::isfinite(x)) continue;
    fs.low = std::min(fs.low, x);
    fs.high = std::max(fs.high, x);
    const double d = std::abs(x - fs.at_estimate);
    if (!parameter.empty() && d > (*moved)[f]) {
      (*moved)[f] = d;
      fs.limiting = parameter;
    }
  }
}

void NoteEndViolations(const std::string& where, const std::vector<std::string>& texts,
                       const std::vector<std::string>& figures,
                       const std::vector<std::string>& broken, bool* robust,
                       std::vector<std::string>* out) {
  for (size_t v = 0; v < texts.size(); ++v) {
    *robust = false;
    if (v < figures.size() &&
        std::find(broken.begin(), broken.end(), figures[v]) != broken.end()) {
      continue;
    }
    out->push_back(where + ": " + texts[v]);
  }
}

std::string EndName(const IntervalEnd& end) {
  return end.parameter + " at " + (end.high ? "high" : "low") + " end";
}

}  // namespace axis
