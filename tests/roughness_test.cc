// Issue 42's checks of a fit, each against a case whose answer is known:
// random starts at the job's cost or below it (estimation/internal/start_agreement.h),
// probe rounds with gains below the roughness scale
// (estimation/internal/rough_optimum.h), and the covariance at the smooth scale of a
// cost whose local slope is a sawtooth's (estimation/internal/smooth_scale.h).
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "estimation/experiment_cost.h"
#include "estimation/internal/rough_optimum.h"
#include "estimation/internal/smooth_scale.h"
#include "estimation/internal/start_agreement.h"

namespace axis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// s² = 9.6, so the tolerance is ½·3.84·9.6 = 18.432 in cost units.
TEST(StartAgreementTest, JudgesStartsAgainstTheJobsCost) {
  const double tol = SameMinimumTolerance(9.6, 1e-3);
  EXPECT_DOUBLE_EQ(tol, 0.5 * 3.84 * 9.6);
  EXPECT_DOUBLE_EQ(SameMinimumTolerance(kNaN, 1e-3), 1e-3);
  EXPECT_DOUBLE_EQ(SameMinimumTolerance(1e-9, 1e-3), 1e-3);
  const double job = 77000.0;
  // Every start within the tolerance either side (failed ones aside): one
  // minimum.
  EXPECT_EQ(JudgeStarts(job, {job + 18.0, job - 18.0, kInf, kNaN}, tol), StartVerdict::kSame);
  // One clearly lower wins over the rest.
  EXPECT_EQ(JudgeStarts(job, {job, job - 19.0, job + 500.0}, tol), StartVerdict::kLower);
  // One clearly higher: several minima (FitTest.AStartFarAboveTheNoise...'s
  // starts 1 and 2: 143224 and 349678 against the job's 143231), no verdict.
  EXPECT_EQ(JudgeStarts(job, {job, job + 19.0}, tol), StartVerdict::kUndecided);
  // Nothing ended: no evidence either way.
  EXPECT_EQ(JudgeStarts(job, {kInf, kNaN}, tol), StartVerdict::kUndecided);
  EXPECT_EQ(JudgeStarts(job, {}, tol), StartVerdict::kUndecided);
}

// Tolerance ½·1·s² (cost units); two small gains in a row make the cost
// rough, a large gain before that resets the count, and after it does not.
TEST(RoughOptimumTest, TwoSmallGainsInARowMakeTheCostRough) {
  EXPECT_DOUBLE_EQ(RoughTolerance(4.0, 1e-6), 2.0);
  EXPECT_DOUBLE_EQ(RoughTolerance(kNaN, 1e-6), 1e-6);
  RoughRounds r;
  r.Restarted(1.0, 0.3, 2.0);
  EXPECT_FALSE(r.rough());
  r.Restarted(5.0, 3.0, 2.0);  // a real gain: the count starts again
  EXPECT_EQ(r.small_rounds(), 0);
  r.Restarted(1.5, 0.01, 2.0);
  EXPECT_FALSE(r.rough());
  r.Restarted(0.5, 0.01, 2.0);
  EXPECT_TRUE(r.rough());
  EXPECT_DOUBLE_EQ(r.small_decrease(), 2.0);
  EXPECT_DOUBLE_EQ(r.last_scale(), 0.01);
  r.Restarted(50.0, 1.0, 2.0);
  EXPECT_TRUE(r.rough());
  EXPECT_NE(RoughCostNote(r, 4.0).find("rough below the standard-error scale"),
            std::string::npos);
  EXPECT_EQ(RoughCostNote(RoughRounds(), 4.0), "");
}

TEST(SmoothScaleTest, EstimateAtIntervalEnd) {
  EXPECT_FALSE(EstimateAtIntervalEnd(0.5, 0.0, 1.0));
  EXPECT_FALSE(EstimateAtIntervalEnd(0.06, 0.0, 1.0));
  EXPECT_TRUE(EstimateAtIntervalEnd(0.05, 0.0, 1.0));
  EXPECT_TRUE(EstimateAtIntervalEnd(0.999, 0.0, 1.0));
  EXPECT_TRUE(EstimateAtIntervalEnd(1.5, 0.0, 1.0));
  EXPECT_FALSE(EstimateAtIntervalEnd(0.5, 1.0, 1.0));
  EXPECT_FALSE(EstimateAtIntervalEnd(0.5, kNaN, 1.0));
}

