#include "common/statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/students_t.hpp>

namespace axis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Throws unless y and yhat have the same non-zero length.
void CheckPair(const char* function, const std::vector<double>& y,
               const std::vector<double>& yhat) {
  if (y.empty() || y.size() != yhat.size()) {
    throw std::invalid_argument(
        std::string(function) +
        ": expected y and yhat of equal non-zero length, got " +
        std::to_string(y.size()) + " and " + std::to_string(yhat.size()));
  }
}

// Σ (a_t − b_t)².
double SumSquaredDifference(const std::vector<double>& a,
                            const std::vector<double>& b) {
  double sum = 0.0;
  for (size_t t = 0; t < a.size(); ++t) {
    const double d = a[t] - b[t];
    sum += d * d;
  }
  return sum;
}

double Mean(const std::vector<double>& x) {
  double sum = 0.0;
  for (double v : x) sum += v;
  return sum / static_cast<double>(x.size());
}

// x − mean(x).
std::vector<double> Demeaned(const std::vector<double>& x) {
  const double mean = Mean(x);
  std::vector<double> d(x.size());
  for (size_t t = 0; t < x.size(); ++t) d[t] = x[t] - mean;
  return d;
}

bool AllFinite(const std::vector<double>& x) {
  for (double v : x) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

}  // namespace

double DifferenceNoiseSd(const std::vector<double>& y) {
  const size_t n = y.size();
  if (n < 3) return std::numeric_limits<double>::quiet_NaN();
  std::vector<double> d(n - 2);
  double sum_squares = 0.0;
  for (size_t k = 1; k + 1 < n; ++k) {
    d[k - 1] = (y[k - 1] - 2.0 * y[k] + y[k + 1]) / std::sqrt(6.0);
    sum_squares += d[k - 1] * d[k - 1];
  }
  if (!std::isfinite(sum_squares)) return std::numeric_limits<double>::quiet_NaN();
  const auto median = [](std::vector<double> v) {
    const size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + mid, v.end());
    double m = v[mid];
    if (v.size() % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + mid));
    return m;
  };
  const double centre = median(d);
  std::vector<double> deviation(d.size());
  for (size_t k = 0; k < d.size(); ++k) deviation[k] = std::abs(d[k] - centre);
  const double mad = median(deviation);
  // 1.4826 = 1/Φ⁻¹(3/4): MAD of a normal sample to its SD.
  if (mad > 0.0) return 1.4826 * mad;
  return std::sqrt(sum_squares / static_cast<double>(d.size()));
}

double Rms(const std::vector<double>& y, const std::vector<double>& yhat) {
  CheckPair("Rms", y, yhat);
  return std::sqrt(SumSquaredDifference(yhat, y) /
                   static_cast<double>(y.size()));
}

double FitPercent(const std::vector<double>& y,
                  const std::vector<double>& yhat) {
  CheckPair("FitPercent", y, yhat);
  const double error = std::sqrt(SumSquaredDifference(y, yhat));
  const std::vector<double> mean(y.size(), Mean(y));
  const double spread = std::sqrt(SumSquaredDifference(y, mean));
  return 100.0 * (1.0 - error / spread);
}

double MeanAbsError(const std::vector<double>& y, const std::vector<double>& yhat) {
  CheckPair("MeanAbsError", y, yhat);
  double sum = 0.0;
  for (size_t t = 0; t < y.size(); ++t) sum += std::abs(yhat[t] - y[t]);
  return sum / static_cast<double>(y.size());
}

double MaxAbsError(const std::vector<double>& y,
                   const std::vector<double>& yhat) {
  CheckPair("MaxAbsError", y, yhat);
  double max = 0.0;
  for (size_t t = 0; t < y.size(); ++t) {
    const double e = std::abs(yhat[t] - y[t]);
    if (std::isnan(e)) return kNaN;
    if (e > max) max = e;
  }
  return max;
}

double RelativeErrorPercent(const std::vector<double>& y,
                            const std::vector<double>& yhat) {
  CheckPair("RelativeErrorPercent", y, yhat);
  const std::vector<double> zero(y.size(), 0.0);
  return 100.0 * std::sqrt(SumSquaredDifference(yhat, y)) /
         std::sqrt(SumSquaredDifference(y, zero));
}

