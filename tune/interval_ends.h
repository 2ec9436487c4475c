// The fit's uncertainty as the tuners check a setting over it (issue 45):
// the identified model with one free parameter at one end of its 95 %
// interval (FitResult's ci95_low / ci95_high, the others at the estimate;
// the discovered effects' parameters included), and each figure's spread
// over those models with the parameter that moves it most.
#ifndef TUNE_INTERVAL_ENDS_H_
#define TUNE_INTERVAL_ENDS_H_

#include <algorithm>
#include <initializer_list>
#include <string>
#include <vector>

#include "estimation/fit_result.h"
#include "sim/config.h"

namespace axis {

// `model` with `parameter` at its interval's low or high end.
struct IntervalEnd {
  std::string parameter;  // MODEL.md name
  bool high = false;
  AxisConfig model;
};

// The ends of every free parameter of `result` with a finite end and a
// name FindParam knows, skipping the names in `skip` (the settings being
// tuned), in the order of result.parameters, low end first; a parameter
// tied to the one moved (ParameterEstimate::tied_to) moves with it. Never
// throws (except std::bad_alloc).
std::vector<IntervalEnd> IntervalEnds(const FitResult& result, const AxisConfig& model,
                                      const std::vector<std::string>& skip);

// A figure over the fit's uncertainty.
struct FigureSpread {
  std::string figure;  // the metric's field name ("settling_time", ...)
  double at_estimate = 0.0;
  double low = 0.0, high = 0.0;  // min and max over the estimate and the ends
  std::string limiting;          // the parameter whose ends move it most ("" if none)
};

// A figure of a metrics struct (StepMetrics, MoveMetrics): its name, as
// FigureSpread::figure, and its field.
template <typename Metrics>
struct FigureField {
  const char* name;
  double Metrics::*field;
};

// The names and the values of `figures` (in their order). Never throw
// (except std::bad_alloc).
template <typename Metrics, size_t N>
std::vector<std::string> FigureNames(const FigureField<Metrics> (&figures)[N]) {
  std::vector<std::string> out;
  for (const FigureField<Metrics>& f : figures) out.push_back(f.name);
  return out;
}
template <typename Metrics, size_t N>
std::vector<double> FigureValues(const Metrics& m, const FigureField<Metrics> (&figures)[N]) {
  std::vector<double> out;
  for (const FigureField<Metrics>& f : figures) out.push_back(m.*f.field);
  return out;
}

// Spreads for `figures` with their values at the estimate (low = high =
// at_estimate), and the widening by one interval end: each finite value
// of `values` (in `figures` order) widens its spread; `moved` (one per
// figure, start at 0) keeps the largest |value − at_estimate| so far and
// `limiting` the parameter that gave it. A `parameter` "" (a sample of the
// joint region, tune/joint_region.h, which moves them all) widens the
// spread without naming a limiting parameter. Never throw (except bad_alloc).
std::vector<FigureSpread> StartSpread(const std::vector<std::string>& figures,
                                      const std::vector<double>& at_estimate);
void WidenSpread(const std::string& parameter, const std::vector<double>& values,
                 std::vector<double>* moved, std::vector<FigureSpread>* spread);

// Widens the band [*low, *high] sample by sample to hold the `channels` of
// `r` (a response with members t, finite and the channels as
// std::vector<double>; a band that is empty takes `r` as it is). Responses
// of another length or not finite are skipped. Never throws (except
// std::bad_alloc).
template <typename Response>
void WidenResponseBand(const Response& r,
                       std::initializer_list<std::vector<double> Response::*> channels,
                       Response* low, Response* high) {
  if (!r.finite) return;
  if (low->t.empty()) {
    *low = r;
    *high = r;
    return;
  }
  if (r.t.size() != low->t.size()) return;
  for (auto channel : channels) {
    std::vector<double>& lo = low->*channel;
    std::vector<double>& hi = high->*channel;
    const std::vector<double>& value = r.*channel;
    for (size_t k = 0; k < value.size(); ++k) {
      lo[k] = std::min(lo[k], value[k]);
      hi[k] = std::max(hi[k], value[k]);
    }
  }
}

// The violations `texts` (with their figures `figures`, one each) of a
// setting on a model other than the estimate, `where` ("V_L at low end"):
// each clears *robust and, unless its figure is already in `broken` at the
// estimate (said once, there), is added to *out as "<where>: <text>".
// Never throws (except std::bad_alloc).
void NoteEndViolations(const std::string& where, const std::vector<std::string>& texts,
                       const std::vector<std::string>& figures,
                       const std::vector<std::string>& broken, bool* robust,
                       std::vector<std::string>* out);

// "<parameter> at <low|high> end". Never throws (except std::bad_alloc).
std::string EndName(const IntervalEnd& end);

}  // namespace axis

#endif  // TUNE_INTERVAL_ENDS_H_
