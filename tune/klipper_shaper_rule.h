// Klipper's choice of input shaper, re-implemented from its documentation
// (Klipper docs/Measuring_Resonances.md and docs/Config_Reference.md
// [resonance_tester]; not from its code), so that the shaper tune.move
// proposes can be set beside the one Klipper's rule would pick on the same
// identified axis (tune.move.klipper:, tune/tune_settings.h;
// docs/tuning.md).
//
// 1. The resonance test (TEST_RESONANCES): the axis, under its position
//    controller, vibrates at a frequency that rises from min_freq to
//    max_freq at hz_per_sec, with an acceleration amplitude of
//    accel_per_hz·f; an accelerometer on the carriage records the arm's
//    acceleration. Here it is simulated on the identified model
//    (SimulateResonanceTest) and its power spectral density estimated by
//    Welch's method (common/spectral.h).
// 2. The fit of each shaper (ZV, MZV, ZVD, EI, 2HUMP_EI, 3HUMP_EI) designed
//    at Klipper's default damping ratio 0.1: for each candidate frequency
//    every 0.2 Hz over the test's range, the remaining vibration v — read
//    here as the test spectrum's share left after shaping, the PSD-weighted
//    mean of the shaper's residual vibration ShaperVibration(f, ζ) over the
//    test's bins, the largest over the damping ratios ζ ∈ {0.075, 0.1,
//    0.15} — and the smoothing s (MoveSmoothing of the move, m: Klipper's
//    own smoothing figure is "abstract"; the score is proportional to it,
//    so its unit does not change the choice); the score
//    s·(v^1.5 + 0.2·v + 0.01) (as issue 59 quotes Klipper's heuristic).
//    The docs say the fit "tries not to exacerbate the smoothing, but at
//    the same time ... minimize the resulting vibrations": the shaper's
//    fitted frequency is the lowest score among the frequencies whose v is
//    within 1.2·v_min + 1 % of the shaper's least.
// 3. The recommended shaper: among the fitted shapers whose score is within
//    20 % of the lowest, the one with the least smoothing — which
//    reproduces the three recommendations the docs print
//    (Measuring_Resonances.md: 2HUMP_EI, 3HUMP_EI with max_smoothing, and
//    MZV at a score of 0.00234 against 2HUMP_EI's 0.00234;
//    tests/input_shaper_test.cc).
#ifndef TUNE_KLIPPER_SHAPER_RULE_H_
#define TUNE_KLIPPER_SHAPER_RULE_H_

#include <string>
#include <vector>

#include "sim/config.h"
#include "sim/controller.h"
#include "sim/input_shaper.h"
#include "tune/tune_settings.h"

namespace axis {

// The power spectral density of the resonance test's accelerometer.
struct ResonanceSpectrum {
  std::vector<double> frequency;  // Hz, the Welch bins in [min_freq, max_freq]
  std::vector<double> psd;        // (m/s²)²/Hz, the arm acceleration's
  double seconds = 0.0;           // s, the test's length
  int averages = 0;               // Welch segments
};

// The resonance test of `test` on `model` under `controller` (MODEL.md §5;
// the model's own is ignored), from rest at x = 0, simulated by RK4 at
// `step` (s, > 0) and recorded at the largest multiple of `step` that
// samples max_freq at least four times a period; the reference is the
// swept vibration (amplitude accel_per_hz·f/(2πf)²) read by the controller
// at every control sample. Throws std::invalid_argument for settings out of
// range (those ParseTuneSettings checks) or a max_freq above a quarter of
// the controller's sample rate 1/T_s (the sweep is read every T_s), and
// std::runtime_error if the simulated test leaves the finite numbers.
ResonanceSpectrum SimulateResonanceTest(const AxisConfig& model,
                                        const ControllerConfig& controller, double step,
                                        const KlipperRuleSettings& test);

// The highest frequency a resonance test may sweep under `controller`: a
// quarter of its sample rate, 0.25 / T_s (Hz; the sweep is read every T_s,
// four samples a period). The job loader refuses a max_freq above it
// (run/load_fit_job.cc), as SimulateResonanceTest does.
double KlipperHighestFrequency(const ControllerConfig& controller);

// One shaper as Klipper's rule fits it.
struct KlipperShaperFit {
  ShaperType type = ShaperType::kNone;
  double frequency = 0.0;  // Hz, the fitted frequency (design damping KlipperRuleSettings)
  double vibration = 0.0;  // the remaining vibration v, a fraction
  double smoothing = 0.0;  // m, MoveSmoothing of the move with it
  double score = 0.0;      // s·(v^1.5 + 0.2·v + 0.01), m
};

struct KlipperShaperChoice {
  std::vector<KlipperShaperFit> fitted;  // one per shaper, in ShaperType order
  size_t recommended = 0;                // the index in `fitted` of the lowest score
  InputShaper shaper;                    // the recommended one, designed
};

// Klipper's score s·(v^1.5 + 0.2·v + 0.01) of a remaining vibration v (a
// fraction) and a smoothing s. Never throws.
double KlipperScore(double vibration, double smoothing);

// Step 3 above: the index in `fitted` (their scores and smoothings set) of
// the recommended shaper. Throws std::invalid_argument if `fitted` is
// empty.
size_t RecommendShaper(const std::vector<KlipperShaperFit>& fitted);

// Steps 2 and 3 above on `spectrum` for the move `move` (its own shaper
// ignored). Throws std::invalid_argument if the spectrum is empty or its
// total power is not positive.
KlipperShaperChoice ChooseShaperAsKlipper(const ResonanceSpectrum& spectrum,
                                          const Reference& move,
                                          const KlipperRuleSettings& rule);

}  // namespace axis

#endif  // TUNE_KLIPPER_SHAPER_RULE_H_
