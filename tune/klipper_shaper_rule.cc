#include "tune/klipper_shaper_rule.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/spectral.h"
#include "sim/experiment.h"
#include "tune/move_response.h"

namespace axis {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Hz, the spacing of the candidate shaper frequencies (Klipper prints its
// fits to 0.1 Hz).
constexpr double kFrequencyStep = 0.2;
// Hz, the Welch resolution aimed at: the largest power-of-two segment no
// finer than this.
constexpr double kResolution = 0.5;
// s, the grid on which a candidate's smoothing is read.
constexpr double kSmoothingGrid = 1e-3;
// Per shaper, the frequencies whose remaining vibration is within this
// factor (and kVibrationSlack) of the shaper's least are "as good" on
// vibration; the least score among them is its fit.
constexpr double kVibrationFactor = 1.2;
constexpr double kVibrationSlack = 0.01;
// Shapers whose score is within this factor of the lowest tie; the one with
// the least smoothing among them is recommended.
constexpr double kScoreTie = 1.2;

// The swept vibration: phase φ(t) = 2π(f0·t + ½·r·t²), frequency
// f(t) = f0 + r·t, position −(A(t)/ω(t)²)·sin φ with A = accel_per_hz·f
// (its second derivative is A·sin φ to within terms of order r/f²).
double SweptPosition(const KlipperRuleSettings& s, double t) {
  const double f = s.min_freq + s.hz_per_sec * t;
  const double w = 2.0 * kPi * f;
  const double phase = 2.0 * kPi * (s.min_freq * t + 0.5 * s.hz_per_sec * t * t);
  return -(s.accel_per_hz * f) / (w * w) * std::sin(phase);
}

double SweptAcceleration(const KlipperRuleSettings& s, double t) {
  const double f = s.min_freq + s.hz_per_sec * t;
  const double phase = 2.0 * kPi * (s.min_freq * t + 0.5 * s.hz_per_sec * t * t);
  return s.accel_per_hz * f * std::sin(phase);
}

// The PSD-weighted remaining vibration of `shaper` over the spectrum, the
// largest over the test damping ratios.
double RemainingVibration(const ResonanceSpectrum& spectrum, double total,
                          const InputShaper& shaper, const std::vector<double>& dampings) {
  double worst = 0.0;
  for (double zeta : dampings) {
    double left = 0.0;
    for (size_t k = 0; k < spectrum.frequency.size(); ++k) {
      left += spectrum.psd[k] * ShaperVibration(shaper, spectrum.frequency[k], zeta);
    }
    worst = std::max(worst, left / total);
  }
  return worst;
}

}  // namespace

double KlipperScore(double vibration, double smoothing) {
  return smoothing * (std::pow(vibration, 1.5) + 0.2 * vibration + 0.01);
}

size_t RecommendShaper(const std::vector<KlipperShaperFit>& fitted) {
  if (fitted.empty()) throw std::invalid_argument("RecommendShaper: expected fits, got none");
  size_t lowest = 0;
  for (size_t k = 1; k < fitted.size(); ++k) {
    if (fitted[k].score < fitted[lowest].score) lowest = k;
  }
  size_t out = lowest;
  for (size_t k = 0; k < fitted.size(); ++k) {
    if (fitted[k].score <= kScoreTie * fitted[lowest].score &&
        fitted[k].smoothing < fitted[out].smoothing) {
      out = k;
    }
  }
  return out;
}

double KlipperHighestFrequency(const ControllerConfig& controller) {
  return 0.25 / controller.T_s;
}

ResonanceSpectrum SimulateResonanceTest(const AxisConfig& model,
                                        const ControllerConfig& controller, double step,
                                        const KlipperRuleSettings& test) {
  if (!(step > 0.0 && test.min_freq > 0.0 && test.max_freq > test.min_freq &&
        test.accel_per_hz > 0.0 && test.hz_per_sec > 0.0)) {
    throw std::invalid_argument(
        "SimulateResonanceTest: expected step > 0, 0 < min_freq < max_freq, accel_per_hz > 0 "
        "and hz_per_sec > 0");
  }
  if (test.max_freq > KlipperHighestFrequency(controller)) {
    throw std::invalid_argument(
        "tune.move.klipper.max_freq: expected at most a quarter of the controller's sample "
        "rate (" + std::to_string(KlipperHighestFrequency(controller)) +
        " Hz: the sweep is read every T_s), "
        "got " + std::to_string(test.max_freq) + " Hz");
  }
  const double duration = (test.max_freq - test.min_freq) / test.hz_per_sec;
  ExperimentConfig e;
  e.model = model;
  e.drive.closed_loop = true;
  e.drive.controller = controller;
  e.drive.reference.kind = Reference::Kind::kTable;
  InputSignal& table = e.drive.reference.table;
  table.kind = InputSignal::Kind::kTable;
  for (long k = 0; k * controller.T_s <= duration + controller.T_s; ++k) {
    table.times.push_back(k * controller.T_s);
    table.values.push_back(SweptPosition(test, k * controller.T_s));
  }
  e.options.step = step;
  e.options.output_period =
      step * std::max(1.0, std::floor(1.0 / (4.0 * test.max_freq * step)));
  e.options.duration = e.options.output_period * std::floor(duration / e.options.output_period);
  e.options.channels = {Channel::kA};
  e.initial_state = ConsistentInitialState(model, AxisState<double>::Zero());
  const Trace<double> trace = RunExperiment(e);
  if (!trace.finite) {
    throw std::runtime_error("the resonance test left the finite numbers on the identified model");
  }
  std::vector<double> command(trace.t.size());
  for (size_t k = 0; k < trace.t.size(); ++k) command[k] = SweptAcceleration(test, trace.t[k]);
  WelchOptions welch;
  welch.segment_length = 16;
  while (welch.segment_length * e.options.output_period < 1.0 / kResolution) {
    welch.segment_length *= 2;
  }
  while (welch.segment_length > 16 &&
         WelchSegmentCount(trace.t.size(), welch.segment_length) < 8) {
    welch.segment_length /= 2;
  }
  const WelchSpectra spectra =
      ComputeWelchSpectra(command, trace[Channel::kA], e.options.output_period, welch);
  ResonanceSpectrum out;
  out.seconds = e.options.duration;
  out.averages = spectra.averages;
  for (size_t k = 0; k < spectra.frequency.size(); ++k) {
    if (spectra.frequency[k] < test.min_freq || spectra.frequency[k] > test.max_freq) continue;
    out.frequency.push_back(spectra.frequency[k]);
    out.psd.push_back(spectra.yy[k]);
  }
  return out;
}

KlipperShaperChoice ChooseShaperAsKlipper(const ResonanceSpectrum& spectrum,
                                          const Reference& move,
                                          const KlipperRuleSettings& rule) {
  double total = 0.0;
  for (double p : spectrum.psd) total += p;
  if (spectrum.frequency.empty() || !(total > 0.0)) {
    throw std::invalid_argument("ChooseShaperAsKlipper: expected a spectrum with power, got " +
                                std::string(spectrum.frequency.empty() ? "no bins" : "none"));
  }
  Reference shaped = move;
  KlipperShaperChoice out;
  for (size_t t = 1; t < ShaperNames().size(); ++t) {
    const ShaperType type = static_cast<ShaperType>(t);
    std::vector<KlipperShaperFit> candidates;
    double least = HUGE_VAL;
    for (double f = rule.min_freq; f <= rule.max_freq + 1e-9; f += kFrequencyStep) {
      shaped.shaper = MakeInputShaper(type, f, rule.design_damping);
      const double v = RemainingVibration(spectrum, total, shaped.shaper, rule.test_damping);
      const double smoothing = MoveSmoothing(shaped, kSmoothingGrid);
      candidates.push_back({type, f, v, smoothing, KlipperScore(v, smoothing)});
      least = std::min(least, v);
    }
    KlipperShaperFit best;
    best.score = HUGE_VAL;
    for (const KlipperShaperFit& c : candidates) {
      if (c.vibration <= kVibrationFactor * least + kVibrationSlack && c.score < best.score) {
        best = c;
      }
    }
    out.fitted.push_back(best);
  }
  out.recommended = RecommendShaper(out.fitted);
  const KlipperShaperFit& chosen = out.fitted[out.recommended];
  out.shaper = MakeInputShaper(chosen.type, chosen.frequency, rule.design_damping);
  return out;
}

}  // namespace axis
