// Residual diagnostics after a fit (issue 4, step 1): for every fitted
// channel, whiteness (Ljung–Box), cross-correlation with the input (its lag
// hints at a delay), and the mean residual in bins of arm velocity
// (sign-dependent steps hint at Coulomb or asymmetric friction), position,
// acceleration and motor angle modulo one revolution (periodic patterns hint
// at cogging), each with a χ² test of "no structure".
#ifndef DISCOVERY_DIAGNOSTICS_H_
#define DISCOVERY_DIAGNOSTICS_H_

#include <string>
#include <vector>

#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"

namespace axis {

// Mean residual (simulated − measured, channel unit) in equal-width bins of
// one variable. Bins with fewer than 10 samples are dropped.
struct BinnedResidual {
  std::string variable;  // "v", "x", "a", "theta mod rev"
  std::string unit;
  std::vector<double> center, mean, std_error;
  std::vector<int> count;
  double width = 0.0;  // bin width, unit of the variable
  // Σ (mean/std_error)² over the bins, χ² with `dof` = number of bins under
  // "every bin's mean residual is 0": the bin means are tested against zero,
  // not against their overall mean, so a constant offset of the residual
  // (a sensor bias the model lacks) fails this test for every variable
  // alike, and a failed test says "depends on" the variable for either.
  // std_error = s/√n with s the residual's standard deviation about its
  // mean (ignores autocorrelation, so p is optimistic for coloured
  // residuals: read it as a ranking).
  double chi2 = 0.0;
  int dof = 0;
  double p_value = 1.0;
};

struct ChannelDiagnostics {
  std::string experiment, channel, unit;
  double rms = 0.0;    // residual RMS, channel unit
  double sigma = 0.0;  // declared noise σ the residual is weighted by
  double ljung_box_p = 1.0;
  double xcorr_peak = 0.0;
  int xcorr_lag = 0;
  std::vector<BinnedResidual> bins;
};

// Diagnoses the fitted channels of every fitted experiment of `job` at the
// job's current parameter values (job.model.params). Throws
// std::runtime_error if a simulation fails.
std::vector<ChannelDiagnostics> DiagnoseResiduals(const EstimationProblem& job);

// A table: per experiment and channel, Ljung–Box p, cross-correlation peak
// and lag, and per variable the χ² p-value and the largest |bin mean|.
std::string FormatDiagnostics(const std::vector<ChannelDiagnostics>& d);

// Writes the bins of `d` as CSV (variable, center, mean, std_error, count;
// one row per bin). Throws std::runtime_error naming `path` if it cannot
// be written.
void WriteDiagnosticsCsv(const std::string& path, const ChannelDiagnostics& d);

// The gnuplot commands that plot the bins of `d` from `csv_path` (written
// by WriteDiagnosticsCsv) into `output`: one panel per variable, the bin
// means with ±1 standard error bars against the variable (units on the
// axes) and the zero line. `svg`: gnuplot's svg terminal, scalable
// (RenderGnuplotSvg, report/report.h), with a legend; else a 1200×800 PNG.
// Paths must not contain a quote or a line break.
std::string DiagnosticsPlotScript(const ChannelDiagnostics& d, const std::string& csv_path,
                                  const std::string& output, bool svg);

// Writes diag_<experiment>_<channel>.csv (variable, center, mean, std_error,
// count) and .png (one panel per variable, gnuplot) into `dir`; gnuplot
// problems are appended to `warnings`. Throws std::runtime_error if a file
// cannot be written.
void WriteDiagnostics(const std::string& dir,
                      const std::vector<ChannelDiagnostics>& d,
                      std::vector<std::string>* warnings);

// The verdict on a model's residuals after the discovery loop (issue 10):
// "explained" when they are consistent with the declared noise, else
// "incomplete" with what remains. At family-wise level `alpha`, Bonferroni
// over all the tests below (threshold = alpha / tests):
// - s² = Σ((ŷ − y)/σ)²/(m − n) (FitResult::residual_variance, m − n its
//   residual_dof) not above 1: P(χ²_{m−n} > Σ((ŷ − y)/σ)²) ≥ threshold
//   (upper tail only: a σ declared too large is not a missing effect);
// - per fitted channel, Ljung–Box (20 lags) p ≥ threshold: white;
// - per channel and binned variable, the χ² of the bin means p ≥
//   threshold: the residual's mean is 0 in every bin of v, x, a and θ mod
//   rev (no dependence on them, and no offset: BinnedResidual).
// A failed bin test names where the residual is significant: the runs of
// bins whose own χ²₁ = (mean/std_error)² has p < threshold / bins.
struct ResidualVerdict {
  std::string verdict;        // "explained" or "incomplete"
  double s2 = 0.0;            // residual variance in σ units
  double s2_p_value = 1.0;    // P(χ²_{m−n} > (m − n)·s2)
  int tests = 0;              // number of tests (Bonferroni)
  double threshold = 0.0;     // alpha / tests
  // Per channel: "experiment/channel: RMS 0.012 m/s^2 = 1.02 sigma", with
  // "; white, no structure" when all its tests pass.
  std::vector<std::string> channels;
  // The failed tests, one line each, e.g. "e/a: not white (Ljung-Box p
  // 3e-12)", "e/a: mean residual depends on x (chi2 p 1e-9): significant
  // for x in [0.12, 0.31] m (largest |mean| 0.2 m/s^2)".
  std::vector<std::string> remains;
};

// Judges `diagnostics` (DiagnoseResiduals of the final model) with the
// fit's s² (`fit`: residual_variance and residual_dof; s² and its p-value
// NaN if residual_dof < 0.5).
// Throws std::invalid_argument unless alpha > 0 (a level of 1 or more
// makes every test fail: nothing counts as explained).
ResidualVerdict JudgeResiduals(const std::vector<ChannelDiagnostics>& diagnostics,
                               const FitResult& fit, double alpha);

// The verdict as text: the verdict, s², one line per channel.
std::string FormatVerdict(const ResidualVerdict& verdict);

}  // namespace axis

#endif  // DISCOVERY_DIAGNOSTICS_H_
