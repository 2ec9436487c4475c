// The force map's roughness penalty (discovery/force_map.h) in the
// linearised fit: the penalty matrix in θ's space and the penalised
// Gauss–Newton figures (edf, data χ², BIC, s², (JᵀJ + P)⁻¹) the step
// chooses λ and compares models by.
#ifndef DISCOVERY_INTERNAL_FORCE_MAP_PENALTY_H_
#define DISCOVERY_INTERNAL_FORCE_MAP_PENALTY_H_

#include <Eigen/Core>

#include "estimation/estimation_problem.h"

namespace axis {

// The penalty's matrix λ·DᵀD + α·CᵀC of `job` (its map, λ, anchor α and
// confounded components C) embedded in the n × n space of θ: the map's
// values are the last K entries of θ (MapJob), θ = value.
// Never throws.
Eigen::MatrixXd PenaltyMatrix(const EstimationProblem& job, int n);

// The penalised Gauss–Newton figures at the residuals r and Jacobian J at
// θ with penalty matrix P: (JᵀJ + P)⁻¹, edf = tr((JᵀJ + P)⁻¹JᵀJ) and the
// data χ², at θ or (`step`) predicted at the penalised optimum one
// Gauss–Newton step away.
struct Penalised {
  double chi2 = 0.0;
  double edf = 0.0;
  Eigen::MatrixXd inverse;
};

// Never throws.
Penalised AtPenalty(const Eigen::VectorXd& r, const Eigen::MatrixXd& j, const Eigen::MatrixXd& p,
                    const Eigen::VectorXd& theta, bool step);

// θ of `job`'s free parameters at their initial values.
// Never throws.
Eigen::VectorXd ThetaOf(const EstimationProblem& job);

// A map job's figures at its free parameters' initial values (its fitted
// point after ApplyEstimates): the data χ² = Σr², edf, BIC = χ² + edf·ln(m),
// s² = χ²/(m − edf) and (JᵀJ + P)⁻¹.
struct Assessment {
  double chi2 = 0.0, edf = 0.0, bic = 0.0, s2 = 0.0;
  Eigen::MatrixXd inverse;
};

// Throws std::runtime_error if a simulation at the job's point fails
// (StackedJacobian).
Assessment Assess(const EstimationProblem& job);

}  // namespace axis

#endif  // DISCOVERY_INTERNAL_FORCE_MAP_PENALTY_H_
