// The analog velocity loop of the identified axis tuned to a specification
// (issue 45; job key `tune:`, tune/tune_settings.h): the paper's procedure
// automated. Nelson & Chang (1984, section III) set K_2 at its maximum
// (870), K_1 for the desired 0.1 m/s per volt, and reduced the preamp's
// T_p "in a series of steps from the maximum of 4.74 s" until the
// transient of a step matched the controller manual's; with the current
// and voltage limits "the usual linear system design methods do not
// apply", so the search simulates the nonlinear model (tune/step_response.h).
//
// The search: the trade-off curve (every figure of the step response on a
// logarithmic grid of T_p, the paper's series of steps), the grid point
// with the lowest settling time among those meeting the specification
// (the least violation where none does), then Brent's minimiser
// (boost/math/tools/minima.hpp, brent_find_minima) on the penalised
// settling time between that point's neighbours. Then the proposal, and the
// current setting, are simulated again with each free parameter of the fit
// at either end of its 95 % interval (the others at the estimate; the
// discovered effects' parameters included) and at TuneSettings::samples
// points of the fit's joint 95 % region (tune/joint_region.h): each
// figure's spread, the parameter whose ends move it most, and whether the
// specification holds at all of them.
#ifndef TUNE_ANALOG_LOOP_TUNING_H_
#define TUNE_ANALOG_LOOP_TUNING_H_

#include <string>
#include <vector>

#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"
#include "tune/tune_settings.h"
#include "tune/interval_ends.h"
#include "tune/step_response.h"

namespace axis {

// One T_p of the trade-off curve.
struct TuningPoint {
  double T_p = 0.0;  // s
  StepMetrics metrics;
  std::vector<std::string> violations;  // SpecViolations
};

// A setting (K_1, T_p) judged at the estimate and over the uncertainty.
struct TunedSetting {
  double K1 = 0.0;   // V/V, MODEL.md §2
  double T_p = 0.0;  // s
  StepMetrics metrics;                  // at the estimate
  std::vector<std::string> violations;  // at the estimate
  // "settling_time", "overshoot", "peak_current", "voltage_headroom",
  // "ringing", "ringing_decay", in this order.
  std::vector<FigureSpread> spread;
  // Every bound met at the estimate, at every end of every interval and at
  // every sample of the joint region.
  bool robust = false;
  // The ends that break a bound met at the estimate: "<parameter> at
  // <low|high> end: <violation>"; of the joint region's samples only the
  // first that does ("joint sample 3: <violation>").
  std::vector<std::string> robust_violations;
  // The samples of the fit's joint 95 % region judged (tune/joint_region.h,
  // TuneSettings::samples) and those where every bound is met.
  int samples = 0, samples_met = 0;
  StepResponse response;  // at the estimate, for the plots
  // The response's band over the estimate and every interval end, sample
  // by sample (WidenBand).
  StepResponse band_low, band_high;
};

struct AnalogLoopTuning {
  bool ran = false;
  std::string note;  // why not, or what the search could not do
  TuneSpec spec;
  double K2 = 0.0;  // tachometer feedback gain (1), as in the model (kept, as the paper: at its maximum)
  TunedSetting current, proposed;
  std::vector<TuningPoint> curve;   // T_p descending, the paper's series of steps
  int simulations = 0;
  double seconds = 0.0;
};

// Tunes K_1 (if spec.velocity_gain is set) and T_p of the axis `job`'s
// model at `result`'s estimate (AtEstimate) under `tune`, simulating at
// the first fitted experiment's RK4 step. The model must have the analog
// velocity loop (amplifier: analog_velocity_loop); otherwise ran is false
// with a note. Throws std::runtime_error if the model at the estimate does
// not simulate; never for a specification that cannot be met (the
// proposal then has the least violation, with its violations listed).
AnalogLoopTuning TuneAnalogLoop(const EstimationProblem& job, const FitResult& result,
                                const TuneSettings& tune);

// The setting `s` (its K1 and T_p) applied to another axis, `axis` (e.g.
// the model that generated the records, with effects the fit did not
// declare), and the step of `spec` simulated on it at `step` (s): the
// spec's violations there (SpecViolations), empty if it holds. Throws
// std::invalid_argument as SimulateStep.
std::vector<std::string> ViolationsOn(const AxisConfig& axis, double step, const TunedSetting& s,
                                      const TuneSpec& spec);

}  // namespace axis

#endif  // TUNE_ANALOG_LOOP_TUNING_H_
