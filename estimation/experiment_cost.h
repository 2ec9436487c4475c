// The cost of one recorded experiment for Ceres: simulate the experiment
// with the current parameters (sim/simulate.h, differentiated with
// ceres::Jet) and return (simulated − measured)/σ for every sample of every
// fitted channel.
#ifndef ESTIMATION_EXPERIMENT_COST_H_
#define ESTIMATION_EXPERIMENT_COST_H_

#include <atomic>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <ceres/ceres.h>

#include "estimation/estimation_problem.h"
#include "estimation/jet_widths.h"
#include "estimation/parameter_tie.h"
#include "sim/simulate.h"

namespace axis {

// The map between the optimiser's vector θ and the model parameters:
// θ_k = log(p_k) for positive parameters (FreeParameter::log), p_k/scale_k
// otherwise. After the free parameters, θ holds (y0, y1) for every experiment
// whose initial state is estimated. Parameters tied to another
// (estimation/parameter_tie.h) take its value, in `base` and in Apply.
class ParameterMap {
 public:
  // Throws std::invalid_argument if a free or tied parameter is not a model
  // name, or a free parameter is tied.
  ParameterMap(const AxisParams<double>& base, std::vector<FreeParameter> free,
               const std::vector<ParameterTie>& ties = {});

  int num_free() const { return static_cast<int>(free_.size()); }
  const std::vector<FreeParameter>& free() const { return free_; }
  const AxisParams<double>& base() const { return base_; }

  double ToInternal(int k, double value) const {
    return free_[k].log ? std::log(value) : value / free_[k].scale;
  }
  double FromInternal(int k, double theta) const {
    return free_[k].log ? std::exp(theta) : theta * free_[k].scale;
  }
  // d(value)/d(θ_k) at θ_k: the Jacobian of the map, for the covariance.
  double Derivative(int k, double theta) const {
    return free_[k].log ? std::exp(theta) : free_[k].scale;
  }

  // The model parameters at θ (first num_free() entries), the tied ones
  // set to their sources'. Never throws but std::bad_alloc.
  template <typename T>
  AxisParams<T> Apply(const T* theta) const {
    using std::exp;
    AxisParams<T> p = base_.cast<T>();
    int index = 0;
    size_t next = 0;
    VisitParams([&](const char*, const char*, T& field) {
      for (size_t k = next; k < order_.size() && order_[k].first == index; ++k) {
        const int j = order_[k].second;
        field = free_[j].log ? T(exp(theta[j])) : T(theta[j] * free_[j].scale);
        next = k + 1;
      }
      ++index;
    }, p);
    ApplyTies(ties_, &p);
    return p;
  }

 private:
  AxisParams<double> base_;
  std::vector<FreeParameter> free_;
  std::vector<std::pair<int, int>> ties_;  // TieIndices
  // (VisitParams index, free index), sorted by VisitParams index.
  std::vector<std::pair<int, int>> order_;
};

// Evaluation counts, shared by the costs of a fit (thread-safe), and the
// switch of their residual-only evaluations' sensitivity guard.
struct EvaluationCounter {
  std::atomic<int> simulations{0};  // residual-only evaluations
  std::atomic<int> jacobians{0};    // evaluations with derivatives
  // True (the default): residual-only evaluations simulate a one-direction
  // Jet and fail where the Jacobian would blow up (ExperimentCost::
  // operator()). False: plain double simulations (about 2× faster,
  // bench_rk4_step), for cost probes whose points the solver never starts
  // from unless re-checked with the guard on, and for the trial points of
  // the fit's solver runs, which run again with the guard if they fail
  // (estimation/internal/optimistic_solve.h).
  std::atomic<bool> guard{true};
};

// Turns `counter`'s guard off for its lifetime and puts back what it found
// (also on an exception). A null counter is left alone.
class ScopedGuardOff {
 public:
  explicit ScopedGuardOff(EvaluationCounter* counter)
      : counter_(counter), was_(counter != nullptr && counter->guard) {
    if (counter_ != nullptr) counter_->guard = false;
  }
  ~ScopedGuardOff() {
    if (counter_ != nullptr) counter_->guard = was_;
  }
  ScopedGuardOff(const ScopedGuardOff&) = delete;
  ScopedGuardOff& operator=(const ScopedGuardOff&) = delete;

