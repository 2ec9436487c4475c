// The records' alignment lag (estimation/alignment_lag.h) against known
// shifts of a smooth signal: 0.1 to 20 samples, both signs, with and
// without noise, across two records.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "estimation/alignment_lag.h"
#include "estimation/fit_result.h"

namespace axis {
namespace {

constexpr double kPeriod = 1e-3;  // s, a 1 kHz record
constexpr double kPi = 3.14159265358979323846;

// A band-limited test signal: a sum of sines of 2–60 Hz (slow against the
// 500 Hz Nyquist frequency, as a servo axis's tachometer or acceleration).
double Signal(double t) {
  return std::sin(2 * kPi * 2.0 * t) + 0.5 * std::sin(2 * kPi * 11.0 * t + 0.3) +
         0.2 * std::sin(2 * kPi * 37.0 * t + 1.1) + 0.1 * std::sin(2 * kPi * 60.0 * t);
}

// A fit whose record of `channel` is the signal late by `delay` (plus noise
// of `sigma`), its simulation the signal itself, over `n` samples.
ExperimentFit Record(double delay, double sigma, int n, unsigned seed, double t0 = 0.0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  ExperimentFit e;
  e.name = "r" + std::to_string(seed);
  e.role = "fit";
  ChannelFit c;
  c.channel = "tach";
  c.fitted = true;
  c.sigma = sigma > 0 ? sigma : 1.0;
  for (int k = 0; k < n; ++k) {
    const double t = t0 + k * kPeriod;
    e.t.push_back(k * kPeriod);
    c.simulated.push_back(Signal(t));
    c.measured.push_back(Signal(t - delay) + (sigma > 0 ? noise(rng) : 0.0));
  }
  e.channels.push_back(c);
  return e;
}

TEST(AlignmentLagTest, FindsDelaysFromATenthToTwentySamplesEitherWay) {
  for (double samples : {0.1, 0.3, 0.5, 1.0, 2.5, 3.0, 7.0, 12.5, 20.0}) {
    for (double sign : {1.0, -1.0}) {
      const double delay = sign * samples * kPeriod;
      FitResult fit;
      fit.experiments = {Record(delay, 0.0, 2000, 1)};
      const double lag = AlignmentLag(fit, "tach", 0.05);
      // Noise-free: the parabola through three whole lags of a smooth
      // misfit, its vertex within a tenth of a sample of the shift.
      EXPECT_NEAR(lag, delay, 0.1 * kPeriod) << samples << " samples, sign " << sign;
    }
  }
}

TEST(AlignmentLagTest, HoldsUnderNoiseAndPoolsTheRecords) {
  for (double samples : {3.0, -6.0, 15.0}) {
    const double delay = samples * kPeriod;
    FitResult fit;
    fit.experiments = {Record(delay, 0.05, 4000, 2), Record(delay, 0.05, 4000, 3, 0.37)};
    EXPECT_NEAR(AlignmentLag(fit, "tach", 0.1), delay, 0.25 * kPeriod) << samples;
  }
}

// A lag far beyond a sample on a slow record: 300 ms on a 4 s record.
TEST(AlignmentLagTest, FindsHundredsOfMilliseconds) {
  FitResult fit;
  fit.experiments = {Record(0.3, 0.0, 4000, 4)};
  EXPECT_NEAR(AlignmentLag(fit, "tach", 1.0), 0.3, 0.1 * kPeriod);
}

TEST(AlignmentLagTest, NaNWithoutTheChannel) {
  FitResult fit;
  fit.experiments = {Record(0.0, 0.0, 100, 5)};
  EXPECT_TRUE(std::isnan(AlignmentLag(fit, "a", 0.01)));
  fit.experiments[0].channels[0].fitted = false;
  EXPECT_TRUE(std::isnan(AlignmentLag(fit, "tach", 0.01)));
}

}  // namespace
}  // namespace axis
