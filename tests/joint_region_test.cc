// The samples of the fit's joint 95 % region the tuners check a setting at
// (tune/joint_region.h), against the distribution they are drawn from: a
// normal truncated to the ellipse zᵀR⁻¹z ≤ χ²_p(0.95), mapped onto each
// parameter's own interval.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "estimation/fit_result.h"
#include "run/fit_job.h"
#include "sim/config.h"
#include "tune/joint_region.h"

namespace axis {
namespace {

constexpr double kZ95 = 1.959963984540054;
// χ²_2(0.95) = −2 ln 0.05 (the χ² of 2 degrees of freedom is exponential).
const double kRadius2 = -2.0 * std::log(0.05);

ParameterEstimate Free(const std::string& name, double value, double low, double high) {
  ParameterEstimate e;
  e.name = name;
  e.value = value;
  e.free = true;
  e.std_error = (high - low) / (2.0 * kZ95);
  e.ci95_low = low;
  e.ci95_high = high;
  return e;
}

// V_L and B_a with correlation `rho`; T_p free too (the setting a tuner
// skips). B_a's interval is asymmetric: 3 below the estimate, 6 above.
FitResult TwoParameterFit(double rho) {
  FitResult r;
  r.parameters = {Free("V_L", 2.7, 2.6, 2.8), Free("B_a", 200.0, 197.0, 206.0),
                  Free("T_p", 0.04, 0.039, 0.041)};
  r.free_names = {"V_L", "B_a", "T_p"};
  r.correlation = Eigen::MatrixXd::Identity(3, 3);
  r.correlation(0, 1) = r.correlation(1, 0) = rho;
  return r;
}

AxisConfig Model() {
  AxisConfig m;
  m.params.V_L = 2.7;
  m.params.B_a = 200.0;
  m.params.T_p = 0.04;
  return m;
}

// z of a sample: each parameter's offset over its interval's half-width
// on its side, times 1.96 (the inverse of the mapping).
std::vector<double> ZOf(const AxisConfig& m) {
  const double zv = (m.params.V_L - 2.7) / 0.1 * kZ95;
  const double zb = m.params.B_a >= 200.0 ? (m.params.B_a - 200.0) / 6.0 * kZ95
                                          : (m.params.B_a - 200.0) / 3.0 * kZ95;
  return {zv, zb};
}

// 4000 samples at ρ = 0.8: every one inside the region (zᵀR⁻¹z ≤ χ²_2(0.95));
// their correlation is ρ (a normal truncated to an ellipse of its own
// covariance keeps its correlation: the standard error of a sample
// correlation is (1 − ρ²)/√n = 0.0057, so within 4 of them, 0.023); each
// z's variance is E[χ²_2 | χ²_2 ≤ c]/2 = 1 − (c/2)·0.05/0.95 = 0.842 (the
// truncated exponential's mean over 2), within 4 standard errors of a
// variance estimate (√(2/n)·0.842·(kurtosis allowance 1.5) ≈ 0.028, so
// 0.11); the skipped T_p is the estimate's in every sample.
TEST(JointRegionTest, SamplesFollowTheTruncatedNormalOfTheFit) {
  const double rho = 0.8;
  const std::vector<RegionSample> samples =
      JointRegionSamples(TwoParameterFit(rho), Model(), {"T_p"}, {}, 4000);
  ASSERT_EQ(samples.size(), 4000u);
  EXPECT_EQ(samples[2].name, "joint sample 3");
  double sv = 0.0, sb = 0.0, svv = 0.0, sbb = 0.0, svb = 0.0;
  for (const RegionSample& s : samples) {
    EXPECT_EQ(s.model.params.T_p, 0.04);
    const std::vector<double> z = ZOf(s.model);
    const double q = (z[0] * z[0] - 2.0 * rho * z[0] * z[1] + z[1] * z[1]) / (1.0 - rho * rho);
    EXPECT_LE(q, kRadius2 * (1.0 + 1e-12));
    sv += z[0], sb += z[1], svv += z[0] * z[0], sbb += z[1] * z[1], svb += z[0] * z[1];
  }
  const double n = static_cast<double>(samples.size());
  const double var_v = svv / n - (sv / n) * (sv / n);
  const double var_b = sbb / n - (sb / n) * (sb / n);
  const double corr = (svb / n - sv / n * sb / n) / std::sqrt(var_v * var_b);
  EXPECT_NEAR(corr, rho, 4.0 * (1.0 - rho * rho) / std::sqrt(n));
  const double expected_var = 1.0 - 0.5 * kRadius2 * 0.05 / 0.95;
  EXPECT_NEAR(var_v, expected_var, 0.11);
  EXPECT_NEAR(var_b, expected_var, 0.11);
}

// The asymmetric interval is kept: B_a reaches 6·√c/1.96 = 7.5 above the
// estimate at most and 3·√c/1.96 = 3.7 below, and both sides are used.
// The job's bounds clamp: with B_a ≤ 202, no sample goes past 202 and the
// samples that would are at it. The same call gives the same samples.
TEST(JointRegionTest, IntervalsAsymmetryAndBoundsAreKept) {
  const std::vector<RegionSample> free_samples =
      JointRegionSamples(TwoParameterFit(0.0), Model(), {"T_p"}, {}, 500);
  double lowest = 200.0, highest = 200.0;
  for (const RegionSample& s : free_samples) {
    lowest = std::min(lowest, s.model.params.B_a);
    highest = std::max(highest, s.model.params.B_a);
  }
  const double reach = std::sqrt(kRadius2) / kZ95;
  EXPECT_LE(highest, 200.0 + 6.0 * reach + 1e-9);
  EXPECT_GE(lowest, 200.0 - 3.0 * reach - 1e-9);
  EXPECT_GT(highest, 206.0);  // beyond the end: the region is wider than one interval
  EXPECT_LT(lowest, 197.0);
  FreeParameter bound;
  bound.name = "B_a";
  bound.lower = 10.0;
  bound.upper = 202.0;
  const std::vector<RegionSample> clamped =
      JointRegionSamples(TwoParameterFit(0.0), Model(), {"T_p"}, {bound}, 500);
  int at_bound = 0;
  for (size_t k = 0; k < clamped.size(); ++k) {
    EXPECT_LE(clamped[k].model.params.B_a, 202.0);
    at_bound += clamped[k].model.params.B_a == 202.0;
    EXPECT_EQ(clamped[k].model.params.V_L, free_samples[k].model.params.V_L);
  }
  EXPECT_GT(at_bound, 0);
}

// Nothing to sample: no count, or no free parameter left once the skipped
// ones are out.
TEST(JointRegionTest, NoSamplesWithoutCountOrParameters) {
  EXPECT_TRUE(JointRegionSamples(TwoParameterFit(0.5), Model(), {}, {}, 0).empty());
  EXPECT_TRUE(
      JointRegionSamples(TwoParameterFit(0.5), Model(), {"V_L", "B_a", "T_p"}, {}, 10).empty());
}

}  // namespace
}  // namespace axis