 private:
  EvaluationCounter* counter_;
  bool was_;
};

// Per-sample σ_k of one experiment's fitted channels, in experiment.fitted
// order: each empty (σ_k = the channel's σ) or one per sample, each ≥ σ
// (estimation/internal/instant_sample_sigma.h). Set by the fit at its estimate,
// never by the problem.
using SampleSigmas = std::vector<std::vector<double>>;

// Cost functor of one experiment (one per experiment; the experiments of a
// job share the parameter block θ).
class ExperimentCost {
 public:
  // Creates the Ceres cost of `experiment` over a parameter block of
  // `theta_size` entries; `state_index` is the position of the experiment's
  // (y0, y1) in θ, or -1 to start from experiment.initial_state. The model,
  // map, experiment and counter must outlive the cost, and the structure,
  // map and experiment must not change while it lives (its last Jacobian
  // is remembered, below). Where the
  // experiment's drive carries no stage inputs covering the grid
  // (StageInputsCover), the cost copies the drive at creation with its
  // input sampled at the grid's stage times (MakeStageInputs), and later
  // changes to the experiment's drive are not seen. The number of residuals
  // is Σ over fitted channels of the sample count. `sample_sigma`, if not
  // null, holds the per-sample σ_k the residuals are divided by where it
  // has one per sample for a channel (read at each evaluation: the fit may
  // change it between solves); it must outlive the cost. An evaluation
  // with a Jacobian at the point (and per-sample σ) of the last successful
  // one answers from memory, bit for bit the same
  // (estimation/internal/last_jacobian_memo.h): the covariance at a fit's
  // end re-reads the solver's last Jacobian. Memory: one Jacobian
  // (residuals × θ size doubles) per cost while it lives.
  static ceres::CostFunction* Create(const AxisStructure& structure,
                                     const ParameterMap& map,
                                     const FitExperiment& experiment,
                                     int theta_size, int state_index,
                                     EvaluationCounter* counter,
                                     const SampleSigmas* sample_sigma = nullptr);

  ExperimentCost(const AxisStructure& structure, const ParameterMap& map,
                 const FitExperiment& experiment, int theta_size,
                 int state_index, EvaluationCounter* counter,
                 const SampleSigmas* sample_sigma = nullptr);
  // drive_ may point into the object itself.
  ExperimentCost(const ExperimentCost&) = delete;
  ExperimentCost& operator=(const ExperimentCost&) = delete;

  // Residuals (ŷ − y)/σ, channel by channel in experiment.fitted order (σ_k
  // per sample where the cost's SampleSigmas hold them).
  // Returns false, so that Ceres rejects the trial step, if the simulation
  // or a residual is not finite, or if a residual's sensitivity to θ exceeds
  // kMaxSensitivity. Residual-only evaluations (T = double) simulate with a
  // one-direction Jet (all θ moved together) so that a candidate point whose
  // Jacobian would blow up is rejected before Ceres accepts it: Ceres
  // evaluates the Jacobian only after accepting a step, and fails outright if
  // that evaluation fails. With counter->guard off they simulate in double
  // and check only finiteness: the fit's solver runs do so and run again
  // with the guard only if they fail (estimation/internal/optimistic_solve.h).
  // Never throws.
  template <typename T>
  bool operator()(T const* const* parameters, T* residuals) const {
    if constexpr (std::is_same<T, double>::value) {
      ++counter_->simulations;
      if (!counter_->guard) return Residuals(parameters[0], residuals);
      const std::vector<double> all_ones(theta_size_, 1.0);
      return Directional(parameters[0], all_ones.data(), residuals, nullptr);
    } else {
      ++counter_->jacobians;
      return Residuals(parameters[0], residuals);
    }
  }

  // Bound on |∂r/∂θ| (r weighted by 1/σ, θ in log units for positive
  // parameters): beyond it a relative parameter change of 1e-6 would move a
  // residual by more than 10⁴ σ, i.e. the trajectory is hypersensitive
  // (chattering at a limit, sensitivities growing exponentially) and its
  // linearisation means nothing.
  static constexpr double kMaxSensitivity = 1e10;

  int num_residuals() const { return num_residuals_; }

  // Residuals at θ and, if `derivative` is non-null, their derivative along
  // `direction` (one Jet<1> simulation): the score test's candidate columns.
  // Returns false as operator() does. Never throws.
  bool Directional(const double* theta, const double* direction,
                   double* residuals, double* derivative) const {
    using Direction = ceres::Jet<double, 1>;
    std::vector<Direction> t(theta_size_);
    for (int k = 0; k < theta_size_; ++k) {
      t[k] = Direction(theta[k]);
      t[k].v[0] = direction[k];
    }
    std::vector<Direction> r(num_residuals_);
    if (!Residuals(t.data(), r.data())) return false;
    for (int k = 0; k < num_residuals_; ++k) {
      residuals[k] = r[k].a;
      if (derivative != nullptr) derivative[k] = r[k].v[0];
    }
    return true;
  }

 private:
  // The experiment's initial state at θ (its (y0, y1) from θ where it is
  // estimated).
  template <typename T>
  AxisState<T> InitialState(const T* theta, const AxisParams<T>& p) const {
    AxisState<T> y0 = experiment_.initial_state.cast<T>();
    if (state_index_ >= 0) {
      y0[0] = theta[state_index_];
      y0[1] = theta[state_index_ + 1];
      y0[2] = y0[0] / p.r_g;
      y0[3] = y0[1] / p.r_g;
    }
    return y0;
  }