LjungBox LjungBoxTest(const std::vector<double>& residual, int lags) {
  const size_t m = residual.size();
  if (lags < 1 || static_cast<size_t>(lags) >= m) {
    throw std::invalid_argument(
        "LjungBoxTest: expected 1 <= lags < " + std::to_string(m) +
        " (the residual length), got " + std::to_string(lags));
  }
  LjungBox result;
  result.lags = lags;
  const std::vector<double> d = Demeaned(residual);
  double c0 = 0.0;
  for (double v : d) c0 += v * v;
  if (!(c0 > 0.0) || !std::isfinite(c0)) {
    result.q = result.p_value = kNaN;
    return result;
  }
  const double md = static_cast<double>(m);
  double sum = 0.0;
  for (int k = 1; k <= lags; ++k) {
    double ck = 0.0;
    for (size_t t = static_cast<size_t>(k); t < m; ++t) ck += d[t] * d[t - k];
    const double rho = ck / c0;
    sum += rho * rho / (md - k);
  }
  result.q = md * (md + 2.0) * sum;
  result.p_value = ChiSquaredSurvival(result.q, lags);
  return result;
}

CrossCorrelation PeakCrossCorrelation(const std::vector<double>& residual,
                                      const std::vector<double>& input,
                                      int max_lag) {
  const size_t m = residual.size();
  if (m == 0 || input.size() != m) {
    throw std::invalid_argument(
        "PeakCrossCorrelation: expected residual and input of equal non-zero "
        "length, got " +
        std::to_string(m) + " and " + std::to_string(input.size()));
  }
  if (max_lag < 0 || static_cast<size_t>(max_lag) >= m) {
    throw std::invalid_argument(
        "PeakCrossCorrelation: expected 0 <= max_lag < " + std::to_string(m) +
        " (the series length), got " + std::to_string(max_lag));
  }
  CrossCorrelation best;
  if (!AllFinite(residual) || !AllFinite(input)) {
    best.peak = kNaN;
    return best;
  }
  const std::vector<double> e = Demeaned(residual);
  const std::vector<double> u = Demeaned(input);
  double see = 0.0;
  double suu = 0.0;
  for (size_t t = 0; t < m; ++t) {
    see += e[t] * e[t];
    suu += u[t] * u[t];
  }
  // m·σ_e·σ_u with σ² = Σd²/m is sqrt(Σe²·Σu²).
  const double norm = std::sqrt(see * suu);
  if (!(norm > 0.0) || !std::isfinite(norm)) return best;
  const long n = static_cast<long>(m);
  // k = 0, 1, −1, 2, −2, ...: with a strict comparison, ties keep the
  // smaller |k|, and k > 0 before −k.
  for (int step = 0; step <= 2 * max_lag; ++step) {
    const int k = (step % 2 == 1) ? (step + 1) / 2 : -(step / 2);
    double sum = 0.0;
    for (long t = std::max(0L, static_cast<long>(k));
         t < std::min(n, n + k); ++t) {
      sum += e[t] * u[t - k];
    }
    const double r = sum / norm;
    if (step == 0 || std::abs(r) > std::abs(best.peak)) {
      best.peak = r;
      best.lag = k;
    }
  }
  return best;
}

double StudentTQuantile975(int dof) {
  if (dof < 1) {
    throw std::invalid_argument(
        "StudentTQuantile975: expected at least 1 degree of freedom, got " +
        std::to_string(dof));
  }
  const boost::math::students_t distribution(static_cast<double>(dof));
  return boost::math::quantile(distribution, 0.975);
}

double ChiSquaredSurvival(double x, int dof) {
  if (dof < 1) {
    throw std::invalid_argument(
        "ChiSquaredSurvival: expected at least 1 degree of freedom, got " +
        std::to_string(dof));
  }
  if (std::isnan(x)) return kNaN;
  if (x <= 0.0) return 1.0;
  if (std::isinf(x)) return 0.0;
  const boost::math::chi_squared distribution(static_cast<double>(dof));
  return boost::math::cdf(boost::math::complement(distribution, x));
}

double LogChiSquaredSurvival(double x, int dof) {
  const double p = ChiSquaredSurvival(x, dof);
  if (!(p < 1e-280) || std::isinf(x)) return std::log(p);
  const double s = 0.5 * dof;
  const double y = 0.5 * x;
  double term = 1.0, sum = 1.0;
  for (int k = 1; k <= 30; ++k) {
    term *= (s - k) / y;
    sum += term;
    if (std::abs(term) < 1e-16 * std::abs(sum)) break;
  }
  return (s - 1.0) * std::log(y) - y - std::lgamma(s) + std::log(sum);
}

}  // namespace axis
