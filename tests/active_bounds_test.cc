// estimation/internal/active_bounds.h: Levenberg–Marquardt within a box by
// an active set, against closed forms of bounded linear least squares.
#include "estimation/internal/active_bounds.h"

#include <cmath>
#include <utility>
#include <limits>
#include <vector>

#include <Eigen/Dense>
#include <ceres/ceres.h>
#include <gtest/gtest.h>

namespace axis {
namespace {

// r = A·θ − b, A 3×3 with strongly correlated columns: the unconstrained
// minimum A⁻¹b lies outside the box on θ_0, so the projected
// Levenberg–Marquardt steps lose most of their predicted decrease.
struct LinearResiduals {
  template <typename T>
  bool operator()(const T* theta, T* r) const {
    for (int i = 0; i < 3; ++i) {
      r[i] = T(-b[i]);
      for (int j = 0; j < 3; ++j) r[i] += T(a(i, j)) * theta[j];
    }
    return true;
  }
  Eigen::Matrix3d a;
  Eigen::Vector3d b;
};

struct BoxProblem {
  BoxProblem(const Eigen::Matrix3d& a, const Eigen::Vector3d& b, const std::vector<double>& lo,
             const std::vector<double>& hi, const std::vector<double>& start)
      : theta(start), lower(lo), upper(hi) {
    auto* functor = new LinearResiduals{a, b};
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<LinearResiduals, 3, 3>(functor), nullptr, theta.data());
    for (int k = 0; k < 3; ++k) {
      problem.SetParameterLowerBound(theta.data(), k, lower[k]);
      problem.SetParameterUpperBound(theta.data(), k, upper[k]);
    }
  }
  ceres::Problem problem;
  std::vector<double> theta, lower, upper;
};

ceres::Solver::Options LmOptions() {
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_QR;
  o.max_num_line_search_step_size_iterations = 0;  // as the fit's refits near a minimum
  o.initial_trust_region_radius = 1.0;
  o.max_num_iterations = 100;
  // Tight enough that each run ends at its minimum to round-off (the
  // residuals are exact here, no noise to stop at).
  o.function_tolerance = 1e-16;
  o.parameter_tolerance = 1e-16;
  o.gradient_tolerance = 1e-16;
  o.logging_type = ceres::SILENT;
  return o;
}

Eigen::Matrix3d CorrelatedColumns() {
  Eigen::Matrix3d a;
  a << 1.0, 0.95, 0.2,  //
      0.95, 1.0, 0.1,   //
      0.3, 0.2, 1.0;
  return a;
}

// Ceres alone on `plain`, the active set on `active` (the same problem and
// start): their summaries.
std::pair<ceres::Solver::Summary, ceres::Solver::Summary> BothWays(BoxProblem* plain,
                                                                   BoxProblem* active) {
  std::pair<ceres::Solver::Summary, ceres::Solver::Summary> out;
  ceres::Solve(LmOptions(), &plain->problem, &out.first);
  SolveWithinBounds(LmOptions(), &active->problem, active->theta.data(), active->lower,
                    active->upper, nullptr, &out.second);
  return out;
}

// The minimum with θ_0 held at `x0`: least squares of the other two columns
// against b − A_0·x0 (normal equations), the closed form of the bounded
// problem when only θ_0's bound is active.
Eigen::Vector3d MinimumWithFirstAt(const Eigen::Matrix3d& a, const Eigen::Vector3d& b,
                                   double x0) {
  const Eigen::Matrix<double, 3, 2> rest = a.rightCols<2>();
  const Eigen::Vector2d others =
      (rest.transpose() * rest).ldlt().solve(rest.transpose() * (b - a.col(0) * x0));
  return Eigen::Vector3d(x0, others[0], others[1]);
}

TEST(ActiveBoundsTest, ReachesTheBoundedMinimumOfLinearLeastSquares) {
  const Eigen::Matrix3d a = CorrelatedColumns();
  // b from θ = (−1, 2, 0.5): θ_0 = −1 is outside the box θ_0 ≥ 0.
  const Eigen::Vector3d b = a * Eigen::Vector3d(-1.0, 2.0, 0.5);
  const Eigen::Vector3d expected = MinimumWithFirstAt(a, b, 0.0);
  // The bound is active at the closed form: ∂cost/∂θ_0 = (Aᵀr)_0 > 0 there.
  ASSERT_GT((a.transpose() * (a * expected - b))[0], 0.0);
  BoxProblem p(a, b, {0.0, -10.0, -10.0}, {10.0, 10.0, 10.0}, {3.0, 0.0, 0.0});
  ceres::Solver::Summary summary;
  SolveWithinBounds(LmOptions(), &p.problem, p.theta.data(), p.lower, p.upper, nullptr,
                    &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.message;
  EXPECT_EQ(p.theta[0], 0.0);

  // To what a cost compared in doubles resolves: a change below ε·cost
  // is invisible, ½·λ_min·δ² < ε·cost with λ_min the smallest eigenvalue
  // of the free columns' AᵀA (twice that, for the last bits of the sum).
  const double cost = 0.5 * (a * expected - b).squaredNorm();
  const Eigen::Matrix<double, 3, 2> rest = a.rightCols<2>();
  const double lambda_min =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(rest.transpose() * rest).eigenvalues()[0];
  const double tol =
      2.0 * std::sqrt(2.0 * std::numeric_limits<double>::epsilon() * cost / lambda_min);
  for (int k = 1; k < 3; ++k) EXPECT_NEAR(p.theta[k], expected[k], tol) << k;
  EXPECT_NEAR(summary.final_cost, cost, 4.0 * std::numeric_limits<double>::epsilon() * cost);
  // No manifold left on the block: the tangent size is the ambient one.
  EXPECT_EQ(p.problem.ParameterBlockTangentSize(p.theta.data()), 3);
}

// The projected steps' ratio of actual to predicted decrease stays low on
// this problem, so Ceres alone needs many more iterations than the active
// set, which holds θ_0 once the crawl shows.
TEST(ActiveBoundsTest, TakesFewerIterationsThanTheProjectedStepsAlone) {
  const Eigen::Matrix3d a = CorrelatedColumns();
  const Eigen::Vector3d b = a * Eigen::Vector3d(-1.0, 2.0, 0.5);
  const std::vector<double> lo = {0.0, -10.0, -10.0}, hi = {10.0, 10.0, 10.0};
  BoxProblem plain(a, b, lo, hi, {3.0, 0.0, 0.0}), active(a, b, lo, hi, {3.0, 0.0, 0.0});
  const auto [alone, held] = BothWays(&plain, &active);
  EXPECT_LT(held.iterations.size(), alone.iterations.size());
  EXPECT_LE(held.final_cost, alone.final_cost);
}

// A held entry whose gradient turns inward is released: started on the
// bound with b from an interior θ, the end is that interior θ.
TEST(ActiveBoundsTest, AnInteriorMinimumIsReachedFromTheBound) {
  const Eigen::Matrix3d a = CorrelatedColumns();
  const Eigen::Vector3d truth(0.7, 2.0, 0.5);
  const Eigen::Vector3d b = a * truth;
  BoxProblem p(a, b, {0.0, -10.0, -10.0}, {10.0, 10.0, 10.0}, {0.0, -3.0, 3.0});
  ceres::Solver::Summary summary;
  SolveWithinBounds(LmOptions(), &p.problem, p.theta.data(), p.lower, p.upper, nullptr,
                    &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.message;
  // A zero-residual minimum: Levenberg–Marquardt converges quadratically
  // there, far below 1e-8 of these O(1) entries.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(p.theta[k], truth[k], 1e-8) << k;
}

// Off the bounds throughout, the run is Ceres' own to the last bit.
TEST(ActiveBoundsTest, AwayFromTheBoundsItIsOneCeresSolve) {
  const Eigen::Matrix3d a = CorrelatedColumns();
  const Eigen::Vector3d b = a * Eigen::Vector3d(0.7, 2.0, 0.5);
  const std::vector<double> lo = {-10.0, -10.0, -10.0}, hi = {10.0, 10.0, 10.0};
  BoxProblem plain(a, b, lo, hi, {1.0, 1.0, 1.0}), active(a, b, lo, hi, {1.0, 1.0, 1.0});
  const auto [alone, within] = BothWays(&plain, &active);
  EXPECT_EQ(plain.theta, active.theta);
  EXPECT_EQ(alone.iterations.size(), within.iterations.size());
}

TEST(ActiveBoundsTest, PressedBoundsReadTheGradientsSign) {
  const std::vector<double> lo = {0.0, 0.0, 0.0}, hi = {1.0, 1.0, 1.0};
  const double theta[3] = {0.0, 1.0, 0.5};
  EXPECT_EQ(PressedBounds(theta, {1.0, -1.0, 5.0}, lo, hi), (std::vector<int>{0, 1}));
  EXPECT_EQ(PressedBounds(theta, {-1.0, 1.0, 5.0}, lo, hi), std::vector<int>{});
}

}  // namespace
}  // namespace axis
