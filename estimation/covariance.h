// The covariance of a fit's estimate: (JᵀJ)⁻¹ of θ by ceres::Covariance
// (DENSE_SVD), the pseudo-inverse when JᵀJ is rank deficient, and the free
// parameters in the Jacobian's numerical null space (not determined by the
// data). Scaled to physical units and by s² in estimation/internal/fitter.cc.
#ifndef ESTIMATION_COVARIANCE_H_
#define ESTIMATION_COVARIANCE_H_

#include <vector>

#include <Eigen/Core>
#include <ceres/ceres.h>

namespace axis {

// Covariance (JᵀJ)⁻¹ of the single parameter block `theta` (size n) of
// `problem` by ceres::Covariance (DENSE_SVD); the pseudo-inverse with the
// null space dropped if JᵀJ is rank deficient; NaN where neither works or
// JᵀJ is not finite. *jtj_out (if not null) receives JᵀJ (n×n; empty if
// the Jacobian could not be evaluated), for NullSpaceMembersOf.
Eigen::MatrixXd CovarianceOfTheta(ceres::Problem* problem, double* theta, int n,
                                  int threads, Eigen::MatrixXd* jtj_out);

// Free parameters (the first n_free of θ) that lie in the numerical null
// space of the weighted Jacobian whose JᵀJ over them is `jtj` (n_free ×
// n_free): the columns are scaled to unit norm (so units do not matter),
// and a parameter is in the null space if it has a component above 0.1 in
// an eigenvector of JᵀJ whose eigenvalue is below 1e-10 of the largest (or
// if its column is zero).
std::vector<bool> NullSpaceMembersOf(const Eigen::MatrixXd& jtj, int n_free);

// NullSpaceMembersOf the Jacobian of `problem` at the current θ; every
// parameter if it cannot be evaluated there.
std::vector<bool> NullSpaceMembers(ceres::Problem* problem, int n_free);

}  // namespace axis

#endif  // ESTIMATION_COVARIANCE_H_
