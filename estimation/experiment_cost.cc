#include "estimation/experiment_cost.h"

#include <algorithm>
#include <stdexcept>

#include "estimation/estimation_problem.h"
#include "estimation/internal/last_jacobian_memo.h"
#include "estimation/jet_widths.h"

namespace axis {
namespace {

// A Ceres dynamic autodiff cost with derivative chunks of `Stride`: one pass
// of the simulator per Jacobian when θ has at most Stride entries; its last
// Jacobian remembered (internal/last_jacobian_memo.h).
template <int Stride>
ceres::CostFunction* MakeDynamic(ExperimentCost* functor, int theta_size,
                                 const SampleSigmas* sample_sigma) {
  auto* cost = new ceres::DynamicAutoDiffCostFunction<ExperimentCost, Stride>(
      functor);
  cost->AddParameterBlock(theta_size);
  cost->SetNumResiduals(functor->num_residuals());
  return new LastJacobianMemo(cost, sample_sigma);
}

// The narrowest stride of jet_widths.h from `Width` up that holds θ whole,
// the widest (several passes per Jacobian) beyond it.
template <int Width>
ceres::CostFunction* MakeNarrowest(ExperimentCost* functor, int theta_size,
                                   const SampleSigmas* sample_sigma) {
  if constexpr (Width < kMaxJetWidth) {
    if (theta_size > Width) {
      return MakeNarrowest<Width + kJetLane>(functor, theta_size, sample_sigma);
    }
  }
  return MakeDynamic<Width>(functor, theta_size, sample_sigma);
}

}  // namespace

ParameterMap::ParameterMap(const AxisParams<double>& base,
                           std::vector<FreeParameter> free,
                           const std::vector<ParameterTie>& ties)
    : base_(base), free_(std::move(free)), ties_(TieIndices(ties)) {
  ApplyTies(ties_, &base_);
  std::vector<std::string> names;
  VisitParams([&](const char* name, const char*, const double&) {
    names.push_back(name);
  }, base_);
  for (size_t j = 0; j < free_.size(); ++j) {
    const auto it = std::find(names.begin(), names.end(), free_[j].name);
    if (it == names.end()) {
      throw std::invalid_argument("expected a model parameter name, got '" +
                                  free_[j].name + "'");
    }
    order_.emplace_back(static_cast<int>(it - names.begin()), static_cast<int>(j));
    if (!TiedTo(ties, free_[j].name).empty()) {
      throw std::invalid_argument("expected a free parameter that is not tied, got '" +
                                  free_[j].name + "' tied to '" +
                                  TiedTo(ties, free_[j].name) + "'");
    }
  }
  std::sort(order_.begin(), order_.end());
}

ExperimentCost::ExperimentCost(const AxisStructure& structure,
                               const ParameterMap& map,
                               const FitExperiment& experiment,
                               int theta_size, int state_index,
                               EvaluationCounter* counter,
                               const SampleSigmas* sample_sigma)
    : structure_(structure),
      map_(map),
      experiment_(experiment),
      sample_sigma_(sample_sigma),
      grid_(MakeGrid(experiment.options, experiment.drive)),
      state_index_(state_index),
      theta_size_(theta_size),
      counter_(counter) {
  drive_ = &experiment.drive;
  if (!StageInputsCover(experiment.drive.stage_inputs.get(), grid_)) {
    own_drive_ = experiment.drive;
    own_drive_->stage_inputs = MakeStageInputs(*own_drive_, grid_);
    drive_ = &*own_drive_;
  }
  for (const FittedChannel& f : experiment_.fitted) {
    num_residuals_ += static_cast<int>(experiment_.Measured(f.channel).size());
  }
  for (int j = 0; j < map_.num_free(); ++j) {
    if (!IsSensorParameter(map_.free()[j].name)) plant_index_.push_back(j);
  }
  if (state_index_ >= 0) {
    plant_index_.push_back(state_index_);
    plant_index_.push_back(state_index_ + 1);
  }
}

ceres::CostFunction* ExperimentCost::Create(const AxisStructure& structure,
                                            const ParameterMap& map,
                                            const FitExperiment& experiment,
                                            int theta_size, int state_index,
                                            EvaluationCounter* counter,
                                            const SampleSigmas* sample_sigma) {
  auto* functor = new ExperimentCost(structure, map, experiment, theta_size, state_index,
                                     counter, sample_sigma);
  return MakeNarrowest<kJetLane>(functor, theta_size, sample_sigma);
}

}  // namespace axis
