#include "tune/step_response.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "sim/experiment.h"
#include "sim/simulate.h"
#include "tune/interval_ends.h"

namespace axis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Output period of a step response (SimulateStep).
constexpr double kOutputPeriod = 1e-4;  // s

std::vector<double> Values(const Trace<double>& trace, Channel c) {
  return trace[c];
}

// Mean of the last 5 % of `v` (at least one sample).
double TailMean(const std::vector<double>& v) {
  const size_t n = std::max<size_t>(1, v.size() / 20);
  double sum = 0.0;
  for (size_t k = v.size() - n; k < v.size(); ++k) sum += v[k];
  return sum / static_cast<double>(n);
}

// RingingDecay of StepMetrics: the e-folding time of the local maxima of
// d = |v − vf| from sample `from` on.
double RingingDecay(const StepResponse& r, double vf, size_t from) {
  const double floor = 1e-4 * std::abs(vf);
  std::vector<double> t, ln;
  for (size_t k = std::max<size_t>(from, 1); k + 1 < r.v.size(); ++k) {
    const double d = std::abs(r.v[k] - vf);
    if (d > floor && d >= std::abs(r.v[k - 1] - vf) && d > std::abs(r.v[k + 1] - vf)) {
      t.push_back(r.t[k]);
      ln.push_back(std::log(d));
    }
  }
  const size_t n = t.size();
  if (n < 3) return kNaN;
  double mt = 0.0, ml = 0.0;
  for (size_t k = 0; k < n; ++k) {
    mt += t[k] / n;
    ml += ln[k] / n;
  }
  double stt = 0.0, stl = 0.0;
  for (size_t k = 0; k < n; ++k) {
    stt += (t[k] - mt) * (t[k] - mt);
    stl += (t[k] - mt) * (ln[k] - ml);
  }
  const double slope = stl / stt;
  return slope < 0.0 ? -1.0 / slope : std::numeric_limits<double>::infinity();
}

std::string Figure(double x) {
  std::ostringstream out;
  out.precision(3);
  out << x;
  return out.str();
}

}  // namespace

StepResponse SimulateStep(const AxisConfig& model, double step, const TuneSpec& spec) {
  ExperimentConfig e;
  e.model = model;
  e.drive.input.kind = InputSignal::Kind::kStep;
  e.drive.input.amplitude = spec.step_voltage;
  e.drive.input.start = 0.0;
  e.options.duration = spec.duration;
  e.options.step = step;
  e.options.output_period = step * std::max(1.0, std::round(kOutputPeriod / step));
  e.options.channels = {Channel::kX, Channel::kV, Channel::kI, Channel::kVm, Channel::kFg};
  e.initial_state = ConsistentInitialState(model, AxisState<double>::Zero());
  const Trace<double> trace = RunExperiment(e);
  StepResponse r;
  r.t = trace.t;
  r.x = Values(trace, Channel::kX);
  r.v = Values(trace, Channel::kV);
  r.i = Values(trace, Channel::kI);
  r.vm = Values(trace, Channel::kVm);
  r.fg = Values(trace, Channel::kFg);
  r.finite = trace.finite;
  return r;
}

void WidenBand(const StepResponse& r, StepResponse* low, StepResponse* high) {
  WidenResponseBand(r,
                    {&StepResponse::x, &StepResponse::v, &StepResponse::i, &StepResponse::vm,
                     &StepResponse::fg},
                    low, high);
}

StepMetrics MeasureStep(const StepResponse& r, const TuneSpec& spec, double V_M) {
  StepMetrics m;
  const size_t n = r.v.size();
  if (!r.finite || n < 2 || r.t.size() != n) {
    return {kNaN, kNaN, false, kNaN, kNaN, kNaN, kNaN, kNaN};
  }
  m.final_velocity = TailMean(r.v);
  const double vf = m.final_velocity;
  if (!(vf > 0.0)) return {vf, kNaN, false, kNaN, kNaN, kNaN, kNaN, kNaN};
  const double band = spec.settling_band * vf;
  size_t last_out = n;  // index of the last sample outside the band
  size_t first_in = n;  // index of the first sample inside it
  double v_max = r.v[0];
  for (size_t k = 0; k < n; ++k) {
    const bool outside = std::abs(r.v[k] - vf) > band;
    if (outside) last_out = k;
    if (!outside && first_in == n) first_in = k;
    v_max = std::max(v_max, r.v[k]);
  }
  m.settled = last_out != n - 1;
  m.settling_time = last_out == n ? 0.0 : m.settled ? r.t[last_out + 1] : r.t[n - 1];
  m.overshoot = std::max(0.0, (v_max - vf) / vf);
  m.peak_current = 0.0;
  double vm_max = 0.0;
  for (size_t k = 0; k < n; ++k) {
    m.peak_current = std::max(m.peak_current, std::abs(r.i[k]));
    vm_max = std::max(vm_max, std::abs(r.vm[k]));
  }
  m.voltage_headroom = V_M - vm_max;
  m.ringing = kNaN;
  if (first_in < n && r.t[first_in] + spec.ringing_after <= r.t[n - 1]) {
    m.ringing = 0.0;
    for (size_t k = first_in; k < n; ++k) {
      if (r.t[k] >= r.t[first_in] + spec.ringing_after) {
        m.ringing = std::max(m.ringing, std::abs(r.v[k] - vf));
      }
    }
  }
  m.ringing_decay = first_in < n ? RingingDecay(r, vf, first_in) : kNaN;
  return m;
}

namespace {

// Each bound of `spec` that `m` does not meet: its figure's name and the
// phrase (SpecViolations, ViolatedFigures).
std::vector<std::pair<std::string, std::string>> Violations(const StepMetrics& m,
                                                            const TuneSpec& spec) {
  std::vector<std::pair<std::string, std::string>> out;
  // One bound: `bound` set (not NaN) and `value` not on its side.
  const auto check = [&out](const char* figure, const char* what, double value, double bound,
                            bool upper, const char* unit) {
    if (std::isnan(bound)) return;
    if (std::isnan(value)) {
      out.emplace_back(figure, std::string(what) + " not measured");
    } else if (upper ? value > bound : value < bound) {
      out.emplace_back(figure, std::string(what) + " " + Figure(value) + unit +
                                   (upper ? " > " : " < ") + Figure(bound) + unit);
    }
  };
  check("settling_time", "settling time", m.settled ? m.settling_time : kNaN,
        spec.max_settling_time, true, " s");
  check("overshoot", "overshoot", m.overshoot, spec.max_overshoot, true, "");
  check("peak_current", "peak current", m.peak_current, spec.max_current, true, " A");
  check("voltage_headroom", "voltage headroom", m.voltage_headroom, spec.min_voltage_headroom,
        false, " V");
  check("ringing", "residual vibration", m.ringing, spec.max_ringing, true, " m/s");
  check("ringing_decay", "ringing decay time", m.ringing_decay, spec.max_ringing_decay, true,
        " s");
  return out;
}

}  // namespace

std::vector<std::string> SpecViolations(const StepMetrics& m, const TuneSpec& spec) {
  std::vector<std::string> out;
  for (const auto& v : Violations(m, spec)) out.push_back(v.second);
  return out;
}

std::vector<std::string> ViolatedFigures(const StepMetrics& m, const TuneSpec& spec) {
  std::vector<std::string> out;
  for (const auto& v : Violations(m, spec)) out.push_back(v.first);
  return out;
}

}  // namespace axis
