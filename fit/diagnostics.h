// Residual diagnostics after a fit (issue 4, step 1): for every fitted
// channel, whiteness (Ljung–Box), cross-correlation with the input (its lag
// hints at a delay), and the mean residual in bins of arm velocity
// (sign-dependent steps hint at Coulomb or asymmetric friction), position,
// acceleration and motor angle modulo one revolution (periodic patterns hint
// at cogging), each with a χ² test of "no structure".
#ifndef FIT_DIAGNOSTICS_H_
#define FIT_DIAGNOSTICS_H_

#include <string>
#include <vector>

#include "fit/job.h"

namespace axis {

// Mean residual (simulated − measured, channel unit) in equal-width bins of
// one variable. Bins with fewer than 10 samples are dropped.
struct BinnedResidual {
  std::string variable;  // "v", "x", "a", "theta mod rev"
  std::string unit;
  std::vector<double> center, mean, std_error;
  std::vector<int> count;
  // Σ (mean/std_error)² over the bins, χ² with `dof` = number of bins under
  // "the residual does not depend on the variable"; std_error = s/√n with s
  // the residual's standard deviation (ignores autocorrelation, so p is
  // optimistic for coloured residuals: read it as a ranking).
  double chi2 = 0.0;
  int dof = 0;
  double p_value = 1.0;
};

struct ChannelDiagnostics {
  std::string experiment, channel, unit;
  double ljung_box_p = 1.0;
  double xcorr_peak = 0.0;
  int xcorr_lag = 0;
  std::vector<BinnedResidual> bins;
};

// Diagnoses the fitted channels of every fitted experiment of `job` at the
// job's current parameter values (job.model.params). Throws
// std::runtime_error if a simulation fails.
std::vector<ChannelDiagnostics> DiagnoseResiduals(const FitJob& job);

// A table: per experiment and channel, Ljung–Box p, cross-correlation peak
// and lag, and per variable the χ² p-value and the largest |bin mean|.
std::string FormatDiagnostics(const std::vector<ChannelDiagnostics>& d);

// Writes diag_<experiment>_<channel>.csv (variable, center, mean, std_error,
// count) and .png (one panel per variable, gnuplot) into `dir`; gnuplot
// problems are appended to `warnings`. Throws std::runtime_error if a file
// cannot be written.
void WriteDiagnostics(const std::string& dir,
                      const std::vector<ChannelDiagnostics>& d,
                      std::vector<std::string>* warnings);

}  // namespace axis

#endif  // FIT_DIAGNOSTICS_H_
