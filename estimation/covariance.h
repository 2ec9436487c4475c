// The covariance of a fit's estimate: (JᵀJ)⁻¹ of θ as ceres::Covariance's
// DENSE_SVD computes it, the pseudo-inverse when JᵀJ is rank deficient, and the free
// parameters in the Jacobian's numerical null space (not determined by the
// data). Scaled to physical units and by s² in estimation/internal/fitter.cc.
#ifndef ESTIMATION_COVARIANCE_H_
#define ESTIMATION_COVARIANCE_H_

#include <vector>

#include <Eigen/Core>
#include <ceres/ceres.h>

namespace axis {

// The reciprocal condition number (of JᵀJ) below which the covariance is
// a pseudo-inverse (ceres::Covariance::Options::min_reciprocal_condition_number).
constexpr double kMinReciprocalCondition = 1e-14;

// Covariance (JᵀJ)⁻¹ of the single parameter block θ (size n) of
// `problem` at its current value, as ceres::Covariance's DENSE_SVD computes
// it (V·S⁻²·Vᵀ from the SVD of the dense Jacobian), from one evaluation of
// the Jacobian; the pseudo-inverse over the singular values above
// √kMinReciprocalCondition of the largest if JᵀJ is rank deficient; NaN
// where the Jacobian cannot be evaluated or is not finite. *jtj_out (if not
// null) receives JᵀJ (n×n; empty if the Jacobian could not be evaluated),
// for NullSpaceMembersOf. The Jacobian's residual blocks are evaluated on
// up to `threads` threads (EvaluateDenseJacobian). Never throws but
// std::bad_alloc.
Eigen::MatrixXd CovarianceOfTheta(ceres::Problem* problem, int n, int threads,
                                  Eigen::MatrixXd* jtj_out);

// (JᵀJ)⁻¹ from the m × n Jacobian `j` (any m ≥ 1, n ≥ 1) as ceres::Covariance's
// DENSE_SVD forms it: V·S⁻²·Vᵀ over the singular values above
// √kMinReciprocalCondition of the largest (the pseudo-inverse where JᵀJ is
// rank deficient), n × n; NaN if `j` has no positive singular value or a
// non-finite entry. The
// SVD is taken of R in J = Q·R (Householder QR, R n × n) where m ≥ n, which
// has J's singular values and right singular vectors (Q's columns are
// orthonormal; Golub & Van Loan, "Matrix Computations", 4th ed., §8.6.3,
// R-SVD), by Eigen's two-sided Jacobi SVD. Never throws but std::bad_alloc.
Eigen::MatrixXd CovarianceOfJacobian(const Eigen::MatrixXd& j);

// Free parameters (the first n_free of θ) that lie in the numerical null
// space of the weighted Jacobian whose JᵀJ over them is `jtj` (n_free ×
// n_free): the columns are scaled to unit norm (so units do not matter),
// and a parameter is in the null space if it has a component above 0.1 in
// an eigenvector of JᵀJ whose eigenvalue is below 1e-10 of the largest (or
// if its column is zero).
std::vector<bool> NullSpaceMembersOf(const Eigen::MatrixXd& jtj, int n_free);

// NullSpaceMembersOf the Jacobian of `problem` at the current θ (evaluated
// on up to `threads` threads); every parameter if it cannot be evaluated
// there.
std::vector<bool> NullSpaceMembers(ceres::Problem* problem, int n_free, int threads);

}  // namespace axis

#endif  // ESTIMATION_COVARIANCE_H_
