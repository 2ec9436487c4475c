#include "tune/analog_loop_tuning.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include <boost/math/tools/minima.hpp>

#include "estimation/at_estimate.h"
#include "sim/linear_model.h"
#include "tune/joint_region.h"

namespace axis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Brent's minimiser on log T_p: bits of precision and iterations (the
// settling time is resolved to the 100 µs output period; 0.1 % of T_p is
// well below what a preamp's capacitor sets).
constexpr int kBrentBits = 10;
constexpr int kBrentIterations = 30;

// The figures of StepMetrics in TunedSetting::spread order.
constexpr FigureField<StepMetrics> kFigures[] = {
    {"settling_time", &StepMetrics::settling_time},
    {"overshoot", &StepMetrics::overshoot},
    {"peak_current", &StepMetrics::peak_current},
    {"voltage_headroom", &StepMetrics::voltage_headroom},
    {"ringing", &StepMetrics::ringing},
    {"ringing_decay", &StepMetrics::ringing_decay}};

// How far `m` is outside the spec: the sum over the bounds of the relative
// excess (0 when it meets them all; 1 for an unmeasured figure).
double Violation(const StepMetrics& m, const TuneSpec& s) {
  double v = 0.0;
  const auto add = [&v](double value, double bound, bool upper) {
    if (std::isnan(bound)) return;
    if (std::isnan(value)) {
      v += 1.0;
      return;
    }
    const double scale = std::max(std::abs(bound), 1e-12);
    v += std::max(0.0, upper ? (value - bound) / scale : (bound - value) / scale);
  };
  add(m.settled ? m.settling_time : kNaN, s.max_settling_time, true);
  add(m.overshoot, s.max_overshoot, true);
  add(m.peak_current, s.max_current, true);
  add(m.voltage_headroom, s.min_voltage_headroom, false);
  add(m.ringing, s.max_ringing, true);
  add(m.ringing_decay, s.max_ringing_decay, true);
  return v;
}

// The search's objective: the settling time (the run's length if it does
// not settle) plus the run's length per unit of violation, so that any
// setting that meets the spec beats any that does not.
double Objective(const StepMetrics& m, const TuneSpec& s) {
  const double ts = std::isfinite(m.settling_time) && m.settled ? m.settling_time : s.duration;
  return ts + s.duration * Violation(m, s);
}

class AnalogLoopTuner {
 public:
  AnalogLoopTuner(const EstimationProblem& job, const FitResult& result, const TuneSettings& tune)
      : job_(job), result_(result), settings_(tune), spec_(tune.spec) {}

  AnalogLoopTuning Run() {
    const auto start = std::chrono::steady_clock::now();
    if (!Prepare()) return out_;
    TradeOffCurve();
    Refine(Best());
    Judge(&out_.current);
    Judge(&out_.proposed);
    out_.ran = true;
    out_.simulations = simulations_;
    out_.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out_;
  }

 private:
  // The model at the estimate, the step, K_1 for the velocity gain.
  bool Prepare() {
    out_.spec = spec_;
    model_ = AtEstimate(job_, result_).model;
    if (model_.structure.amplifier != Amplifier::kAnalogVelocityLoop) {
      out_.note = "no tuning: the model's amplifier is not the analog velocity loop "
                  "(amplifier: analog_velocity_loop), whose K_1 and T_p are tuned";
      return false;
    }
    if (job_.experiments.empty()) throw std::runtime_error("the job has no fitted experiment");
    step_ = job_.experiments.front().options.step;
    out_.K2 = model_.params.K2;
    out_.current.K1 = model_.params.K1;
    out_.current.T_p = model_.params.T_p;
    out_.proposed.K1 = model_.params.K1;
    if (std::isfinite(spec_.velocity_gain)) {
      const double gain = model_.params.r_g * SteadyStateGain(model_.params);
      if (!(gain > 0.0)) throw std::runtime_error("the model's velocity gain is not positive");
      out_.proposed.K1 = model_.params.K1 * spec_.velocity_gain / gain;
    }
    const StepMetrics now = Measure(model_.params.K1, model_.params.T_p, model_);
    if (std::isnan(now.final_velocity)) {
      throw std::runtime_error("the identified model's step response is not finite");
    }
    return true;
  }

  StepMetrics Measure(double K1, double T_p, AxisConfig model) {
    model.params.K1 = K1;
    model.params.T_p = T_p;
    ++simulations_;
    return MeasureStep(SimulateStep(model, step_, spec_), spec_, model.params.V_M);
  }

  // The paper's series of steps: T_p from T_p_high down to T_p_low.
  void TradeOffCurve() {
    const int n = settings_.curve_points;
    const double a = std::log(settings_.T_p_high), b = std::log(settings_.T_p_low);
    for (int k = 0; k < n; ++k) {
      TuningPoint p;
      p.T_p = std::exp(a + (b - a) * k / (n - 1));
      p.metrics = Measure(out_.proposed.K1, p.T_p, model_);
      p.violations = SpecViolations(p.metrics, spec_);
      out_.curve.push_back(std::move(p));
    }
  }

