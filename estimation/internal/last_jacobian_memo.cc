#include "estimation/internal/last_jacobian_memo.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace axis {

LastJacobianMemo::LastJacobianMemo(ceres::CostFunction* inner, const SampleSigmas* sample_sigma)
    : inner_(inner), sample_sigma_(sample_sigma) {
  if (inner_ == nullptr || inner_->parameter_block_sizes().size() != 1) {
    throw std::invalid_argument("LastJacobianMemo: expected a cost with one parameter block");
  }
  *mutable_parameter_block_sizes() = inner_->parameter_block_sizes();
  set_num_residuals(inner_->num_residuals());
  n_ = inner_->parameter_block_sizes()[0];
}

bool LastJacobianMemo::Remembers(const double* theta) const {
  if (!valid_ || std::memcmp(theta, theta_.data(), sizeof(double) * n_) != 0) return false;
  return sample_sigma_ == nullptr || *sample_sigma_ == sigma_;
}

bool LastJacobianMemo::Evaluate(double const* const* parameters, double* residuals,
                                double** jacobians) const {
  if (jacobians == nullptr || jacobians[0] == nullptr) {
    return inner_->Evaluate(parameters, residuals, jacobians);
  }
  const size_t m = static_cast<size_t>(num_residuals());
  {
    const std::lock_guard<std::mutex> hold(mutex_);
    if (Remembers(parameters[0])) {
      std::copy(residuals_.begin(), residuals_.end(), residuals);
      std::copy(jacobian_.begin(), jacobian_.end(), jacobians[0]);
      return true;
    }
  }
  if (!inner_->Evaluate(parameters, residuals, jacobians)) return false;
  const std::lock_guard<std::mutex> hold(mutex_);
  theta_.assign(parameters[0], parameters[0] + n_);
  residuals_.assign(residuals, residuals + m);
  jacobian_.assign(jacobians[0], jacobians[0] + m * n_);
  if (sample_sigma_ != nullptr) sigma_ = *sample_sigma_;
  valid_ = true;
  return true;
}

}  // namespace axis
