// Residual statistics against closed forms and hand-computed values.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/statistics.h"
#include "sim/random.h"

namespace axis {
namespace {

// Gaussian white noise of unit variance, m samples, from the project's
// generator (sim/random.h) seeded with `seed`.
std::vector<double> WhiteNoise(size_t m, unsigned seed) {
  RandomEngine rng(seed);
  std::vector<double> e(m);
  for (double& v : e) v = StandardNormal(rng);
  return e;
}

TEST(StatisticsTest, FitPercentOfPerfectFitIs100AndOfMeanIs0) {
  const std::vector<double> y = {0.5, -1.0, 2.0, 3.5, 0.0};
  EXPECT_DOUBLE_EQ(FitPercent(y, y), 100.0);
  double mean = 0.0;
  for (double v : y) mean += v;
  mean /= static_cast<double>(y.size());
  EXPECT_NEAR(FitPercent(y, std::vector<double>(y.size(), mean)), 0.0, 1e-12);
}

TEST(StatisticsTest, MeasuresOnHandValues) {
  // Errors ŷ − y = (0, 1, 0, −2): Σe² = 5, ‖y‖² = 1 + 4 + 9 + 16 = 30.
  const std::vector<double> y = {1, 2, 3, 4};
  const std::vector<double> yhat = {1, 3, 3, 2};
  EXPECT_DOUBLE_EQ(Rms(y, yhat), std::sqrt(5.0 / 4.0));        // 1.118034
  EXPECT_DOUBLE_EQ(MaxAbsError(y, yhat), 2.0);
  EXPECT_DOUBLE_EQ(RelativeErrorPercent(y, yhat),
                   100.0 * std::sqrt(5.0 / 30.0));             // 40.8248 %
  // ‖y − mean(y)‖² = 2.25 + 0.25 + 0.25 + 2.25 = 5 = ‖y − ŷ‖²: fit 0 %.
  EXPECT_NEAR(FitPercent(y, yhat), 0.0, 1e-12);
  // y = (0, 2, 4), ŷ = (1, 2, 3): ‖y − ŷ‖ = √2, ‖y − 2‖ = √8, fit 50 %.
  EXPECT_DOUBLE_EQ(FitPercent({0, 2, 4}, {1, 2, 3}), 50.0);
}

TEST(StatisticsTest, ConstantMeasurementGivesNonFiniteFitPercent) {
  const std::vector<double> y = {2, 2, 2};
  EXPECT_TRUE(std::isinf(FitPercent(y, {2, 2, 3})));
  EXPECT_TRUE(std::isnan(FitPercent(y, y)));
  EXPECT_TRUE(std::isinf(RelativeErrorPercent({0, 0}, {1, 0})));
}

TEST(StatisticsTest, SizeMismatchAndEmptyThrow) {
  try {
    Rms({1, 2, 3}, {1, 2, 3, 4});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "expected y and yhat of equal non-zero length, got 3 and 4"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(FitPercent({}, {}), std::invalid_argument);
  EXPECT_THROW(MaxAbsError({1}, {}), std::invalid_argument);
  EXPECT_THROW(RelativeErrorPercent({1, 2}, {1}), std::invalid_argument);
}

TEST(StatisticsTest, LjungBoxOnHandComputedSeries) {
  // e = (1, −1, 1, −1): mean 0, Σd² = 4; Σ d_t d_{t−1} = −3 → ρ1 = −0.75;
  // Σ d_t d_{t−2} = 2 → ρ2 = 0.5. h = 2, m = 4:
  //   Q = 4·6·(0.5625/3 + 0.25/2) = 24·0.3125 = 7.5,
  // and for 2 dof P(χ² > Q) = exp(−Q/2) = exp(−3.75).
  const LjungBox a = LjungBoxTest({1, -1, 1, -1}, 2);
  EXPECT_DOUBLE_EQ(a.q, 7.5);
  EXPECT_EQ(a.lags, 2);
  EXPECT_NEAR(a.p_value, std::exp(-3.75), 1e-14);

  // e = (1, 2, 3, 4, 5): d = (−2, −1, 0, 1, 2), Σd² = 10,
  // Σ d_t d_{t−1} = 2 + 0 + 0 + 2 = 4 → ρ1 = 0.4; h = 1, m = 5:
  //   Q = 5·7·0.16/4 = 1.4, and for 1 dof P(χ² > Q) = erfc(√(Q/2)).
  const LjungBox b = LjungBoxTest({1, 2, 3, 4, 5}, 1);
  EXPECT_NEAR(b.q, 1.4, 1e-14);
  EXPECT_NEAR(b.p_value, std::erfc(std::sqrt(0.7)), 1e-14);
}

// On white noise the test holds its level: over 400 seeds (m = 2000, 20
// lags) it rejects at 5 % in 20 ± 4.4 cases (binomial); 4 standard
// deviations either way. One seed alone would fail 1 time in 20.
TEST(StatisticsTest, LjungBoxAcceptsWhiteNoise) {
  constexpr int kSeeds = 400;
  int rejected = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const LjungBox lb = LjungBoxTest(WhiteNoise(2000, 20240500u + seed), 20);
    EXPECT_EQ(lb.lags, 20);
    rejected += lb.p_value < 0.05;
  }
  std::cout << "white noise, 400 seeds, m = 2000: rejected at 5 % in " << rejected << "\n";
  const double sd = std::sqrt(kSeeds * 0.05 * 0.95);
  EXPECT_NEAR(rejected, 0.05 * kSeeds, 4.0 * sd);
}

// The noise under a smooth signal with a step: 20 000 samples at 1 ms of a
// 1 Hz sine of 5 units (its curvature adds 8e-5 to the SD of the second
// differences), a step of 30 (100 σ) halfway, white noise σ = 0.3. The
// MAD estimate's relative SD is about 1.2 % here (1.16/√n for independent
// samples, the second differences' correlation adding about half); 5 % is
// 4 of them, over 20 seeds. A record linear in k has no noise; too short a
// record or a NaN gives NaN.
TEST(StatisticsTest, DifferenceNoiseSdFindsTheNoiseUnderASmoothSignalAndAStep) {
  constexpr size_t kN = 20000;
  double worst = 0.0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const std::vector<double> e = WhiteNoise(kN, 20261125u + seed);
    std::vector<double> y(kN);
    for (size_t k = 0; k < kN; ++k) {
      const double t = 1e-3 * static_cast<double>(k);
      y[k] = 5.0 * std::sin(2.0 * M_PI * t) + (k >= kN / 2 ? 30.0 : 0.0) + 0.3 * e[k];
    }
    const double sd = DifferenceNoiseSd(y);
    worst = std::max(worst, std::abs(sd / 0.3 - 1.0));
    EXPECT_NEAR(sd / 0.3, 1.0, 0.05) << "seed " << seed;
  }
  std::cout << "DifferenceNoiseSd: largest relative error over 20 seeds " << worst << "\n";
  std::vector<double> line(100);
  for (size_t k = 0; k < line.size(); ++k) line[k] = 2.0 + 0.5 * static_cast<double>(k);
  EXPECT_NEAR(DifferenceNoiseSd(line), 0.0, 1e-12);
  EXPECT_TRUE(std::isnan(DifferenceNoiseSd({1.0, 2.0})));
  line[50] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(DifferenceNoiseSd(line)));
}