  // The grid index with the lowest objective (the first of equals: the
  // largest T_p, the gentlest preamp, among settings alike).
  size_t Best() const {
    size_t best = 0;
    for (size_t k = 1; k < out_.curve.size(); ++k) {
      if (Objective(out_.curve[k].metrics, spec_) < Objective(out_.curve[best].metrics, spec_)) {
        best = k;
      }
    }
    return best;
  }

  // Brent between the neighbours of grid point k; the better of its answer
  // and the grid point.
  void Refine(size_t k) {
    const std::vector<TuningPoint>& c = out_.curve;
    const double lo = std::log(c[std::min(k + 1, c.size() - 1)].T_p);
    const double hi = std::log(c[k == 0 ? 0 : k - 1].T_p);
    double best_tp = c[k].T_p;
    double best_j = Objective(c[k].metrics, spec_);
    if (hi > lo) {
      const auto f = [this](double log_tp) {
        return Objective(Measure(out_.proposed.K1, std::exp(log_tp), model_), spec_);
      };
      std::uintmax_t iterations = kBrentIterations;
      const std::pair<double, double> r =
          boost::math::tools::brent_find_minima(f, lo, hi, kBrentBits, iterations);
      if (r.second < best_j) {
        best_tp = std::exp(r.first);
        best_j = r.second;
      }
    }
    out_.proposed.T_p = best_tp;
  }

  // The setting at the estimate and at each end of each free parameter's
  // interval (K_1 and T_p, the settings, excepted).
  void Judge(TunedSetting* s) {
    AxisConfig model = model_;
    model.params.K1 = s->K1;
    model.params.T_p = s->T_p;
    ++simulations_;
    s->response = SimulateStep(model, step_, spec_);
    s->metrics = MeasureStep(s->response, spec_, model.params.V_M);
    WidenBand(s->response, &s->band_low, &s->band_high);
    s->violations = SpecViolations(s->metrics, spec_);
    const std::vector<std::string> broken = ViolatedFigures(s->metrics, spec_);
    s->robust = s->violations.empty();
    s->spread = StartSpread(FigureNames(kFigures), FigureValues(s->metrics, kFigures));
    std::vector<double> moved(std::size(kFigures), 0.0);
    for (const IntervalEnd& end : IntervalEnds(result_, model, {"T_p", "K1"})) {
      ++simulations_;
      const StepResponse r = SimulateStep(end.model, step_, spec_);
      WidenBand(r, &s->band_low, &s->band_high);
      const StepMetrics m = MeasureStep(r, spec_, end.model.params.V_M);
      NoteEndViolations(EndName(end), SpecViolations(m, spec_), ViolatedFigures(m, spec_), broken,
                        &s->robust, &s->robust_violations);
      WidenSpread(end.parameter, FigureValues(m, kFigures), &moved, &s->spread);
    }
    for (const RegionSample& sample :
         JointRegionSamples(result_, model, {"T_p", "K1"}, job_.free, settings_.samples)) {
      ++simulations_;
      const StepResponse r = SimulateStep(sample.model, step_, spec_);
      WidenBand(r, &s->band_low, &s->band_high);
      const StepMetrics m = MeasureStep(r, spec_, sample.model.params.V_M);
      const std::vector<std::string> violations = SpecViolations(m, spec_);
      ++s->samples;
      s->samples_met += violations.empty();
      if (s->samples - s->samples_met > 1) {
        s->robust = false;  // an earlier sample broke it and was noted
      } else {
        NoteEndViolations(sample.name, violations, ViolatedFigures(m, spec_), broken, &s->robust,
                          &s->robust_violations);
      }
      WidenSpread("", FigureValues(m, kFigures), &moved, &s->spread);
    }
  }

  const EstimationProblem& job_;
  const FitResult& result_;
  const TuneSettings& settings_;
  const TuneSpec& spec_;
  AxisConfig model_;
  double step_ = 0.0;
  int simulations_ = 0;
  AnalogLoopTuning out_;
};

}  // namespace

AnalogLoopTuning TuneAnalogLoop(const EstimationProblem& job, const FitResult& result,
                                const TuneSettings& tune) {
  return AnalogLoopTuner(job, result, tune).Run();
}

std::vector<std::string> ViolationsOn(const AxisConfig& axis, double step, const TunedSetting& s,
                                      const TuneSpec& spec) {
  AxisConfig model = axis;
  model.params.K1 = s.K1;
  model.params.T_p = s.T_p;
  return SpecViolations(MeasureStep(SimulateStep(model, step, spec), spec, model.params.V_M),
                        spec);
}

}  // namespace axis
