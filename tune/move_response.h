// The test of a move tuning (issue 45; job key `tune.move:`,
// tune/tune_settings.h MoveSpec): a point-to-point move of the identified
// axis under the sampled position controller of MODEL.md §5, simulated with
// the model's limits, and the figures a servo engineer reads off it (move
// time, settling after the move, following error, overshoot, peak current,
// residual vibration).
#ifndef TUNE_MOVE_RESPONSE_H_
#define TUNE_MOVE_RESPONSE_H_

#include <string>
#include <vector>

#include "tune/tune_settings.h"
#include "sim/config.h"
#include "sim/controller.h"

namespace axis {

// The simulated move, at the output period of SimulateMove.
struct MoveResponse {
  std::vector<double> t;      // s, from the move's start
  std::vector<double> x_ref;  // m, the profile (Reference::Profile, continuous)
  std::vector<double> x;      // m, arm position y0
  std::vector<double> v;      // m/s, arm velocity y1
  std::vector<double> i;      // A, motor current
  std::vector<double> u;      // V, the controller's output
  std::vector<double> fg;     // N, gear force
  double move_duration = 0.0;  // s, the profile's (Reference::MoveDuration)
  double target = 0.0;         // m, origin + distance
  bool finite = true;          // false if the run left the finite numbers
};

// The move `reference` (a trapezoid or minimum-jerk move from rest at
// x = reference.origin, start 0) of `model` under the controller
// `controller` (MODEL.md §5; the model's own is ignored), simulated by RK4
// at `step` (s, > 0) until `settle` s after the profile ends, recorded
// every `step` times the whole number nearest to 1e-4/step (at least 1).
// Throws std::invalid_argument for a reference that is not a move or a
// step that does not fit the run (MakeGrid).
MoveResponse SimulateMove(const AxisConfig& model, const ControllerConfig& controller,
                          const Reference& reference, double step, double settle);

// Widens the band [*low, *high] sample by sample to hold `r` (x, v, i, u,
// fg; a band that is empty takes `r` as it is). Responses of another
// length or not finite are skipped. Never throws (except std::bad_alloc).
void WidenMoveBand(const MoveResponse& r, MoveResponse* low, MoveResponse* high);

// The figures of one move, in the units of MoveSpec.
struct MoveMetrics {
  // s from the start, the last time |x − target| > position_band (0 if
  // never); the run's length if it is outside at its end (settled false).
  double move_time = 0.0;
  bool settled = false;
  double settling_time = 0.0;     // s, max(0, move_time − move_duration)
  double following_error = 0.0;  // m, max |x_ref − x| up to the profile's end
  double overshoot = 0.0;        // m, max of (x − target)·sgn(D), ≥ 0
  double peak_current = 0.0;     // A, max |i|
  // m, max |x − target| from ringing_after s after the profile's end; NaN
  // if that is past the run's end.
  double ringing = 0.0;
};

// The figures of `r` under `spec`. A response that is not finite gives
// every figure NaN (settled false). Never throws.
MoveMetrics MeasureMove(const MoveResponse& r, const MoveSpec& spec);

// Hz, the frequency of the residual vibration of `r` after its profile
// ends: from the crossings of x through its mean over that stretch,
// (crossings − 1)/(2·(last − first crossing time)); NaN where it crosses
// fewer than three times or its largest swing about the mean is below
// `floor` (m, ≥ 0). Never throws.
double ResidualVibrationFrequency(const MoveResponse& r, double floor);

// m, the smoothing of `reference`'s input shaper: the largest distance
// between the shaped command and the unshaped one delayed by the shaper's
// centroid t̄ = Σ A_i·t_i, max |Σ A_i·P(t − t_i) − P(t − t̄)| over the move,
// sampled every `dt` s (> 0). The delay alone costs no path (0 at constant
// velocity); at a constant acceleration a it is ½·a·Σ A_i·(t_i − t̄)², the
// rounding the shaper gives the move's corners. 0 without a shaper. Never
// throws.
double MoveSmoothing(const Reference& reference, double dt);

// The bounds of `spec` that `m` violates, one phrase each ("following
// error 0.0061 m > 0.005 m"), in MoveSpec order, and the matching
// MoveMetrics field names ("settling_time", "following_error",
// "overshoot", "peak_current", "ringing"). A NaN figure violates the bound
// it is checked against. Never throws.
std::vector<std::string> MoveViolations(const MoveMetrics& m, const MoveSpec& spec);
std::vector<std::string> MoveViolatedFigures(const MoveMetrics& m, const MoveSpec& spec);

// How far `m` is outside `spec`: the sum over its bounds of the relative
// excess (0 when it meets them all; 1 for an unmeasured figure). Never
// throws.
double MoveViolation(const MoveMetrics& m, const MoveSpec& spec);

}  // namespace axis

#endif  // TUNE_MOVE_RESPONSE_H_
