// A Ceres cost that remembers its last evaluation with a Jacobian: the
// solver evaluates the Jacobian at every point it accepts, and the
// covariance (estimation/covariance.h) then evaluates it again at the
// estimate, the solver's last point; each fit paid one Jacobian twice
// (on a full-loop refit at 5 µs, 1.2 s of its 5.7 s). Internal to
// estimation/ (ExperimentCost::Create wraps every experiment's cost).
#ifndef ESTIMATION_INTERNAL_LAST_JACOBIAN_MEMO_H_
#define ESTIMATION_INTERNAL_LAST_JACOBIAN_MEMO_H_

#include <memory>
#include <mutex>
#include <vector>

#include <ceres/cost_function.h>

namespace axis {

// Wraps `inner` (one parameter block; owned): an evaluation with a
// Jacobian at the same point as the last successful one (θ equal bit for
// bit, and the per-sample σ of `sample_sigma`, if not null, equal value
// for value: the fit may change them between solves) copies that one's
// residuals and Jacobian instead of evaluating `inner` again, so the
// result is the same to the last bit (the simulation is deterministic).
// Residual-only evaluations always evaluate `inner` (its sensitivity guard,
// estimation/experiment_cost.h, differs from the Jacobian's check) and
// leave the memory as it is; a failed evaluation is not remembered. Safe
// to call from several threads (a mutex guards the memory). Memory: one
// residual vector and one Jacobian (num_residuals × θ size doubles).
class LastJacobianMemo final : public ceres::CostFunction {
 public:
  // Per-sample σ per fitted channel (estimation/experiment_cost.h
  // SampleSigmas).
  using SampleSigmas = std::vector<std::vector<double>>;

  // Throws std::invalid_argument unless `inner` has one parameter block.
  LastJacobianMemo(ceres::CostFunction* inner, const SampleSigmas* sample_sigma);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  bool Remembers(const double* theta) const;  // caller holds mutex_

  std::unique_ptr<ceres::CostFunction> inner_;
  const SampleSigmas* sample_sigma_;
  int n_ = 0;  // θ size
  mutable std::mutex mutex_;
  mutable bool valid_ = false;
  mutable std::vector<double> theta_;
  mutable std::vector<double> residuals_;
  mutable std::vector<double> jacobian_;  // row-major, num_residuals × n_
  mutable SampleSigmas sigma_;
};

}  // namespace axis

#endif  // ESTIMATION_INTERNAL_LAST_JACOBIAN_MEMO_H_
