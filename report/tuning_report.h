// What a tuning of the analog loop (tune/analog_loop_tuning.h, job key
// `tune:`) prints and writes: the recommended setting beside the current
// one with each figure's value at the estimate and its spread over the
// fit's 95 % intervals, the trade-off curve, and the files to verify the
// proposal on the machine.
#ifndef REPORT_TUNING_REPORT_H_
#define REPORT_TUNING_REPORT_H_

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "job/fit_job.h"
#include "tune/analog_loop_tuning.h"

namespace axis {

// The text of fit-params's "Tuning" block (and params.md's section): the
// spec, current and proposed K_1 and T_p, a table of the figures (value at
// the estimate, low–high over the intervals' ends, the limiting parameter,
// the bounds), whether the spec holds over the uncertainty, the curve.
// "" if the tuning did not run and has no note. Never throws.
std::string FormatTuning(const AnalogLoopTuning& t);

// report.json's "tuning": {"ran", "note", "spec": {...}, "current" and
// "proposed": {"K1", "T_p", "metrics": {...}, "violations", "spread":
// [{"figure", "at_estimate", "low", "high", "limiting"}], "robust",
// "robust_violations"}, "curve": [{"T_p", <figures>, "violations"}],
// "simulations", "seconds"}; NaN figures are null. Never throws.
nlohmann::json TuningToJson(const AnalogLoopTuning& t);

// The files of a tuning that ran, into the folder `dir`: tune_curve.csv
// (the trade-off curve: T_p and every figure), tune_step.csv (t; x, v,
// i, vm and fg of the current and the proposed setting at the estimate;
// the proposal's band of x, v, i and fg over the interval ends, *_low and
// *_high),
// model_tuned.yaml (the job's model at the estimate `model` with the
// proposed K1 and T_p) and tune_verify.yaml (the step as an experiment of
// simulate-axis on model_tuned.yaml: the test to run on the machine and
// fit). Their names are appended to *files. Throws std::runtime_error if a
// file cannot be written.
void WriteTuning(const std::string& dir, const AxisConfig& model, const AnalogLoopTuning& t,
                 std::vector<std::string>* files);

}  // namespace axis

#endif  // REPORT_TUNING_REPORT_H_