TEST(StatisticsTest, LjungBoxRejectsAr1) {
  // e_t = 0.5·e_{t−1} + w_t: ρ1 ≈ 0.5, so Q ≈ 2000·0.25 + ... ≫ χ²_20 tail.
  const std::vector<double> w = WhiteNoise(2000, 7u);
  std::vector<double> e(w.size());
  e[0] = w[0];
  for (size_t t = 1; t < e.size(); ++t) e[t] = 0.5 * e[t - 1] + w[t];
  const LjungBox lb = LjungBoxTest(e, 20);
  std::cout << "AR(1) phi = 0.5 (seed 7, m = 2000): Q = " << lb.q
            << ", p = " << lb.p_value << "\n";
  EXPECT_LT(lb.p_value, 1e-6);
}

TEST(StatisticsTest, LjungBoxEdgeCases) {
  EXPECT_THROW(LjungBoxTest({1, 2, 3}, 3), std::invalid_argument);
  EXPECT_THROW(LjungBoxTest({1, 2, 3}, 0), std::invalid_argument);
  EXPECT_THROW(LjungBoxTest({}, 1), std::invalid_argument);
  const LjungBox constant = LjungBoxTest({2, 2, 2, 2}, 2);
  EXPECT_TRUE(std::isnan(constant.q));
  EXPECT_TRUE(std::isnan(constant.p_value));
  const LjungBox nan = LjungBoxTest({1, NAN, 2, 3}, 2);
  EXPECT_TRUE(std::isnan(nan.p_value));
}

