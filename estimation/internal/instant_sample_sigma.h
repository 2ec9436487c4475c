// The instant accelerometer's uncertainty at the jumps of y1' (MODEL.md §6,
// "The accelerometer"): per-sample σ_k for the samples of `a` whose sensor
// window holds a backlash contact.
//
// Why: y1' jumps at every contact (eq. 5). The model reads an instant
// sample as the mean of y1' over its window (±instant_window, at least one
// RK4 step), which keeps the cost continuous in the parameters; a recorder's
// own sensor sees the jump through a response the job does not know (a
// point sample, a narrower or otherwise shaped window). At a sample whose
// window holds a contact the two differ by up to the jump's share inside
// the window, and such a sample, moving steeply with the contact's time, can
// pull an estimate by a standard error on its own. Every narrower response
// lies between the model's window mean and y1' at the instant, so
//     Δ_k = |window mean_k − y1'(t_k)|
// bounds the difference, and the sample is weighted by
//     σ_k = √(σ² + Δ_k²)
// (σ the channel's noise), the model's own uncertainty added to the noise as
// an independent error. Away from contacts Δ_k is the window's curvature
// term, w²·|y1'''|/6, far below σ at the steps the fits use, and σ_k = σ.
// Δ_k is continuous in the parameters: y1'(t_k) jumps by J when a contact
// crosses t_k, and the window mean sits at the middle of the jump there, so
// |Δ_k| is J/2 on both sides.
#ifndef ESTIMATION_INTERNAL_INSTANT_SAMPLE_SIGMA_H_
#define ESTIMATION_INTERNAL_INSTANT_SAMPLE_SIGMA_H_

#include <vector>

#include "estimation/estimation_problem.h"
#include "estimation/experiment_cost.h"
#include "sim/axis_params.h"

namespace axis {

// σ_k (m/s², one per sample of `experiment`) for its fitted channel `a` at
// `params` from initial state `y0`, or empty where there is nothing to
// weight: the accelerometer is not `instant`, `a` is not fitted, the
// simulation left the finite numbers, or every Δ_k is below 10 % of σ (the
// weights would move by less than 0.5 %). Δ_k comes from one simulation in
// double with SimulationOptions::point_acceleration (sim/simulate.h), which
// puts y1' through the channel's delay and low-pass filters as the window
// mean is. Throws std::invalid_argument as MakeGrid on a bad grid.
std::vector<double> InstantSampleSigmas(const AxisStructure& structure,
                                        const AxisParams<double>& params,
                                        const AxisState<double>& y0,
                                        const FitExperiment& experiment);

// Σ_k log(σ_k²/σ²) over every fitted channel's per-sample σ_k
// (sample_sigma[j][i]: experiment j, its fitted channel i;
// estimation/experiment_cost.h SampleSigmas) of `experiments`: what
// −2·log-likelihood adds to the weighted Σ r² where σ_k replaces σ (for the
// BIC and AIC). 0 without per-sample σ. Never throws.
double SampleSigmaLogTerm(const std::vector<FitExperiment>& experiments,
                          const std::vector<SampleSigmas>& sample_sigma);

}  // namespace axis

#endif  // ESTIMATION_INTERNAL_INSTANT_SAMPLE_SIGMA_H_
