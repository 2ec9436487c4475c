// The notes a fit's result carries beside its numbers (FitResult::integration,
// stop_note, model_note, residual_note; estimation/fit_result.h): how the
// records were integrated, why a stop may depend on the path, what the
// quasi-steady current loop neglects, and a residual far above the noise.
// Each returns "" when there is nothing to say. Never throw.
#ifndef ESTIMATION_FIT_NOTES_H_
#define ESTIMATION_FIT_NOTES_H_

#include <string>
#include <vector>

#include <ceres/ceres.h>

#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"

namespace axis {

// FitResult::integration (estimation/fit_result.h): the RK4 steps of the job's
std::string IntegrationNote(const EstimationProblem& job);

// FitResult::stop_note (estimation/fit_result.h): why a stop on Ceres' parameter
// tolerance on a model that quantises its position feedback may depend on
// the path; empty otherwise.
std::string QuantisedFeedbackStopNote(const EstimationProblem& job,
                                      const ceres::Solver::Summary& summary);

// FitResult::model_note (estimation/fit_result.h). The quasi-steady current loop
// (sim/axis_model.h) follows the current's quasi-steady value without the
// lag τ_i = L/(K_a/K_i + R) of eq. 3 (7.0 µs on the X axis), and a fitted
// sensor delay absorbs part of it: on the noise-free records of the
// sensor_delay discovery case (testdata/generate/discover/), tau_d.a =
// 1.99634 ms against the true 2 ms, −0.52·τ_i, 1.0 standard error of the
// noisy records, with the full loop 2.00000 ms. A bias b lowers a 95 %
// interval's coverage to Φ(1.96 − b/SE) − Φ(−1.96 − b/SE): 94.3 % at a
// quarter of the standard error, 92.1 % at half, 83 % at one (the
// quasi-steady campaign covered 17 of 20). The note is written from a
// quarter on: b ≈ τ_i/2 ≥ SE/4, i.e. τ_i ≥ 0.5·std_error.
std::string QuasiSteadyDelayNote(const EstimationProblem& job, const FitResult& result);

// FitResult::residual_note for a fit that ends at s² = `s2` (empty at or
// below kAutoStartsAbove, or for NaN).
std::string ResidualNote(double s2);

// Misspecification (FitResult::misspecification_note): s² above this (the
// residual RMS 1.4 times σ; the discovery loop's kMisspecifiedS2 alike)
// with a fitted channel whose Ljung–Box p is below kStructuredResidualP.
constexpr double kMisspecifiedS2 = 2.0;
constexpr double kStructuredResidualP = 0.01;

// The fitted channels ("experiment/channel") of `result` with Ljung–Box p
// below kStructuredResidualP. Never throws.
std::vector<std::string> StructuredChannels(const FitResult& result);

// FitResult::misspecification_note: s² = `s2`, the `structured` channels,
// the Newey–West lags, and the sandwich standard errors of the free
// parameters of `result` (their std_error_sandwich). Never throws.
std::string MisspecificationNote(const FitResult& result, double s2,
                                 const std::vector<std::string>& structured, int lags);

}  // namespace axis

#endif  // ESTIMATION_FIT_NOTES_H_
