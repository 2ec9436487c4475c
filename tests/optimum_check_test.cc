// estimation/optimum_check.h ProbeRound: the probes and their quadratic
// reach, against costs whose shape is known in closed form.
#include "estimation/optimum_check.h"

#include <cmath>
#include <vector>

#include <ceres/ceres.h>
#include <gtest/gtest.h>

namespace axis {
namespace {

// r = (θ_0, 2·θ_1) plus, past θ_0 = kink, a residual 3·(θ_0 − kink): the
// cost ½Σr² is the quadratic ½(θ_0² + 4θ_1²) inside the kink, whose
// Gauss–Newton standard deviations are 1 (θ_0) and 0.5 (θ_1). A kink at
// +∞ leaves the quadratic alone.
struct KinkedResiduals {
  template <typename T>
  bool operator()(const T* theta, T* r) const {
    r[0] = theta[0];
    r[1] = T(2.0) * theta[1];
    r[2] = theta[0] > T(kink) ? T(3.0) * (theta[0] - T(kink)) : T(0.0);
    return true;
  }
  double kink;
};

struct Probed {
  explicit Probed(double kink, double upper = 1e3) : theta{0.0, 0.0} {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<KinkedResiduals, 3, 2>(new KinkedResiduals{kink}),
        nullptr, theta.data());
    lower = {-1e3, -1e3};
    this->upper = {1e3, upper};
    // The last step: along θ_0 (any direction with curvature will do).
    result = ProbeRound(&problem, lower, this->upper, {1.0, 0.0}, 0.0, &counter, 1, &theta);
  }
  ceres::Problem problem;
  std::vector<double> theta, lower, upper;
  EvaluationCounter counter;
  ProbeRoundResult result;
};

// Exactly quadratic: every principal-axis probe rises by ½s², out to the
// furthest probe (10 standard deviations); nothing lower than the minimum.
TEST(OptimumCheckTest, AQuadraticReachesTheFurthestProbe) {
  Probed p(1e300);
  EXPECT_DOUBLE_EQ(p.result.quadratic_reach, 10.0);
  EXPECT_EQ(p.result.best, (std::vector<double>{0.0, 0.0}));
  EXPECT_EQ(p.result.best_cost, 0.0);
  EXPECT_EQ(p.result.lowest_scale, 0.0);
  // 2 coordinates, 2 principal axes and the last step, 5 scales, 2 signs.
  EXPECT_EQ(p.result.probes, 50);
  EXPECT_EQ(p.theta, (std::vector<double>{0.0, 0.0})) << "θ left at θ*";
}

// A kink 2 standard deviations out on θ_0: the probe at 3 rises by
// ½·9 + ½·9·1 = 9 instead of 4.5, so the reach ends at 1; a kink at 5
// leaves 1 and 3 quadratic (reach 3: the probe at 10 rises 162.5 against
// the quadratic's 50); a kink at 0.5 already spoils the probe at 1.
TEST(OptimumCheckTest, AKinkEndsTheReachBeforeIt) {
  EXPECT_DOUBLE_EQ(Probed(2.0).result.quadratic_reach, 1.0);
  EXPECT_DOUBLE_EQ(Probed(5.0).result.quadratic_reach, 3.0);
  EXPECT_DOUBLE_EQ(Probed(0.5).result.quadratic_reach, 0.0);
}

// A bound 4 standard deviations out on θ_1 (0.5 each: θ_1 ≤ 2) clips the
// probe at 10 there: a clipped probe does not count as agreeing.
TEST(OptimumCheckTest, AClippedProbeEndsTheReach) {
  EXPECT_DOUBLE_EQ(Probed(1e300, 2.0).result.quadratic_reach, 3.0);
}

// The tolerance (kQuadraticAgreement, 10 %): a residual √e·θ_0 on the
// positive side of θ_0 only (no slope at θ* = 0, so JᵀJ does not see it)
// makes every probe at +θ_0 rise (1 + e) times ½s²: e = 0.08 still
// agrees, e = 0.12 does not, from the first scale on.
struct ScaledSide {
  template <typename T>
  bool operator()(const T* theta, T* r) const {
    r[0] = theta[0];
    r[1] = T(2.0) * theta[1];  // distinct eigenvalues: the principal axes are θ_0, θ_1
    r[2] = theta[0] > T(0.0) ? T(slope) * theta[0] : T(0.0);
    return true;
  }
  double slope;
};

double ReachWithSide(double extra) {
  std::vector<double> theta{0.0, 0.0};
  ceres::Problem problem;
  problem.AddResidualBlock(
      new ceres::AutoDiffCostFunction<ScaledSide, 3, 2>(new ScaledSide{std::sqrt(extra)}),
      nullptr, theta.data());
  EvaluationCounter counter;
  return ProbeRound(&problem, {-1e3, -1e3}, {1e3, 1e3}, {1.0, 0.0}, 0.0, &counter, 1, &theta)
      .quadratic_reach;
}

TEST(OptimumCheckTest, AgreementWithinTenPercent) {
  EXPECT_DOUBLE_EQ(ReachWithSide(0.08), 10.0);
  EXPECT_DOUBLE_EQ(ReachWithSide(0.12), 0.0);
}

}  // namespace
}  // namespace axis