TEST(StatisticsTest, ChiSquaredSurvivalMatchesTables) {
  // Upper-tail critical values of χ² tables.
  EXPECT_NEAR(ChiSquaredSurvival(31.410, 20), 0.05, 1e-4);
  EXPECT_NEAR(ChiSquaredSurvival(3.841, 1), 0.05, 1e-4);
  EXPECT_NEAR(ChiSquaredSurvival(23.209, 10), 0.01, 1e-5);
  EXPECT_NEAR(ChiSquaredSurvival(37.566, 20), 0.01, 1e-5);
  // Closed form for 2 dof: exp(−x/2).
  EXPECT_NEAR(ChiSquaredSurvival(5.0, 2), std::exp(-2.5), 1e-15);
  EXPECT_EQ(ChiSquaredSurvival(0.0, 3), 1.0);
  EXPECT_EQ(ChiSquaredSurvival(-1.0, 3), 1.0);
  EXPECT_EQ(ChiSquaredSurvival(INFINITY, 3), 0.0);
  EXPECT_TRUE(std::isnan(ChiSquaredSurvival(NAN, 3)));
  EXPECT_THROW(ChiSquaredSurvival(1.0, 0), std::invalid_argument);
}

// Where the p-value underflows, its logarithm from the asymptotic series
// against closed forms: 2 dof, log Q = −x/2; 4 dof, Q = e^(−y)(1 + y) with
// y = x/2; 1 dof, Q = erfc(z), z = √(x/2), whose own asymptotic expansion is
// log erfc z = −z² − log(z√π) + log(1 − 1/(2z²) + 3/(4z⁴) − 15/(8z⁶)) to
// within ~1e-12 at z² = 1000 (A&S 7.1.23).
TEST(StatisticsTest, LogChiSquaredSurvivalBeyondUnderflow) {
  EXPECT_EQ(ChiSquaredSurvival(2000.0, 2), 0.0);
  EXPECT_NEAR(LogChiSquaredSurvival(2000.0, 2), -1000.0, 1e-9);
  EXPECT_NEAR(LogChiSquaredSurvival(1e5, 2), -5e4, 1e-7);
  EXPECT_NEAR(LogChiSquaredSurvival(3000.0, 4), -1500.0 + std::log(1501.0), 1e-9);
  const double z2 = 1000.0, z = std::sqrt(z2);
  const double log_erfc = -z2 - std::log(z * std::sqrt(M_PI)) +
                          std::log(1 - 1 / (2 * z2) + 3 / (4 * z2 * z2) -
                                   15 / (8 * z2 * z2 * z2));
  EXPECT_NEAR(LogChiSquaredSurvival(2 * z2, 1), log_erfc, 1e-9);
  // Where the p-value is representable, the plain logarithm.
  EXPECT_NEAR(LogChiSquaredSurvival(37.566, 20), std::log(0.01), 1e-4);
  // 1.9e5 on 1 dof is more significant than 1.5e5 on 2 dof (log p −95006
  // vs −75000), the ordering the discovery ranking relies on (the
  // Wilson–Hilferty normal deviate orders these two the other way).
  EXPECT_LT(LogChiSquaredSurvival(1.9e5, 1), LogChiSquaredSurvival(1.5e5, 2));
  EXPECT_THROW(LogChiSquaredSurvival(1.0, 0), std::invalid_argument);
}