  // The trace at θ. Where θ's Jets carry more derivative parts than the
  // entries of θ that act on the plant (the free parameters other than
  // sensor ones, sim/axis_params.h IsSensorParameter, and this
  // experiment's own initial state), the plant is integrated with Jets of
  // those entries alone (the narrowest of the simulator's instantiated
  // widths, jet_widths.h, or in double if none), its derivatives chained
  // to θ's, and the sensor front end applied in T: the integration's cost
  // grows with the Jet's width, and a discovered front end (a delay, a
  // filter) adds entries that never act on the plant. The same values and derivatives
  // as Simulate at θ, up to the rounding of the chain rule's products by
  // θ's derivative parts (exact for the unit seeds Ceres uses).
  template <typename T>
  Trace<T> SimulateAt(const T* theta) const {
    const AxisParams<T> p = map_.Apply(theta);
    if constexpr (!std::is_same_v<T, double>) {
      const int k = static_cast<int>(plant_index_.size());
      if (k == 0) return PlantInNarrowerJets<double>(theta, p);
      return PlantInNarrowestJet<kJetLane>(k, theta, p);
    }
    return Simulate(structure_, p, InitialState(theta, p), *drive_, experiment_.options, grid_);
  }

  // The plant in the narrowest width of jet_widths.h from `Width` up that
  // holds its k entries, if narrower than T; the whole trace in T otherwise.
  template <int Width, typename T>
  Trace<T> PlantInNarrowestJet(int k, const T* theta, const AxisParams<T>& p) const {
    if constexpr (Width < T::DIMENSION) {
      if (k <= Width) return PlantInNarrowerJets<ceres::Jet<double, Width>>(theta, p);
      return PlantInNarrowestJet<Width + kJetLane>(k, theta, p);
    } else {
      return Simulate(structure_, p, InitialState(theta, p), *drive_, experiment_.options, grid_);
    }
  }

  // SimulateAt's split: the plant in P (derivative part i: θ entry
  // plant_index_[i]), lifted to T by the chain rule, then the front end in
  // T with `p` (the parameters at θ in T).
  template <typename P, typename T>
  Trace<T> PlantInNarrowerJets(const T* theta, const AxisParams<T>& p) const {
    std::vector<P> plant_theta(theta_size_);
    for (int j = 0; j < theta_size_; ++j) plant_theta[j] = P(ScalarValue(theta[j]));
    if constexpr (!std::is_same_v<P, double>) {
      for (size_t i = 0; i < plant_index_.size(); ++i) plant_theta[plant_index_[i]].v[i] = 1.0;
    }
    const AxisParams<P> plant_params = map_.Apply(plant_theta.data());
    const PlantRecord<P> plant =
        SimulatePlant(structure_, plant_params, InitialState(plant_theta.data(), plant_params),
                      *drive_, experiment_.options, grid_, /*progress=*/nullptr,
                      /*counted_with_derivatives=*/true);
    const auto lift = [&](const P& x) {
      T y(ScalarValue(x));
      if constexpr (!std::is_same_v<P, double>) {
        for (size_t i = 0; i < plant_index_.size(); ++i) {
          y.v += x.v[i] * theta[plant_index_[i]].v;
        }
      }
      return y;
    };
    return ApplySensorFrontEnd(structure_, p, grid_, MapPlantRecord<T>(plant, lift));
  }

  template <typename T>
  bool Residuals(const T* theta, T* residuals) const {
    const Trace<T> trace = SimulateAt(theta);
    if (!trace.finite) return false;
    size_t r = 0;
    for (size_t i = 0; i < experiment_.fitted.size(); ++i) {
      const FittedChannel& f = experiment_.fitted[i];
      const std::vector<T>& simulated = trace[f.channel];
      const std::vector<double>& measured = experiment_.Measured(f.channel);
      const double inv_sigma = 1.0 / f.sigma;
      const std::vector<double>* per_sample =
          sample_sigma_ != nullptr && i < sample_sigma_->size() &&
                  (*sample_sigma_)[i].size() == measured.size()
              ? &(*sample_sigma_)[i]
              : nullptr;
      for (size_t k = 0; k < measured.size(); ++k) {
        residuals[r] = (simulated[k] - measured[k]) *
                       (per_sample != nullptr ? 1.0 / (*per_sample)[k] : inv_sigma);
        if (!AllFinite(residuals[r]) ||
            MaxAbsDerivative(residuals[r]) > kMaxSensitivity) {
          return false;
        }
        ++r;
      }
    }
    return true;
  }

  const AxisStructure& structure_;
  const ParameterMap& map_;
  const FitExperiment& experiment_;
  const SampleSigmas* sample_sigma_;
  SimulationGrid grid_;
  // The drive simulated: experiment_.drive if its stage inputs cover the
  // grid (FitParameters shares one table per experiment with its horizon
  // stages), else own_drive_, a copy with its input sampled here.
  std::optional<Drive> own_drive_;
  const Drive* drive_ = nullptr;
  int state_index_;
  int theta_size_;
  // The entries of θ that act on this experiment's plant, ascending: the
  // free parameters other than sensor ones and its own initial state.
  std::vector<int> plant_index_;
  int num_residuals_ = 0;
  EvaluationCounter* counter_;
};

}  // namespace axis

#endif  // ESTIMATION_EXPERIMENT_COST_H_
