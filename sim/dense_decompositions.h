// Eigen's dense decompositions behind plain functions, compiled once here
// instead of in every translation unit that uses them. Each of Eigen's
// decomposition templates is instantiated (and optimised) wherever it is
// used: Eigen::SelfAdjointEigenSolver<MatrixXd> alone cost 11 of the 15 s
// g++ -O3 spent on estimation/internal/smooth_scale.cc, and the same
// instantiations recurred in a dozen files of sim/, estimation/, discovery/,
// design/, tune/ and run/ (and again in the sanitizer build). The functions
// run the Eigen algorithm named beside each, with the options given, and
// return what the callers read from it; the arithmetic is Eigen's own, so a
// result is the one the decomposition gives where it is written inline.
// Source: the Eigen 3.4 documentation of each class
// (https://eigen.tuxfamily.org/dox/group__TopicLinearAlgebraDecompositions.html).
#ifndef SIM_DENSE_DECOMPOSITIONS_H_
#define SIM_DENSE_DECOMPOSITIONS_H_

#include <complex>

#include <Eigen/Core>

#include "sim/axis_model.h"

namespace axis {

// The eigen-decomposition A = V·diag(values)·Vᵀ of a symmetric matrix
// (Eigen::SelfAdjointEigenSolver<MatrixXd>, eigenvalues and eigenvectors;
// only A's lower triangle is read).
struct SymmetricEigen {
  Eigen::VectorXd values;   // n, ascending
  Eigen::MatrixXd vectors;  // n × n, column k the unit eigenvector of values[k]
  bool ok = false;          // Eigen::Success; values and vectors unspecified if not
};

// The decomposition of the square matrix `a` (n × n; n = 0 gives empty
// values and vectors, ok). Never throws but std::bad_alloc.
SymmetricEigen SymmetricEigenOf(const Eigen::MatrixXd& a);

// The pseudo-inverse V·diag(g(λ))·Vᵀ from a decomposition, g(λ) = 1/λ for
// λ > relative·(the largest eigenvalue), 0 otherwise (a positive
// semi-definite matrix's inverse on the span it resolves). n × n.
Eigen::MatrixXd PseudoInverseOf(const SymmetricEigen& eig, double relative);

// The singular value decomposition A = U·diag(s)·Vᵀ of an m × n matrix by
// Eigen::JacobiSVD<MatrixXd> (column-pivoting QR preconditioner, the
// default); U and V full (m × m, n × n) where asked, else empty (0 × 0).
struct Svd {
  Eigen::VectorXd singular_values;  // min(m, n), descending, ≥ 0
  Eigen::MatrixXd u;
  Eigen::MatrixXd v;
};
Svd SvdOf(const Eigen::MatrixXd& a, bool full_u, bool full_v);

// The least-squares solution x of A·x = b of least norm by the JacobiSVD of
// `a` (full U and V) with singular values at most threshold·(the largest)
// treated as zero (JacobiSVD::setThreshold, solve). b has m rows; x has n.
Eigen::VectorXd SvdSolve(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, double threshold);

// The pseudo-inverse of the square matrix `a` (n × n) the same way: the
// thresholded JacobiSVD's solve of A·X = I.
Eigen::MatrixXd SvdPseudoInverse(const Eigen::MatrixXd& a, double threshold);

// An orthonormal basis of A's column space, m × rank: the first rank
// columns of Q of the column-pivoting Householder QR of `a`
// (Eigen::ColPivHouseholderQR<MatrixXd>, setThreshold(threshold), rank);
// m × 0 where A is zero.
Eigen::MatrixXd ColumnSpaceBasis(const Eigen::MatrixXd& a, double threshold);

// The least-squares solution of A·x = b by the column-pivoting Householder
// QR of `a` (ColPivHouseholderQR::solve, Eigen's default threshold).
Eigen::VectorXd QrLeastSquares(const Eigen::MatrixXd& a, const Eigen::VectorXd& b);

// The minimum-norm least-squares solution of A·x = b and the pseudo-inverse
// of A (n × m), by the complete orthogonal decomposition
// (Eigen::CompleteOrthogonalDecomposition<MatrixXd>, solve, pseudoInverse;
// Eigen's default threshold).
Eigen::VectorXd CodSolve(const Eigen::MatrixXd& a, const Eigen::VectorXd& b);
Eigen::MatrixXd CodPseudoInverse(const Eigen::MatrixXd& a);

// The eigenvalues of a state matrix, one per state, in no particular order.
using StateEigenvalueVector = Eigen::Matrix<std::complex<double>, kNumStates, 1>;

// The eigenvalues of a state matrix (the model's kNumStates × kNumStates
// ∂f/∂y, MODEL.md §9), by Eigen::EigenSolver without eigenvectors. *ok (if
// not null) is false, the values then unspecified, where its QR iteration
// did not converge.
StateEigenvalueVector StateEigenvalues(
    const Eigen::Matrix<double, kNumStates, kNumStates>& a, bool* ok = nullptr);

}  // namespace axis

#endif  // SIM_DENSE_DECOMPOSITIONS_H_
