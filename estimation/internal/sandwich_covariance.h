// The sandwich (Huber–White) covariance of a least-squares estimate with
// the residuals' autocorrelation (Newey–West): the interval of a fit whose
// model misses part of the data (s² well above 1, structured residuals),
// where (JᵀJ)⁻¹·s² assumes white residuals of one variance.
#ifndef ESTIMATION_INTERNAL_SANDWICH_COVARIANCE_H_
#define ESTIMATION_INTERNAL_SANDWICH_COVARIANCE_H_

#include <vector>

#include <Eigen/Core>

namespace axis {

// Newey–West covariance of θ for the cost ½Σr²:
//   C = B·S·B,  B = (JᵀJ)⁺,
//   S = Σ_series [ Σ_t g_t g_tᵀ + Σ_{l=1}^{L} w_l Σ_t (g_t g_{t−l}ᵀ + g_{t−l} g_tᵀ) ],
//   g_t = J_tᵀ r_t,  w_l = 1 − l/(L + 1) (Bartlett),
// the inner sums over the t of one series (lags never cross a series
// boundary: the residuals of one channel of one experiment are one series).
// J: m×n Jacobian of the residuals r (m) at the estimate, r in the units of
// the cost (σ-weighted); `series`: the lengths of the consecutive series the
// rows form, summing to m; `lags` = L ≥ 0 (0 is HC0, White 1980). No
// small-sample factor m/(m − n). B is the pseudo-inverse (eigenvalues below
// 1e-14 of the largest dropped). Returns n×n in the units of θ².
// Throws std::invalid_argument if r.size() ≠ m, the series do not sum to m
// or one is negative, or lags < 0. Source: Newey & West, "A simple,
// positive semi-definite, heteroskedasticity and autocorrelation
// consistent covariance matrix", Econometrica 55 (1987); White,
// Econometrica 48 (1980).
Eigen::MatrixXd NeweyWestCovariance(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& r,
                                    const std::vector<int>& series, int lags);

}  // namespace axis

#endif  // ESTIMATION_INTERNAL_SANDWICH_COVARIANCE_H_