// r_i(θ) = a_i·θ − y_i + c·saw(θ/δ), saw(x) = x − round(x) ∈ [−½, ½]: a
// line plus a sawtooth of amplitude c and slope c/δ. The analytic Jacobian
// at a point is a_i + c/δ; the cost at the scale of the interval is the
// line's, whose Gauss–Newton variance is s²/Σa_i².
class SawtoothCost : public ceres::CostFunction {
 public:
  SawtoothCost(std::vector<double> a, std::vector<double> y, double c, double delta)
      : a_(std::move(a)), y_(std::move(y)), c_(c), delta_(delta) {
    set_num_residuals(static_cast<int>(a_.size()));
    mutable_parameter_block_sizes()->push_back(1);
  }
  bool Evaluate(double const* const* p, double* r, double** j) const override {
    const double x = p[0][0] / delta_;
    const double saw = x - std::round(x);
    for (size_t i = 0; i < a_.size(); ++i) {
      r[i] = a_[i] * p[0][0] - y_[i] + c_ * saw;
      if (j != nullptr && j[0] != nullptr) j[0][i] = a_[i] + c_ / delta_;
    }
    return true;
  }

 private:
  std::vector<double> a_, y_;
  double c_, delta_;
};

// m = 100 residuals with a_i = 1 and y_i alternating ±1 about 0.3 (the
// line's minimum at 0.3, s² = 1 by construction): the smooth-scale SD is
// 1/√100 = 0.1. Without the sawtooth the central differences are exact:
// the Jacobian is a to round-off, SD 0.1 to 1e-9. With c = 0.05,
// δ = 0.00123 the slope at a point is 1 + 40.7, an SD of 0.0024 (what
// autodiff's JᵀJ gives); a difference over ±h adds at most c/(2h) to the
// slope, so at the fixed point h ≈ 0.1 the SD is within 0.1/(1 ± 0.25·2)
// — asserted within [0.1/1.5, 0.1/0.5] — and at least 20 times autodiff's.
TEST(SmoothScaleTest, CentralDifferencesAtOneStandardErrorSeeTheLinesSlope) {
  const int m = 100;
  std::vector<double> a(m, 1.0), y(m);
  for (int i = 0; i < m; ++i) y[i] = 0.3 + (i % 2 == 0 ? 1.0 : -1.0);
  EvaluationCounter counter;
  for (double c : {0.0, 0.05}) {
    std::vector<double> theta = {0.3};
    ceres::Problem problem;
    problem.AddResidualBlock(new SawtoothCost(a, y, c, 0.00123), nullptr, theta.data());
    const double autodiff_sd = 1.0 / ((1.0 + c / 0.00123) * std::sqrt(m));
    const Eigen::MatrixXd cov0 = Eigen::MatrixXd::Constant(1, 1, autodiff_sd * autodiff_sd);
    const SmoothScale s = SmoothScaleCovariance(&problem, {0.3}, cov0, {-kInf}, {kInf}, 1.0,
                                                &counter, 1, &theta);
    ASSERT_TRUE(s.ok) << c;
    EXPECT_DOUBLE_EQ(theta[0], 0.3);
    const double sd = std::sqrt(s.cov(0, 0));
    if (c == 0.0) {
      EXPECT_NEAR(sd, 0.1, 1e-9);
      EXPECT_NEAR(s.jacobian(0, 0), 1.0, 1e-9);
    } else {
      EXPECT_GT(sd, 0.1 / 1.5);
      EXPECT_LT(sd, 0.1 / 0.5);
      EXPECT_GT(sd, 20.0 * autodiff_sd);
      EXPECT_GT(s.passes, 1);
    }
  }
}

}  // namespace
}  // namespace axis
