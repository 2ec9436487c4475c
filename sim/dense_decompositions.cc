#include "sim/dense_decompositions.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>

namespace axis {

SymmetricEigen SymmetricEigenOf(const Eigen::MatrixXd& a) {
  SymmetricEigen out;
  if (a.size() == 0) {  // Eigen's solver reads the largest entry of the matrix
    out.ok = true;
    return out;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(a);
  out.ok = eig.info() == Eigen::Success;
  out.values = eig.eigenvalues();
  out.vectors = eig.eigenvectors();
  return out;
}

Eigen::MatrixXd PseudoInverseOf(const SymmetricEigen& eig, double relative) {
  const double largest = eig.values.size() > 0 ? eig.values.maxCoeff() : 0.0;
  return eig.vectors *
         eig.values.unaryExpr([&](double v) { return v > relative * largest ? 1.0 / v : 0.0; })
             .asDiagonal() *
         eig.vectors.transpose();
}

Svd SvdOf(const Eigen::MatrixXd& a, bool full_u, bool full_v) {
  const unsigned options = (full_u ? Eigen::ComputeFullU : 0) | (full_v ? Eigen::ComputeFullV : 0);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, options);
  Svd out;
  out.singular_values = svd.singularValues();
  if (full_u) out.u = svd.matrixU();
  if (full_v) out.v = svd.matrixV();
  return out;
}

namespace {

Eigen::JacobiSVD<Eigen::MatrixXd> ThresholdedSvd(const Eigen::MatrixXd& a, double threshold) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
  svd.setThreshold(threshold);
  return svd;
}

}  // namespace

Eigen::VectorXd SvdSolve(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, double threshold) {
  return ThresholdedSvd(a, threshold).solve(b);
}

Eigen::MatrixXd SvdPseudoInverse(const Eigen::MatrixXd& a, double threshold) {
  return ThresholdedSvd(a, threshold).solve(Eigen::MatrixXd::Identity(a.rows(), a.cols()));
}

Eigen::MatrixXd ColumnSpaceBasis(const Eigen::MatrixXd& a, double threshold) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  qr.setThreshold(threshold);
  const Eigen::Index rank = qr.rank();
  // No columns: Eigen's product with an empty block offsets a null pointer
  // (UBSan's pointer-overflow check).
  if (rank == 0) return Eigen::MatrixXd(a.rows(), 0);
  return qr.householderQ() * Eigen::MatrixXd::Identity(a.rows(), rank);
}

Eigen::VectorXd QrLeastSquares(const Eigen::MatrixXd& a, const Eigen::VectorXd& b) {
  return a.colPivHouseholderQr().solve(b);
}

Eigen::VectorXd CodSolve(const Eigen::MatrixXd& a, const Eigen::VectorXd& b) {
  return a.completeOrthogonalDecomposition().solve(b);
}

Eigen::MatrixXd CodPseudoInverse(const Eigen::MatrixXd& a) {
  return Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(a).pseudoInverse();
}

StateEigenvalueVector StateEigenvalues(
    const Eigen::Matrix<double, kNumStates, kNumStates>& a, bool* ok) {
  const Eigen::EigenSolver<Eigen::Matrix<double, kNumStates, kNumStates>> solver(a, false);
  if (ok != nullptr) *ok = solver.info() == Eigen::Success;
  return solver.eigenvalues();
}

}  // namespace axis
