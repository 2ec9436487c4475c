// NeweyWestCovariance (estimation/internal/sandwich_covariance.h) against closed
// forms of linear regression: the mean of autocorrelated errors by hand, and
// the group means of heteroscedastic groups (HC0 = Σe²/n_g² per group).
#include <stdexcept>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "estimation/internal/sandwich_covariance.h"

namespace axis {
namespace {

// Regression on a constant (J = 1, n = 1): C = (1/m²)·[Σe² + 2Σ_l w_l Σ_t
// e_t e_{t−l}], w_l = 1 − l/(L + 1). For e = (1, −2, 3, −1, 2), m = 5:
// Σe² = 19, Σ e_t e_{t−1} = −2 − 6 − 3 − 2 = −13, Σ e_t e_{t−2} = 3 + 2 + 6 = 11.
// L = 0: 19/25; L = 1 (w 1/2): (19 − 13)/25; L = 2 (w 2/3, 1/3):
// (19 − 2·13·2/3 + 2·11/3)/25 = 9/25. Series (2, 3), L = 1: the lag-1
// products within each, −2 and −3 − 2: (19 − 7)/25. Exact in binary but
// for the thirds: 1e-14.
TEST(SandwichCovarianceTest, MeanOfAutocorrelatedErrorsMatchesTheHandSum) {
  const Eigen::MatrixXd j = Eigen::MatrixXd::Ones(5, 1);
  Eigen::VectorXd e(5);
  e << 1, -2, 3, -1, 2;
  EXPECT_NEAR(NeweyWestCovariance(j, e, {5}, 0)(0, 0), 19.0 / 25, 1e-14);
  EXPECT_NEAR(NeweyWestCovariance(j, e, {5}, 1)(0, 0), 6.0 / 25, 1e-14);
  EXPECT_NEAR(NeweyWestCovariance(j, e, {5}, 2)(0, 0), 9.0 / 25, 1e-14);
  EXPECT_NEAR(NeweyWestCovariance(j, e, {2, 3}, 1)(0, 0), 12.0 / 25, 1e-14);
  // Lags past a series' length add nothing more than its own products.
  EXPECT_NEAR(NeweyWestCovariance(j, e, {5}, 0)(0, 0),
              NeweyWestCovariance(j, e, {1, 1, 1, 1, 1}, 3)(0, 0), 1e-14);
}

// Two groups' means (J the group indicators, residuals from each group's
// mean): y_A = (1, 2, 6), e_A = (−2, −1, 3); y_B = (4, 8), e_B = (−2, 2).
// HC0 (White): Var A = Σe_A²/3² = 14/9, Var B = Σe_B²/2² = 2, Cov 0,
// where (JᵀJ)⁻¹·s² with the pooled s² = 22/3 gives 22/9 and 22/6.
TEST(SandwichCovarianceTest, HeteroscedasticGroupMeansMatchWhite) {
  Eigen::MatrixXd j(5, 2);
  j << 1, 0, 1, 0, 1, 0, 0, 1, 0, 1;
  Eigen::VectorXd e(5);
  e << -2, -1, 3, -2, 2;
  const Eigen::MatrixXd c = NeweyWestCovariance(j, e, {5}, 0);
  EXPECT_NEAR(c(0, 0), 14.0 / 9, 1e-14);
  EXPECT_NEAR(c(1, 1), 2.0, 1e-14);
  EXPECT_NEAR(c(0, 1), 0.0, 1e-14);
  EXPECT_NEAR(c(1, 0), 0.0, 1e-14);
}

// A general design against the formula written out: (XᵀX)⁻¹ Xᵀ Ω X (XᵀX)⁻¹
// with Ω_tt = e_t², Ω_{t,t±1} = ½e_t e_{t±1} (L = 1), Eigen's inverse.
TEST(SandwichCovarianceTest, GeneralDesignMatchesTheMatrixFormula) {
  Eigen::MatrixXd x(6, 2);
  x << 1, 0.5, 1, -1.0, 1, 2.0, 1, 0.3, 1, -0.7, 1, 1.1;
  Eigen::VectorXd e(6);
  e << 0.4, -0.2, 0.9, -1.3, 0.1, 0.6;
  Eigen::MatrixXd omega = Eigen::MatrixXd::Zero(6, 6);
  for (int t = 0; t < 6; ++t) {
    omega(t, t) = e[t] * e[t];
    if (t > 0) omega(t, t - 1) = omega(t - 1, t) = 0.5 * e[t] * e[t - 1];
  }
  const Eigen::MatrixXd inv = (x.transpose() * x).inverse();
  const Eigen::MatrixXd expected = inv * x.transpose() * omega * x * inv;
  const Eigen::MatrixXd c = NeweyWestCovariance(x, e, {6}, 1);
  EXPECT_LT((c - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());
}

TEST(SandwichCovarianceTest, RejectsMismatchedShapes) {
  const Eigen::MatrixXd j = Eigen::MatrixXd::Ones(3, 1);
  EXPECT_THROW(NeweyWestCovariance(j, Eigen::VectorXd::Ones(2), {3}, 0),
               std::invalid_argument);
  EXPECT_THROW(NeweyWestCovariance(j, Eigen::VectorXd::Ones(3), {2}, 0),
               std::invalid_argument);
  EXPECT_THROW(NeweyWestCovariance(j, Eigen::VectorXd::Ones(3), {3}, -1),
               std::invalid_argument);
}

}  // namespace
}  // namespace axis
