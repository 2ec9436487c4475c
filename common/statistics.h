// Residual statistics for judging a fit: error measures of a simulated
// channel ŷ against the measured one y, whiteness of the residual (Ljung–Box)
// and its correlation with the input, and the χ² / Student-t distribution
// values the estimator needs (from Boost.Math).
//
// All measures take y and ŷ per sample, in the channel's unit (MODEL.md §6).
// Size errors are std::invalid_argument with messages of the form
//   "<function>: expected y and yhat of equal non-zero length, got 3 and 4".
// Non-finite samples are not rejected: they propagate as NaN or ±inf into
// the result, which the report writes as null.
#ifndef COMMON_STATISTICS_H_
#define COMMON_STATISTICS_H_

#include <vector>

namespace axis {

// Root-mean-square error sqrt((1/m)·Σ_t (ŷ_t − y_t)²), in the channel unit.
// Throws std::invalid_argument if y and yhat differ in length or are empty.
double Rms(const std::vector<double>& y, const std::vector<double>& yhat);

// The standard deviation of the white measurement noise on a sampled
// signal y (equally spaced samples, the channel's unit), from its second
// differences d_k = (y_{k−1} − 2y_k + y_{k+1})/√6, k = 1 … n−2, whose SD
// is the noise's σ for white noise (weights 1, −2, 1) while a signal
// smooth at the sampling rate adds only its curvature (y''·h²/√6): the
// pseudo-residuals of Gasser, Sroka & Jennen-Steinmetz, "Residual
// variance and residual pattern in nonlinear regression", Biometrika 73
// (1986). Estimated robustly as 1.4826·MAD(d) (the median absolute
// deviation about the median; steps and spikes touch two or three d_k and
// do not move it); where more than half of the d_k are equal (a quantised
// or piecewise linear signal: MAD 0) the RMS of d instead. Noise that is
// not white (filtered before sampling) is underestimated. 0 for a signal
// linear in k; NaN for fewer than 3 samples or a non-finite one. Never
// throws (except std::bad_alloc).
double DifferenceNoiseSd(const std::vector<double>& y);

// NRMSE fit in percent, as MATLAB's `compare`:
//   100·(1 − ‖y − ŷ‖₂ / ‖y − mean(y)‖₂).
// 100 for a perfect fit, 0 for ŷ = mean(y), negative if worse than the mean.
// Dimensionless. A constant y gives −inf (NaN if ŷ = y exactly too), by IEEE
// division. Throws as Rms.
double FitPercent(const std::vector<double>& y,
                  const std::vector<double>& yhat);

// Mean absolute error (1/n)·Σ_t |ŷ_t − y_t|, in the channel unit (NaN if a
// sample is NaN): the score of BAM's rollouts (Duclusaud et al., ICRA
// 2025; testdata/bam_xl330/README.md). Throws as Rms.
double MeanAbsError(const std::vector<double>& y, const std::vector<double>& yhat);

// Largest absolute error max_t |ŷ_t − y_t|, in the channel unit (NaN if a
// sample is NaN). Throws as Rms.
double MaxAbsError(const std::vector<double>& y,
                   const std::vector<double>& yhat);

// Relative error in percent, 100·‖ŷ − y‖₂/‖y‖₂ (the measure of the EMPS
// benchmark). Dimensionless. y ≡ 0 gives +inf (NaN if ŷ ≡ 0 too). Throws as
// Rms.
double RelativeErrorPercent(const std::vector<double>& y,
                            const std::vector<double>& yhat);

// Result of a Ljung–Box portmanteau test for whiteness.
struct LjungBox {
  double q = 0.0;        // the statistic Q, dimensionless
  int lags = 0;          // h, the number of autocorrelations summed (= χ² dof)
  double p_value = 0.0;  // P(χ²_h > Q); small means the residual is not white
};

// Ljung–Box test (Ljung & Box 1978) of the residual e_0..e_{m−1}:
//   Q = m(m+2)·Σ_{k=1..h} ρ_k²/(m−k),
//   ρ_k = Σ_{t=k}^{m−1} d_t·d_{t−k} / Σ_{t=0}^{m−1} d_t²,  d = e − mean(e),
// p = P(χ²_h > Q) (Boost.Math chi_squared). A constant residual has no
// autocorrelation: q and p_value are then NaN, as they are for a residual
// with a non-finite sample. Throws std::invalid_argument if lags < 1 or
// lags ≥ m ("LjungBoxTest: expected 1 <= lags < 5 (the residual length),
// got 20").
LjungBox LjungBoxTest(const std::vector<double>& residual, int lags = 20);

// Largest normalised cross-correlation between residual and input.
struct CrossCorrelation {
  double peak = 0.0;  // r_eu at `lag`, signed, in [−1, 1]
  int lag = 0;        // in samples; > 0: the residual follows the input
};

// Normalised cross-correlation of the mean-removed residual e and input u,
//   r_eu(k) = Σ_t e(t)·u(t−k) / (m·σ_e·σ_u),
// σ the population standard deviation (divisor m), the sum over the t with
// both 0 ≤ t < m and 0 ≤ t−k < m, for k in [−max_lag, max_lag]. Returns the
// r of largest |r| (ties go to the smaller |k|, then to k > 0) and its k;
// k > 0 means the residual follows the input by k samples (a dead time the
// model is missing). A constant input or residual gives peak 0, lag 0; a
// non-finite sample gives peak NaN, lag 0. Throws std::invalid_argument if
// the lengths differ or are zero, or unless 0 ≤ max_lag < m.
CrossCorrelation PeakCrossCorrelation(const std::vector<double>& residual,
                                      const std::vector<double>& input,
                                      int max_lag = 20);

// The 0.975 quantile of Student's t distribution with `dof` degrees of
// freedom (boost::math::students_t), the half-width factor of a 95 %
// two-sided interval: 12.706 for 1, 2.0860 for 20, → 1.95996 as dof → ∞.
// Throws std::invalid_argument if dof < 1.
double StudentTQuantile975(int dof);

// Survival function P(χ²_dof > x) (boost::math::chi_squared): 1 for x ≤ 0,
// 0 for x = +inf, NaN for NaN x. Throws std::invalid_argument if dof < 1.
double ChiSquaredSurvival(double x, int dof);

// log P(χ²_dof > x), finite where the p-value itself underflows (x beyond
// ~1400): there from the asymptotic series of the upper incomplete gamma
// function, Γ(s, y) ~ y^(s−1)·e^(−y)·Σ_k (s−1)(s−2)…(s−k)/y^k with s = dof/2,
// y = x/2 (Abramowitz & Stegun 6.5.32). Orders candidates by significance
// when many p-values are 0. Throws std::invalid_argument if dof < 1.
double LogChiSquaredSurvival(double x, int dof);

}  // namespace axis

#endif  // COMMON_STATISTICS_H_
