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

#include "estimation/estimation_problem.h"
#include "tune/analog_loop_tuning.h"
#include "tune/move_tuning.h"

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

// The text of the move tuning (tune.move:; tune/move_tuning.h): the move
// and its limits, a table of the current setting and of each profile's
// tuned one (profile, speed, with shapers the input shaper and its
// smoothing, gains, figures at the estimate), the shaper frequency range
// of each profile, the proposed setting's residual vibration at the
// estimate and the largest over the checks, the figures
// of the current and the proposed setting with their spread over the
// intervals and the limiting parameter, and whether the spec holds over
// the uncertainty. "" if it did not run and has no note. Never throws.
std::string FormatMoveTuning(const MoveTuning& t);

// report.json's "move_tuning": {"ran", "note", "spec": {...}, "gains":
// [{"name", "low", "high"}], "shapers" (names), "shaper_notes", "slow_down",
// "margin", "on_proposed_analog_loop", "current", "proposed" and "tuned":
// [{"profile", "speed", "K1", "T_p", "controller": {"G_p", "G_i", "G_v",
// "G_ff", "alpha"}, "move": {"velocity", "acceleration", "jerk",
// "duration"}, "shaper": {"type", "frequency" (Hz), "damping",
// "amplitudes", "times" (s), "duration" (s)}, "smoothing" (m),
// "residual_vibration": [{"check", "ringing" (m)}], "checks_met", "metrics": {...},
// "violations", "objective", "scenarios", "evaluations", "spread", "robust",
// "robust_violations"}], "klipper": {"ran", "note" (if not), "resonance_test":
// {"seconds", "averages", "frequency" (Hz), "psd" ((m/s²)²/Hz)}, "fitted":
// [{"shaper", "frequency", "vibration", "smoothing", "score"}],
// "recommended", "setting" (as "tuned")}, "simulations", "seconds"}; NaN and infinite
// figures are null. Never throws.
nlohmann::json MoveTuningToJson(const MoveTuning& t);

// The files of a move tuning that ran, into `dir`: tune_move.csv (t;
// x_ref, x, v, i, u, fg of the current and the proposed setting at the
// estimate, run to the same end; the proposal's band of x, v, i and u over
// the interval ends),
// model_tuned_move.yaml (the job's model at the estimate `model` with the
// K1, T_p and controller gains of the proposal) and tune_move_verify.yaml
// (the proposed move as a simulate-axis experiment on that model: the
// test to run on the machine). Names appended to *files. Throws
// std::runtime_error if a file cannot be written.
void WriteMoveTuning(const std::string& dir, const AxisConfig& model, const MoveTuning& t,
                     std::vector<std::string>* files);

// tune_step.csv (the columns WriteTuning documents) and tune_move.csv
// (WriteMoveTuning's) at `path`; false, writing nothing, if the tuning did
// not run or its responses are missing or not finite. Throw
// std::runtime_error if the file cannot be written.
bool WriteTuneStepCsv(const std::string& path, const AnalogLoopTuning& t);
bool WriteTuneMoveCsv(const std::string& path, const MoveTuning& t);

// gnuplot scripts (SVG terminal, for report.html's RenderGnuplotSvg) that
// draw such a CSV `csv` into `output`: velocity and current (the step),
// position with the proposal's reference and current (the move), each
// the current and the proposed setting with the proposal's band over the
// interval ends. Never throw.
std::string TuneStepPlotScript(const std::string& csv, const std::string& output);
std::string TuneMovePlotScript(const std::string& csv, const std::string& output);

}  // namespace axis

#endif  // REPORT_TUNING_REPORT_H_
