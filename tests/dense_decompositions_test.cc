// sim/dense_decompositions.h against closed forms (no Eigen decomposition
// is instantiated here: that is what the header saves). Tolerances: 1e-12
// relative, a few hundred ulps of round-off on matrices of norm ≤ 10.
#include "sim/dense_decompositions.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include <gtest/gtest.h>

namespace axis {
namespace {

constexpr double kTol = 1e-12;

// A rotation by `angle` about the z axis (an orthogonal Q for test matrices).
Eigen::Matrix3d RotationZ(double angle) {
  Eigen::Matrix3d q;
  q << std::cos(angle), -std::sin(angle), 0.0, std::sin(angle), std::cos(angle), 0.0, 0.0, 0.0,
      1.0;
  return q;
}

TEST(DenseDecompositionsTest, SymmetricEigenIsAscendingOrthonormalAndReconstructs) {
  const Eigen::Matrix3d q = RotationZ(0.7);
  const Eigen::MatrixXd a = q * Eigen::Vector3d(3.0, 1.0, 2.0).asDiagonal() * q.transpose();
  const SymmetricEigen eig = SymmetricEigenOf(a);
  ASSERT_TRUE(eig.ok);
  ASSERT_EQ(eig.values.size(), 3);
  EXPECT_NEAR(eig.values[0], 1.0, kTol);
  EXPECT_NEAR(eig.values[1], 2.0, kTol);
  EXPECT_NEAR(eig.values[2], 3.0, kTol);
  EXPECT_LE((eig.vectors.transpose() * eig.vectors - Eigen::MatrixXd::Identity(3, 3))
                .cwiseAbs()
                .maxCoeff(),
            kTol);
  EXPECT_LE((eig.vectors * eig.values.asDiagonal() * eig.vectors.transpose() - a)
                .cwiseAbs()
                .maxCoeff(),
            10 * kTol);
}

TEST(DenseDecompositionsTest, PseudoInverseOfARankOneMatrixIsItsClosedForm) {
  // (u·uᵀ)⁺ = u·uᵀ / (uᵀu)²; the two zero eigenvalues are below 1e-14 of
  // the largest and are dropped.
  const Eigen::Vector3d u(1.0, 2.0, 2.0);
  const Eigen::MatrixXd a = u * u.transpose();
  const Eigen::MatrixXd expected = a / (u.squaredNorm() * u.squaredNorm());
  const Eigen::MatrixXd pinv = PseudoInverseOf(SymmetricEigenOf(a), 1e-14);
  EXPECT_LE((pinv - expected).cwiseAbs().maxCoeff(), kTol);
}

TEST(DenseDecompositionsTest, AnEmptyMatrixHasAnEmptyDecomposition) {
  const SymmetricEigen eig = SymmetricEigenOf(Eigen::MatrixXd(0, 0));
  EXPECT_TRUE(eig.ok);
  EXPECT_EQ(eig.values.size(), 0);
  const Eigen::MatrixXd pinv = PseudoInverseOf(eig, 1e-14);
  EXPECT_EQ(pinv.rows(), 0);
  EXPECT_EQ(pinv.cols(), 0);
}

TEST(DenseDecompositionsTest, SvdOfARotatedDiagonalMatrix) {
  // A = Q·[3 0; 0 -2; 0 0]: singular values 3 and 2; U, V only where asked.
  Eigen::MatrixXd d(3, 2);
  d << 3.0, 0.0, 0.0, -2.0, 0.0, 0.0;
  const Eigen::MatrixXd a = RotationZ(0.3) * d;
  const Svd full = SvdOf(a, true, true);
  ASSERT_EQ(full.singular_values.size(), 2);
  EXPECT_NEAR(full.singular_values[0], 3.0, kTol);
  EXPECT_NEAR(full.singular_values[1], 2.0, kTol);
  ASSERT_EQ(full.u.rows(), 3);
  ASSERT_EQ(full.u.cols(), 3);
  ASSERT_EQ(full.v.rows(), 2);
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(3, 2);
  s.diagonal() = full.singular_values;
  EXPECT_LE((full.u * s * full.v.transpose() - a).cwiseAbs().maxCoeff(), 10 * kTol);
  const Svd values_only = SvdOf(a, false, false);
  EXPECT_EQ(values_only.u.size(), 0);
  EXPECT_EQ(values_only.v.size(), 0);
  EXPECT_NEAR(values_only.singular_values[0], 3.0, kTol);
}

TEST(DenseDecompositionsTest, SvdSolveAndPseudoInverseAgreeWithClosedForms) {
  // A consistent overdetermined system: x = (2, -1) exactly.
  Eigen::MatrixXd a(3, 2);
  a << 1.0, 0.0, 0.0, 1.0, 1.0, 1.0;
  const Eigen::VectorXd x = SvdSolve(a, a * Eigen::Vector2d(2.0, -1.0), 1e-12);
  EXPECT_NEAR(x[0], 2.0, kTol);
  EXPECT_NEAR(x[1], -1.0, kTol);
  // [2 1; 1 1]⁻¹ = [1 -1; -1 2].
  Eigen::MatrixXd m(2, 2);
  m << 2.0, 1.0, 1.0, 1.0;
  Eigen::MatrixXd inverse(2, 2);
  inverse << 1.0, -1.0, -1.0, 2.0;
  EXPECT_LE((SvdPseudoInverse(m, 1e-14) - inverse).cwiseAbs().maxCoeff(), 10 * kTol);
  // Singular: [1 1; 1 1]⁺ = [1 1; 1 1]/4.
  const Eigen::MatrixXd ones = Eigen::MatrixXd::Ones(2, 2);
  EXPECT_LE((SvdPseudoInverse(ones, 1e-12) - ones / 4.0).cwiseAbs().maxCoeff(), kTol);
}

TEST(DenseDecompositionsTest, ColumnSpaceBasisSpansTheColumnsWithTheirRank) {
  // Third column = first + second: rank 2.
  Eigen::MatrixXd a(4, 3);
  a << 1.0, 0.0, 1.0, 0.0, 1.0, 1.0, 2.0, 1.0, 3.0, 1.0, -1.0, 0.0;
  const Eigen::MatrixXd q = ColumnSpaceBasis(a, 1e-10);
  ASSERT_EQ(q.rows(), 4);
  ASSERT_EQ(q.cols(), 2);
  EXPECT_LE((q.transpose() * q - Eigen::MatrixXd::Identity(2, 2)).cwiseAbs().maxCoeff(), kTol);
  EXPECT_LE((q * (q.transpose() * a) - a).cwiseAbs().maxCoeff(), 10 * kTol);
  EXPECT_EQ(ColumnSpaceBasis(Eigen::MatrixXd::Zero(3, 2), 1e-10).cols(), 0);
}

TEST(DenseDecompositionsTest, QrAndCodLeastSquares) {
  // y = 1 + 2t through four points exactly.
  Eigen::MatrixXd basis(4, 2);
  Eigen::VectorXd y(4);
  for (int k = 0; k < 4; ++k) {
    basis(k, 0) = 1.0;
    basis(k, 1) = k;
    y[k] = 1.0 + 2.0 * k;
  }
  const Eigen::VectorXd c = QrLeastSquares(basis, y);
  EXPECT_NEAR(c[0], 1.0, kTol);
  EXPECT_NEAR(c[1], 2.0, kTol);
  // x1 + x2 = 2: the least-norm solution (1, 1); [1 1]⁺ = [1/2; 1/2].
  const Eigen::MatrixXd row = Eigen::MatrixXd::Ones(1, 2);
  const Eigen::VectorXd x = CodSolve(row, Eigen::VectorXd::Constant(1, 2.0));
  EXPECT_NEAR(x[0], 1.0, kTol);
  EXPECT_NEAR(x[1], 1.0, kTol);
  const Eigen::MatrixXd pinv = CodPseudoInverse(row);
  ASSERT_EQ(pinv.rows(), 2);
  ASSERT_EQ(pinv.cols(), 1);
  EXPECT_NEAR(pinv(0, 0), 0.5, kTol);
  EXPECT_NEAR(pinv(1, 0), 0.5, kTol);
}

TEST(DenseDecompositionsTest, StateEigenvaluesOfABlockDiagonalMatrix) {
  // A damped pair -1 ± 2i and the real modes -3 … -7.
  Eigen::Matrix<double, kNumStates, kNumStates> a =
      Eigen::Matrix<double, kNumStates, kNumStates>::Zero();
  a(0, 0) = -1.0;
  a(0, 1) = 2.0;
  a(1, 0) = -2.0;
  a(1, 1) = -1.0;
  for (int k = 2; k < kNumStates; ++k) a(k, k) = -(k + 1.0);
  bool ok = false;
  const StateEigenvalueVector values = StateEigenvalues(a, &ok);
  ASSERT_TRUE(ok);
  std::vector<std::complex<double>> expected = {{-1.0, 2.0}, {-1.0, -2.0}};
  for (int k = 2; k < kNumStates; ++k) expected.push_back({-(k + 1.0), 0.0});
  for (const std::complex<double>& e : expected) {
    double nearest = std::abs(values[0] - e);
    for (int k = 1; k < kNumStates; ++k) nearest = std::min(nearest, std::abs(values[k] - e));
    EXPECT_LE(nearest, 10 * kTol) << e;
  }
  EXPECT_EQ(StateEigenvalues(a)[0], values[0]);  // ok is optional
}

}  // namespace
}  // namespace axis
