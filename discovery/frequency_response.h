// The frequency response of every fitted experiment whose input excites a
// band (docs/frequency-response.md): the H1 estimate with Welch averaging
// and its coherence (common/spectral.h) from the experiment's input to each
// fitted channel, of the data and of the model at the estimate simulated on
// the same input and read by the same estimator (so a nonlinear model is
// compared like for like), the linear model's response at the operating
// point where one is meaningful (sim/operating_point.h,
// sim/linearisation.h, MODEL.md §9), and the linear model's resonances and
// each channel's anti-resonances with 95 % intervals by the delta method.
//
// The input of an experiment: open loop, the drive's input U (V: the
// set-velocity voltage, the force-source input or the voltage drive's
// terminal voltage); closed loop, the injection added to the controller's
// output where there is one (V, or a duty cycle for a firmware loop), else
// the reference position x_ref (m, or rad on a rotary axis). The linear
// model is of the open-loop plant: a closed loop has none (the sampled
// controller is not linearised).
#ifndef DISCOVERY_FREQUENCY_RESPONSE_H_
#define DISCOVERY_FREQUENCY_RESPONSE_H_

#include <complex>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "common/spectral.h"
#include "discovery/frequency_response_settings.h"
#include "estimation/estimation_problem.h"
#include "estimation/fit_result.h"
#include "sim/axis_config.h"
#include "sim/operating_point.h"

namespace axis {

// A resonance (pole pair) or anti-resonance (zero pair) of the linear
// model: natural frequency and damping (sim/linearisation.h LinearMode)
// with the 95 % interval frequency ± 1.96·SE, SE² = gᵀ·Σ·g, g the
// derivatives of the frequency in the free parameters (central
// differences, the operating point found again at each) and Σ their
// covariance (ParameterCovariance). SE and the interval NaN without a
// covariance, or where a perturbed model loses the mode.
struct ModeEstimate {
  double frequency = 0.0;  // Hz
  double damping = 0.0;    // ζ
  double std_error = 0.0;  // Hz
  double ci95_low = 0.0, ci95_high = 0.0;  // Hz
};

// The linear model at an experiment's operating point.
struct LinearModelModes {
  std::string blocker;  // why there is no linear model ("" if there is one)
  OperatingPoint point;
  std::vector<ModeEstimate> resonances;
  std::vector<std::vector<ModeEstimate>> anti_resonances;  // per channel given
};

// The covariance of the free parameters of `result` in the order of
// `result.free_names`: diag(SE)·R·diag(SE) from their standard errors and
// correlation matrix; 0×0 if those are missing or not finite. Never throws.
Eigen::MatrixXd ParameterCovariance(const FitResult& result);

// The linear model of `model` at the steady state under constant input `u`
// (V) from `start` (FindOperatingPoint on AveragedStructure; blocker
// LinearModelBlocker's), its resonances and the anti-resonances of each
// of `channels` (functions of the state), with intervals from `covariance`
// (free × free, in the order of `free`, VisitParams names; 0×0: no
// intervals); the parameters tied to a free one (`ties`,
// estimation/parameter_tie.h) move with it in the derivatives. Throws
// std::invalid_argument for an unknown free or tied parameter name or a
// covariance of the wrong size.
LinearModelModes LinearModelWithIntervals(const AxisConfig& model,
                                          const AxisState<double>& start, double u,
                                          const std::vector<Channel>& channels,
                                          const std::vector<std::string>& free,
                                          const Eigen::MatrixXd& covariance,
                                          const std::vector<ParameterTie>& ties = {});

// One fitted channel's response on the excited band's bins.
struct ChannelFrequencyResponse {
  std::string channel, unit;  // MODEL.md §6 name, its unit
  std::vector<double> frequency;                   // Hz
  std::vector<std::complex<double>> data, model;   // H1, channel unit per input unit
  std::vector<double> data_coherence, model_coherence;  // γ²
  // The linear model's response (with the sensor front end), empty where
  // there is no linear model or the channel is not a function of the state.
  std::vector<std::complex<double>> linear;
  std::vector<ModeEstimate> anti_resonances;
};

struct ExperimentFrequencyResponse {
  std::string experiment;
  std::string input, input_unit;  // "U", "injection" or "x_ref"; its unit
  BandExcitation band;            // the criterion's verdict on the input
  // Why there is no frequency response (no band, a record too short), ""
  // where there is one.
  std::string note;
  int averages = 0, segment_length = 0;
  double sample_period = 0.0;  // s
  double mean_input = 0.0;     // ū, the operating point's input
  LinearModelModes linear;     // blocker set where there is no linear model
  std::vector<ChannelFrequencyResponse> channels;
};

// The frequency response of each fitted experiment of `job`, whose model
// must hold the estimate (AtEstimate, estimation/at_estimate.h), with the
// covariance of `result` (ParameterCovariance). Welch options: the
// automatic segment length (≥ settings.min_averages averages), at most
// 4096 samples (a longer record gives more averages); band: BandCriterion's
// defaults. `settings.enabled` is the caller's to test.
// Throws std::runtime_error if the model at the estimate does not simulate
// a record.
std::vector<ExperimentFrequencyResponse> AnalyseFrequencyResponse(
    const EstimationProblem& job, const FitResult& result,
    const FrequencyResponseSettings& settings = {});

// The input of experiment `e` at its sample times (see above) and its name
// and unit. Never throws (but std::bad_alloc).
std::vector<double> ExperimentInput(const FitExperiment& e, bool rotary, std::string* name,
                                    std::string* unit);

// A table: per experiment and channel the band, averages, median coherence
// of data and model, and the linear model's anti-resonances with the
// half-widths of their intervals; per experiment the linear model's
// resonances or why it has none, and, where the model's own median
// coherence is below 0.9 on some channel, that the record is not
// small-signal; the experiments without a response with the reason. ""
// for none.
std::string FormatFrequencyResponse(const std::vector<ExperimentFrequencyResponse>& responses);

// report.json's "frequency_response": an array, one object per experiment
// (docs/frequency-response.md lists the keys).
nlohmann::json FrequencyResponseToJson(const std::vector<ExperimentFrequencyResponse>& responses);

// Writes channel `c` of `r` as CSV: frequency (Hz), then magnitude (dB),
// phase (deg) and coherence of the data's H1, the same of the model's, and
// magnitude and phase of the linear model (empty cells where there is
// none). Throws std::runtime_error naming `path` if it cannot be written.
void WriteFrequencyResponseCsv(const std::string& path, const ExperimentFrequencyResponse& r,
                               const ChannelFrequencyResponse& c);

// gnuplot commands drawing that CSV into `output` as a Bode plot: magnitude
// (dB), phase (deg) and coherence against frequency on a log axis; svg: the
// svg terminal (RenderGnuplotSvg), else a PNG. Paths must not contain a
// quote or a line break.
std::string BodePlotScript(const ExperimentFrequencyResponse& r,
                           const ChannelFrequencyResponse& c, const std::string& csv_path,
                           const std::string& output, bool svg);

}  // namespace axis

#endif  // DISCOVERY_FREQUENCY_RESPONSE_H_
