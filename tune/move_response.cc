#include "tune/move_response.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/format.h"
#include "sim/experiment.h"
#include "tune/interval_ends.h"

namespace axis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kOutputPeriod = 1e-4;  // s, as the step response's

// One bound of MoveSpec: the figure's name, its field, the phrase, the unit.
struct MoveBound {
  const char* figure;
  double MoveMetrics::*value;
  double MoveSpec::*bound;
  const char* phrase;
  const char* unit;
};
constexpr MoveBound kBounds[] = {
    {"settling_time", &MoveMetrics::settling_time, &MoveSpec::max_settling_time,
     "settling time after the move", "s"},
    {"following_error", &MoveMetrics::following_error, &MoveSpec::max_following_error,
     "following error", "m"},
    {"overshoot", &MoveMetrics::overshoot, &MoveSpec::max_overshoot, "overshoot", "m"},
    {"peak_current", &MoveMetrics::peak_current, &MoveSpec::max_current, "peak current", "A"},
    {"ringing", &MoveMetrics::ringing, &MoveSpec::max_ringing, "residual vibration", "m"},
};

// The figure checked against its bound: NaN where the move did not settle
// (the settling time is then not a time).
double Checked(const MoveMetrics& m, const MoveBound& b) {
  if (b.value == &MoveMetrics::settling_time && !m.settled) return kNaN;
  return m.*b.value;
}

}  // namespace

MoveResponse SimulateMove(const AxisConfig& model, const ControllerConfig& controller,
                          const Reference& reference, double step, double settle) {
  if (reference.kind == Reference::Kind::kTable) {
    throw std::invalid_argument("SimulateMove: the reference is a table, not a move");
  }
  ExperimentConfig e;
  e.model = model;
  e.drive.closed_loop = true;
  e.drive.controller = controller;
  e.drive.reference = reference;
  MoveResponse r;
  r.move_duration = reference.MoveDuration();
  r.target = reference.origin + reference.distance;
  e.options.step = step;
  e.options.output_period = step * std::max(1.0, std::round(kOutputPeriod / step));
  e.options.duration =
      e.options.output_period * std::ceil((r.move_duration + settle) / e.options.output_period);
  e.options.channels = {Channel::kX, Channel::kV, Channel::kI, Channel::kU, Channel::kFg,
                        Channel::kXRef};
  AxisState<double> y0 = AxisState<double>::Zero();
  e.initial_state = ConsistentInitialState(model, y0);
  const Trace<double> trace = RunExperiment(e);
  r.t = trace.t;
  r.x_ref = trace[Channel::kXRef];
  r.x = trace[Channel::kX];
  r.v = trace[Channel::kV];
  r.i = trace[Channel::kI];
  r.u = trace[Channel::kU];
  r.fg = trace[Channel::kFg];
  r.finite = trace.finite;
  return r;
}

void WidenMoveBand(const MoveResponse& r, MoveResponse* low, MoveResponse* high) {
  WidenResponseBand(r,
                    {&MoveResponse::x, &MoveResponse::v, &MoveResponse::i, &MoveResponse::u,
                     &MoveResponse::fg},
                    low, high);
}

MoveMetrics MeasureMove(const MoveResponse& r, const MoveSpec& spec) {
  MoveMetrics m;
  const size_t n = r.t.size();
  if (!r.finite || n == 0) {
    m = {kNaN, false, kNaN, kNaN, kNaN, kNaN, kNaN};
    return m;
  }
  const double sign = r.target >= r.x.front() ? 1.0 : -1.0;
  size_t last_out = n;  // the last sample outside the band
  for (size_t k = 0; k < n; ++k) {
    const double d = r.x[k] - r.target;
    if (std::abs(d) > spec.position_band) last_out = k;
    m.overshoot = std::max(m.overshoot, sign * d);
    m.peak_current = std::max(m.peak_current, std::abs(r.i[k]));
    if (r.t[k] <= r.move_duration) {
      m.following_error = std::max(m.following_error, std::abs(r.x_ref[k] - r.x[k]));
    }
  }
  m.settled = last_out != n - 1;
  m.move_time = last_out == n ? 0.0 : (m.settled ? r.t[last_out + 1] : r.t.back());
  m.settling_time = std::max(0.0, m.move_time - r.move_duration);
  const double from = r.move_duration + spec.ringing_after;
  m.ringing = from > r.t.back() ? kNaN : 0.0;
  for (size_t k = 0; k < n; ++k) {
    if (r.t[k] >= from) m.ringing = std::max(m.ringing, std::abs(r.x[k] - r.target));
  }
  return m;
}