TEST(StatisticsTest, StudentTQuantileMatchesTables) {
  EXPECT_NEAR(StudentTQuantile975(1), 12.7062, 1e-4);
  EXPECT_NEAR(StudentTQuantile975(10), 2.2281, 1e-4);
  EXPECT_NEAR(StudentTQuantile975(20), 2.0860, 1e-4);
  EXPECT_NEAR(StudentTQuantile975(1000000), 1.959966, 1e-5);
  EXPECT_THROW(StudentTQuantile975(0), std::invalid_argument);
}

TEST(StatisticsTest, CrossCorrelationFindsKnownLag) {
  const std::vector<double> u = WhiteNoise(1000, 11u);
  // Residual = input delayed by 3 samples: lag +3, peak ≈ 1.
  std::vector<double> delayed(u.size(), 0.0);
  for (size_t t = 3; t < u.size(); ++t) delayed[t] = u[t - 3];
  const CrossCorrelation d = PeakCrossCorrelation(delayed, u, 20);
  std::cout << "delayed copy: peak = " << d.peak << ", lag = " << d.lag << "\n";
  EXPECT_EQ(d.lag, 3);
  EXPECT_NEAR(d.peak, 1.0, 0.01);
  // A negated copy leading the input by 2: lag −2, peak ≈ −1.
  std::vector<double> leading(u.size(), 0.0);
  for (size_t t = 0; t + 2 < u.size(); ++t) leading[t] = -u[t + 2];
  const CrossCorrelation l = PeakCrossCorrelation(leading, u, 20);
  EXPECT_EQ(l.lag, -2);
  EXPECT_NEAR(l.peak, -1.0, 0.01);
  // Independent noise: no peak above a few 1/√m.
  const CrossCorrelation n = PeakCrossCorrelation(WhiteNoise(1000, 12u), u, 20);
  EXPECT_LT(std::abs(n.peak), 0.15);
}

TEST(StatisticsTest, CrossCorrelationExactOnHandValues) {
  // e = u = (1, −1, 1, −1) (mean 0, σ = 1, m = 4): r(0) = 1 exactly, and
  // r(±1) = −3/4, so the peak is 1 at lag 0.
  const CrossCorrelation c = PeakCrossCorrelation({1, -1, 1, -1}, {1, -1, 1, -1}, 1);
  EXPECT_DOUBLE_EQ(c.peak, 1.0);
  EXPECT_EQ(c.lag, 0);
}

TEST(StatisticsTest, CrossCorrelationEdgeCases) {
  const CrossCorrelation constant =
      PeakCrossCorrelation({1, 2, 3, 4}, {5, 5, 5, 5}, 2);
  EXPECT_EQ(constant.peak, 0.0);
  EXPECT_EQ(constant.lag, 0);
  EXPECT_THROW(PeakCrossCorrelation({1, 2, 3}, {1, 2}, 1), std::invalid_argument);
  EXPECT_THROW(PeakCrossCorrelation({1, 2, 3}, {1, 2, 3}, 3),
               std::invalid_argument);
  EXPECT_THROW(PeakCrossCorrelation({1, 2, 3}, {1, 2, 3}, -1),
               std::invalid_argument);
  EXPECT_TRUE(std::isnan(PeakCrossCorrelation({1, NAN, 3}, {1, 2, 3}, 1).peak));
}

}  // namespace
}  // namespace axis
