// The paper's test of a tuning (Nelson & Chang 1984, section III, Fig. 4):
// a step of the set-velocity voltage U on the axis at rest, simulated with
// the identified model and its limits, and the figures an engineer reads
// off it (settling time, overshoot, peak current, voltage headroom,
// residual vibration).
#ifndef TUNE_STEP_RESPONSE_H_
#define TUNE_STEP_RESPONSE_H_

#include <string>
#include <vector>

#include "tune/tune_settings.h"
#include "sim/config.h"

namespace axis {

// The simulated step, at the output period of StepResponseOptions.
struct StepResponse {
  std::vector<double> t;   // s, from the step
  std::vector<double> x;   // arm position y0 (m)
  std::vector<double> v;   // arm velocity y1 (m/s)
  std::vector<double> i;   // motor current (A)
  std::vector<double> vm;  // motor voltage (V)
  std::vector<double> fg;  // gear force (N)
  bool finite = true;      // false if the run left the finite numbers
};

// Simulates a step of spec.step_voltage at t = 0 of `model` (its structure,
// parameters and effects; open loop, the model's analog loop, no sampled
// controller even if the model has one) from rest for spec.duration s, by
// RK4 at `step` (s, > 0), recorded every output period: `step` times the
// whole number nearest to 1e-4/step, at least 1 (100 µs resolves the
// settling time to well under the 5 ms control period). Throws
// std::invalid_argument for a step that does not fit the duration (MakeGrid).
StepResponse SimulateStep(const AxisConfig& model, double step, const TuneSpec& spec);

// Widens the band [*low, *high] sample by sample to hold `r` (every
// channel; a band that is empty takes `r` as it is). Responses of another
// length or not finite are skipped. Never throws (except std::bad_alloc).
void WidenBand(const StepResponse& r, StepResponse* low, StepResponse* high);

// The figures of one response, in the units of TuneSpec.
struct StepMetrics {
  double final_velocity = 0.0;  // m/s, the mean of the last 5 % of the run
  // s, the last time |v − v_final| > settling_band·|v_final| (0 if never);
  // the run's duration if it is still outside at its end.
  double settling_time = 0.0;
  bool settled = false;          // inside the band at the end of the run
  double overshoot = 0.0;        // (max v − v_final)/v_final, ≥ 0 (v_final > 0)
  double peak_current = 0.0;     // A, max |i|
  double voltage_headroom = 0.0;  // V, V_M − max |vm| (may be negative: at the limit)
  // m/s, max |v − v_final| from ringing_after s after v first enters the
  // band; NaN if it never enters or that time is past the run's end.
  double ringing = 0.0;
  // s, the e-folding time of the ringing: −1/slope of the least-squares
  // line through ln of the local maxima of |v − v_final| after v first
  // enters the band (maxima above 1e-4·|v_final|, at least 3); +inf if
  // they do not decay, NaN if there are fewer than 3. The paper's "below
  // about 0.04 s the ringing decays too slowly" (section III) in figures.
  double ringing_decay = 0.0;
};

// The figures of `r` (a response of SimulateStep with `spec`) for a model
// whose motor-voltage limit is V_M (V). A response that is not finite, or
// whose final velocity is not positive, gives every figure NaN. Never
// throws.
StepMetrics MeasureStep(const StepResponse& r, const TuneSpec& spec, double V_M);

// The spec's bounds that `m` violates, one phrase each ("settling time
// 0.91 s > 0.8 s"), in TuneSpec order; empty if it meets them all. A NaN
// figure violates the bound it is checked against ("overshoot not
// measured"). Never throws.
std::vector<std::string> SpecViolations(const StepMetrics& m, const TuneSpec& spec);

// The StepMetrics field names of the bounds SpecViolations reports, in the
// same order ("settling_time", "overshoot", "peak_current",
// "voltage_headroom", "ringing", "ringing_decay"). Never throws.
std::vector<std::string> ViolatedFigures(const StepMetrics& m, const TuneSpec& spec);

}  // namespace axis

#endif  // TUNE_STEP_RESPONSE_H_