double ResidualVibrationFrequency(const MoveResponse& r, double floor) {
  const size_t n = r.t.size();
  if (!r.finite || n == 0) return kNaN;
  size_t first = 0;
  while (first < n && r.t[first] <= r.move_duration) ++first;
  if (n - first < 4) return kNaN;
  double mean = 0.0;
  for (size_t k = first; k < n; ++k) mean += r.x[k];
  mean /= static_cast<double>(n - first);
  double swing = 0.0;
  for (size_t k = first; k < n; ++k) swing = std::max(swing, std::abs(r.x[k] - mean));
  if (!(swing > floor)) return kNaN;
  std::vector<double> crossings;
  for (size_t k = first + 1; k < n; ++k) {
    const double a = r.x[k - 1] - mean, b = r.x[k] - mean;
    if ((a < 0.0) != (b < 0.0)) {
      crossings.push_back(r.t[k - 1] + (r.t[k] - r.t[k - 1]) * a / (a - b));
    }
  }
  if (crossings.size() < 3) return kNaN;
  return static_cast<double>(crossings.size() - 1) /
         (2.0 * (crossings.back() - crossings.front()));
}

double MoveSmoothing(const Reference& reference, double dt) {
  if (reference.shaper.type == ShaperType::kNone || !(dt > 0.0)) return 0.0;
  double centroid = 0.0;
  for (size_t i = 0; i < reference.shaper.amplitudes.size(); ++i) {
    centroid += reference.shaper.amplitudes[i] * reference.shaper.times[i];
  }
  const double end = reference.start + reference.MoveDuration();
  double out = 0.0;
  for (double t = reference.start; t <= end + dt; t += dt) {
    out = std::max(out,
                   std::abs(reference.Profile(t) - reference.UnshapedProfile(t - centroid)));
  }
  return out;
}

std::vector<std::string> MoveViolations(const MoveMetrics& m, const MoveSpec& spec) {
  std::vector<std::string> out;
  for (const MoveBound& b : kBounds) {
    const double bound = spec.*b.bound;
    if (std::isnan(bound)) continue;
    const double x = Checked(m, b);
    if (std::isnan(x)) {
      out.push_back(std::string(b.phrase) + " not measured" +
                    (b.value == &MoveMetrics::settling_time ? " (the move does not settle)"
                                                            : ""));
    } else if (x > bound) {
      out.push_back(std::string(b.phrase) + " " + FormatNumber(x, 4) + " " + b.unit + " > " +
                    FormatNumber(bound, 4) + " " + b.unit);
    }
  }
  return out;
}

std::vector<std::string> MoveViolatedFigures(const MoveMetrics& m, const MoveSpec& spec) {
  std::vector<std::string> out;
  for (const MoveBound& b : kBounds) {
    const double bound = spec.*b.bound;
    if (std::isnan(bound)) continue;
    const double x = Checked(m, b);
    if (std::isnan(x) || x > bound) out.push_back(b.figure);
  }
  return out;
}

double MoveViolation(const MoveMetrics& m, const MoveSpec& spec) {
  double v = 0.0;
  for (const MoveBound& b : kBounds) {
    const double bound = spec.*b.bound;
    if (std::isnan(bound)) continue;
    const double x = Checked(m, b);
    if (std::isnan(x)) {
      v += 1.0;
      continue;
    }
    // A bound of 0 (no overshoot, no settling after the move) counts its
    // excess in mm or ms.
    v += std::max(0.0, (x - bound) / std::max(std::abs(bound), 1e-3));
  }
  return v;
}

}  // namespace axis
