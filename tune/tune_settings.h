// Job key `tune:` (configs/README.md; issue 45): the specification a
// tuning of the identified axis must meet, in the engineer's terms, and the
// settings the tuner may move (tune/analog_loop_tuning.h,
// tune/move_tuning.h), and their strict loader.
//
// The test is the paper's own (Nelson & Chang 1984, section III and
// Fig. 4): a step of the set-velocity voltage U applied to the identified
// axis at rest, simulated with the fitted model and its limits. A bound
// left unset (NaN) is not part of the specification.
#ifndef TUNE_TUNE_SETTINGS_H_
#define TUNE_TUNE_SETTINGS_H_

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "sim/input_shaper.h"

namespace axis {

struct TuneSpec {
  // V, the set-velocity voltage step, in (0, 10] (the drive's ±10 V; the
  // paper's Fig. 4 uses 10 V).
  double step_voltage = 10.0;
  // s, simulated from the step, in [0.1, 60]; long enough for the velocity
  // to settle.
  double duration = 1.5;
  // The settling band, a fraction of the final velocity, in (0, 0.5):
  // the settling time is the last time |v − v_final| exceeds it.
  double settling_band = 0.02;
  // s after the velocity first enters the band at which the residual
  // vibration (the largest |v − v_final| from then on, m/s) is read, ≥ 0.
  double ringing_after = 0.1;
  // Bounds (NaN: none). s, ≥ 0.
  double max_settling_time = std::numeric_limits<double>::quiet_NaN();
  // Fraction of the final velocity, ≥ 0.
  double max_overshoot = std::numeric_limits<double>::quiet_NaN();
  // A, the motor's rating, > 0. The preamp limit K_i·V_L of the model
  // (MODEL.md §3) always applies; this is the rating the peak must respect.
  double max_current = std::numeric_limits<double>::quiet_NaN();
  // V, the least margin between the motor voltage and its limit V_M, ≥ 0.
  double min_voltage_headroom = std::numeric_limits<double>::quiet_NaN();
  // m/s, the largest residual vibration allowed (see ringing_after), > 0.
  double max_ringing = std::numeric_limits<double>::quiet_NaN();
  // s, the longest e-folding time of the ringing allowed
  // (tune/step_response.h StepMetrics::ringing_decay), > 0.
  double max_ringing_decay = std::numeric_limits<double>::quiet_NaN();
  // m/s per V, the drive's steady-state velocity gain r_g·ω/U (MODEL.md §3,
  // linear_model.h SteadyStateGain); if set, K_1 is recomputed for it with
  // the identified arm friction B_a (the paper sets K_1 for 0.1 m/s per V
  // with K_2 at its maximum 870). NaN: K_1 as in the model.
  double velocity_gain = std::numeric_limits<double>::quiet_NaN();
};

// A gain of the sampled position controller (MODEL.md §5) the move tuning
// may move, within [low, high] (the gain's units; G_p in V/m, G_i in
// V/(m·s), G_v and G_ff in V·s/m, alpha in [0, 1]). Searched on a log scale
// where low > 0, else linearly.
struct TunedGain {
  std::string name;  // "G_p", "G_i", "G_v", "G_ff" or "alpha"
  double low = 0.0, high = 0.0;
};

// `tune.move:` (issue 45): a point-to-point move under the sampled position
// controller (MODEL.md §5) and the specification it must meet. The move
// starts at rest at t = 0; "after the move" means after the reference
// profile has ended.
struct MoveSpec {
  double distance = 0.1;  // m, signed, nonzero
  // The machine's limits on the profile: m/s, m/s² and m/s³ (> 0; jerk
  // applies to the minimum-jerk profile, +inf: none).
  double max_velocity = 1.0, max_acceleration = 10.0, max_jerk = HUGE_VAL;
  // The profiles compared: "trapezoid" and/or "min_jerk" (sim/controller.h
  // Reference), at least one.
  std::vector<std::string> profiles = {"trapezoid", "min_jerk"};
  // s simulated after the move, in [0.05, 60].
  double settle = 0.5;
  // m, > 0: the position band around the target; the move time is the last
  // time |x − target| exceeds it.
  double position_band = 1e-4;
  // s after the move at which the residual vibration is read, ≥ 0.
  double ringing_after = 0.05;
  // Bounds (NaN: none). s after the move, ≥ 0.
  double max_settling_time = std::numeric_limits<double>::quiet_NaN();
  // m, the largest |x_ref − x| during the move, > 0.
  double max_following_error = std::numeric_limits<double>::quiet_NaN();
  // m beyond the target in the direction of travel, ≥ 0.
  double max_overshoot = std::numeric_limits<double>::quiet_NaN();
  // A, the motor's rating, > 0.
  double max_current = std::numeric_limits<double>::quiet_NaN();
  // m, the largest |x − target| from ringing_after on, > 0.
  double max_ringing = std::numeric_limits<double>::quiet_NaN();
};

// `tune.move.klipper:` (issue 59): the shaper Klipper's selection rule
// would choose (tune/klipper_shaper_rule.h), from its resonance test
// simulated on the identified model, set beside the proposal and judged
// the same way. Klipper's [resonance_tester] defaults, in SI units.
struct KlipperRuleSettings {
  bool enabled = false;       // `tune.move.klipper:` present
  double min_freq = 5.0;      // Hz, > 0
  double max_freq = 133.33;   // Hz, > min_freq
  double accel_per_hz = 0.075;  // m/s² per Hz (Klipper's 75 mm/s² per Hz), > 0
  double hz_per_sec = 1.0;    // Hz/s, the sweep's rate, > 0
  // The damping ratio the shapers are designed at (Klipper's default),
  // in [0, 1), and those their remaining vibration is judged over.
  double design_damping = 0.1;
  std::vector<double> test_damping = {0.075, 0.1, 0.15};
};

struct MoveTuneSettings {
  bool enabled = false;  // `tune.move:` present
  MoveSpec spec;
  // The controller gains searched (default G_p in [10, 10000] V/m and G_v
  // in [0, 100] V·s/m); at least one.
  std::vector<TunedGain> gains = {{"G_p", 10.0, 1e4}, {"G_v", 0.0, 100.0}};
  // Whether the profile may be slowed below the limits (stretched in time
  // by 1/s, s in [0.25, 1]: v·s, a·s², j·s³) when that meets the spec or
  // ends sooner: minimum time subject to the limits and the spec.
  bool slow_down = true;
  // Simulations of the search per profile, in [20, 5000].
  int evaluations = 160;
  // Input shapers (sim/input_shaper.h) tried on each profile besides the
  // unshaped move: "ZV", "MZV", "ZVD", "EI", "2HUMP_EI", "3HUMP_EI" (empty:
  // none). For each, the gains, the speed, the shaper's frequency and its
  // damping are searched together.
  std::vector<ShaperType> shapers;
  // Hz, the shaper frequencies searched (log scale), 0.05 <= low < high; NaN:
  // from half to twice the frequency of the residual vibration the
  // profile's unshaped tuned move leaves on the identified model (no shaper
  // where it leaves none).
  double shaper_frequency_low = std::numeric_limits<double>::quiet_NaN();
  double shaper_frequency_high = std::numeric_limits<double>::quiet_NaN();
  // The shaper damping ratios searched, 0 <= low < high < 1.
  double shaper_damping_low = 0.0, shaper_damping_high = 0.3;
  KlipperRuleSettings klipper;
  // The design margin, in [0, 0.5]: the search meets every bound of the
  // spec lowered by this fraction (what the identified model does not
  // capture — its RK4 step, the quasi-steady current loop, the corners of
  // the uncertainty); the report checks the spec itself.
  double margin = 0.1;
};

struct TuneSettings {
  bool enabled = false;  // `tune:` present in the job
  TuneSpec spec;
  // The analog loop's preamp time constant T_p (s), searched on a
  // logarithmic grid of `curve_points` points from T_p_high down to
  // T_p_low (the paper's series of steps from its maximum 4.74 s), then
  // refined between the best point's neighbours. 0 < T_p_low < T_p_high.
  double T_p_low = 0.005;
  double T_p_high = 4.74;
  int curve_points = 25;  // in [5, 200]
  // Points of the fit's joint 95 % region (tune/joint_region.h) each
  // setting is checked at besides the interval ends, in [0, 1000]; 0: the
  // ends only.
  int samples = 32;
  MoveTuneSettings move;
};

// Reads `tune:` of job `path` (every key optional; `enabled` set):
//   tune:
//     step: {voltage: 10, duration: 1.5}
//     spec: {settling_band: 0.02, ringing_after: 0.1, settling_time: 0.8,
//            overshoot: 0.05, current: 8.1, voltage_headroom: 5,
//            ringing: 0.005, ringing_decay: 0.1, velocity_gain: 0.1}
//     T_p: {low: 0.005, high: 4.74, points: 25}
//     samples: 32
//     move:
//       distance: 0.1
//       limits: {velocity: 1.0, acceleration: 10, jerk: 1000}
//       profiles: [trapezoid, min_jerk]
//       settle: 0.5
//       spec: {position_band: 1.0e-4, ringing_after: 0.05, settling_time: 0.05,
//              following_error: 0.005, overshoot: 1.0e-4, current: 8.1,
//              ringing: 1.0e-4}
//       gains: {G_p: [10, 10000], G_v: [0, 100]}
//       shapers: [ZV, MZV, ZVD, EI, 2HUMP_EI, 3HUMP_EI]
//       shaper_frequency: [5, 50]
//       shaper_damping: [0, 0.3]
//       klipper: {min_freq: 5, max_freq: 133.33, accel_per_hz: 0.075,
//                 hz_per_sec: 1}
//       slow_down: true
//       evaluations: 160
//       margin: 0.1
// Throws std::invalid_argument "<file>:<line>: key 'tune.<key>': expected
// …, got …" for an unknown key or a value outside the ranges above.
void ParseTuneSettings(const YAML::Node& node, const std::string& path, TuneSettings* out);

}  // namespace axis

#endif  // TUNE_TUNE_SETTINGS_H_
