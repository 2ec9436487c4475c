#include "estimation/fit.h"

#include "common/concurrency.h"
#include "common/format.h"
#include "common/progress.h"
#include "common/statistics.h"
#include "estimation/at_estimate.h"
#include "estimation/evaluate_experiment.h"
#include "estimation/experiment_cost.h"
#include "estimation/fit_notes.h"
#include "estimation/fit_result.h"
#include "estimation/horizon_checkpoint.h"
#include "estimation/roughness_cost.h"
#include "estimation/shared_level.h"
#include "estimation/uncertainty.h"
#include "job/fit_job.h"
#include "job/solver_settings.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include <ceres/ceres.h>

#include "sim/controller.h"
#include "sim/csv.h"
#include "sim/interrupt.h"
#include "sim/random.h"

namespace axis {
namespace {

// Prints iteration, cost, relative decrease and step norm: one line per
// iteration, or on a terminal (ProgressStream) the detail of its status
// line. `plain_lines` false: nothing but that detail (the refits of the
// profile, which printed nothing before issue 14).
class ProgressPrinter : public ceres::IterationCallback {
 public:
  ProgressPrinter(std::ostream* out, int start, double horizon, bool plain_lines = true)
      : out_(out), progress_(AsProgressStream(out)), start_(start), horizon_(horizon),
        plain_lines_(plain_lines) {}
  ceres::CallbackReturnType operator()(
      const ceres::IterationSummary& s) override {
    if (progress_ != nullptr && progress_->terminal()) {
      std::ostringstream detail;
      detail << "iter " << s.iteration << ", cost " << std::setprecision(6) << s.cost;
      progress_->Detail(detail.str());
    } else if (out_ != nullptr && plain_lines_) {
      *out_ << "start " << std::setw(2) << start_ << "  horizon "
            << std::fixed << std::setprecision(3) << horizon_ << " s  iter "
            << std::setw(3) << s.iteration << "  cost " << std::scientific
            << std::setprecision(6) << s.cost << "  rel.decrease "
            << std::setprecision(3) << s.relative_decrease << "  step "
            << s.step_norm << std::defaultfloat << "\n";
      out_->flush();
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  std::ostream* out_;
  ProgressStream* progress_;
  int start_;
  double horizon_;
  bool plain_lines_;
};

// Adds `phase`'s time and evaluations to the phase of that name in
// result->phases (appended, in first-run order, if it has none yet).
void AddPhase(const FitPhase& phase, FitResult* result) {
  auto it = std::find_if(result->phases.begin(), result->phases.end(),
                         [&](const FitPhase& f) { return f.name == phase.name; });
  if (it == result->phases.end()) {
    result->phases.push_back(phase);
    return;
  }
  it->seconds += phase.seconds;
  it->simulations += phase.simulations;
  it->jacobians += phase.jacobians;
}

// Adds the wall time and evaluations between construction and destruction
// to the phase `name` of *result (FitResult::phases).
class PhaseTimer {
 public:
  PhaseTimer(const char* name, const EvaluationCounter& counter, FitResult* result)
      : name_(name), counter_(counter), result_(result),
        start_(std::chrono::steady_clock::now()),
        simulations_(counter.simulations), jacobians_(counter.jacobians) {}
  ~PhaseTimer() {
    AddPhase(FitPhase{name_,
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_)
                          .count(),
                      counter_.simulations - simulations_, counter_.jacobians - jacobians_},
             result_);
  }
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;

 private:
  std::string name_;
  const EvaluationCounter& counter_;
  FitResult* result_;
  std::chrono::steady_clock::time_point start_;
  int simulations_;
  int jacobians_;
};

// The first `horizon` seconds of an experiment (all of it if shorter).
FitExperiment Truncate(const FitExperiment& e, double horizon) {
  FitExperiment out = e;
  size_t n = 0;
  while (n < e.t.size() && e.t[n] <= horizon * (1 + 1e-9)) ++n;
  n = std::max<size_t>(n, 3);
  if (n >= e.t.size()) return out;
  out.t.resize(n);
  for (auto& m : out.measured) m.resize(n);
  out.options.duration = out.t.back();
  return out;
}

// The optimisation vector θ, its map to parameters and its bounds.
struct Problem {
  std::unique_ptr<ParameterMap> map;
  std::vector<double> theta;
  std::vector<double> lower, upper;  // internal bounds
  EvaluationCounter counter;
};

// One least-squares problem over a set of experiments (a horizon stage).
struct Stage {
  double horizon = 0.0;  // s; the last stage covers every sample
  std::vector<FitExperiment> experiments;  // referenced by the costs
  std::unique_ptr<ceres::Problem> problem;
  int num_residuals = 0;
};

void BuildStage(const FitJob& job, const ParameterMap& map,
                const std::vector<int>& state_index,
                const std::vector<double>& lower,
                const std::vector<double>& upper, double* theta,
                EvaluationCounter* counter, Stage* stage) {
  const int theta_size = static_cast<int>(lower.size());
  stage->problem = std::make_unique<ceres::Problem>();
  for (size_t j = 0; j < stage->experiments.size(); ++j) {
    ceres::CostFunction* cost =
        ExperimentCost::Create(job.model.structure, map, stage->experiments[j],
                               theta_size, state_index[j], counter);
    stage->num_residuals += cost->num_residuals();
    stage->problem->AddResidualBlock(cost, nullptr, theta);
  }
  // A force map's roughness penalty (discovery/force_map.h): in the cost, not in
  // the residual count (it is a prior on the map, not data).
  if (ceres::CostFunction* roughness = RoughnessCost::Create(
          job.model.structure.force_map, map, theta_size, job.force_map_lambda,
          job.force_map_anchor)) {
    stage->problem->AddResidualBlock(roughness, nullptr, theta);
  }
  for (int k = 0; k < theta_size; ++k) {
    if (std::isfinite(lower[k])) stage->problem->SetParameterLowerBound(theta, k, lower[k]);
    if (std::isfinite(upper[k])) stage->problem->SetParameterUpperBound(theta, k, upper[k]);
  }
}

// Why `checkpoint` is not one of the fit with these stages and starts
// (estimation/horizon_checkpoint.h), or "" if it is: the number of starts and
// their points, the shorter stages' horizons, the stages per start (fewer
// than the job's) and their points' size, and the cost at the first start
// on the first horizon (relative tolerance 1e-9: the same cost summed on
// another number of threads). May move *theta to starts[0].
std::string CheckpointMismatch(const HorizonCheckpoint& checkpoint,
                               const std::vector<Stage>& stages,
                               const std::vector<std::vector<double>>& starts, int threads,
                               std::vector<double>* theta) {
  if (checkpoint.starts.size() != starts.size()) {
    return std::to_string(checkpoint.starts.size()) + " start(s) where the job has " +
           std::to_string(starts.size());
  }
  std::vector<double> horizons;
  for (size_t i = 0; i + 1 < stages.size(); ++i) horizons.push_back(stages[i].horizon);
  if (checkpoint.horizons != horizons) return "other horizons";
  for (size_t s = 0; s < starts.size(); ++s) {
    const HorizonCheckpoint::Start& start = checkpoint.starts[s];
    if (start.point != starts[s]) return "start " + std::to_string(s) + " elsewhere";
    if (start.stages.size() >= stages.size()) return "too many stages";
    for (const HorizonCheckpoint::StageEnd& done : start.stages) {
      if (done.theta.size() != theta->size()) return "points of another size";
    }
  }
  const std::vector<HorizonCheckpoint::StageEnd>& first = checkpoint.starts[0].stages;
  if (!first.empty() && first[0].usable) {
    const double cost = CostAt(stages[0].problem.get(), starts[0], threads, theta);
    if (!(std::abs(cost - first[0].start_cost) <= 1e-9 * std::abs(first[0].start_cost))) {
      return "another cost on the first horizon (other data or model)";
    }
  }
  return "";
}

// JᵀJ of the weighted residuals over the first n entries of θ at the
// current θ (the Gauss–Newton approximation of the cost's Hessian), or false
// if the Jacobian cannot be evaluated there.
bool GaussNewtonMatrix(ceres::Problem* problem, int n, Eigen::MatrixXd* jtj) {
  ceres::CRSMatrix crs;
  double cost = 0.0;
  if (!problem->Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr,
                         nullptr, &crs)) {
    return false;
  }
  *jtj = Eigen::MatrixXd::Zero(n, n);
  for (int row = 0; row < crs.num_rows; ++row) {
    for (int a = crs.rows[row]; a < crs.rows[row + 1]; ++a) {
      if (crs.cols[a] >= n) continue;
      for (int b = crs.rows[row]; b < crs.rows[row + 1]; ++b) {
        if (crs.cols[b] >= n) continue;
        (*jtj)(crs.cols[a], crs.cols[b]) += crs.values[a] * crs.values[b];
      }
    }
  }
  return true;
}

// Stops a Levenberg–Marquardt run once a successful step lowers the cost by
// less than `tolerance` (absolute): Ceres' function_tolerance is relative,
// and near a zero-residual optimum (noise-free records) the relative
// decrease stays large down to round-off.
class AbsoluteDecreaseStop : public ceres::IterationCallback {
 public:
  explicit AbsoluteDecreaseStop(double tolerance) : tolerance_(tolerance) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (s.iteration > 0 && s.step_is_successful && s.cost_change < tolerance_) {
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  double tolerance_;
};

// The relative function and parameter tolerance of the continuation's
// shorter horizons (at least; the job's if larger): they only deliver a warm
// start for the next.
constexpr double kStageParameterTolerance = 1e-4;

// A point counts as lower than the estimate if its cost (½Σr² of σ-weighted
// residuals, i.e. half a χ²) is below by more than `relative` (the solver's
// function_tolerance, at least 1e-9) times the cost plus 1e-6 absolute. The
// solver itself stops once an iteration gains less than function_tolerance
// relative, so a smaller difference is within its accuracy and restarting
// it there moves the estimate by a few thousandths of a standard deviation
// (the paper job: three probe rounds and two local-restart passes, 9 s,
// for a decrease of 4.6e-5 in a cost of 4070, where 4.1e-5 is the solver's
// own stop); a χ² difference of 2e-6 means nothing statistically, and on
// noise-free records (cost ~1e-8 at the optimum) smaller differences are
// round-off that would otherwise restart the solver again and again
// (CostResolution, estimation/fit.h).
constexpr double kLowerRelative = 1e-9;
constexpr double kLowerAbsolute = 1e-6;

// The cost a point must be below to count as lower than `cost` (see above).
double LowerThan(double cost, double relative) {
  return cost - CostResolution(cost, relative);
}

// One round of the optimum check: the cost at θ* + s·d for the probe
// directions d (every coordinate and every principal axis of (JᵀJ)⁻¹, scaled
// to one standard deviation — a change of ½ in cost on a quadratic — and the
// last step, scaled alike) and s = ±{0.01, 0.3, 1, 3, 10}, clipped to the
// bounds. Returns the lowest point found and its cost in *best / *best_cost
// (θ* and `cost` if nothing is lower). The probes simulate in double (the
// guard of `counter` off); a point lower than θ* is kept only if it also
// passes the sensitivity guard (ExperimentCost), as the solver will start
// from it. The cost is evaluated on `threads` threads (CostAt). Leaves
// *theta at θ*.
void ProbeRound(ceres::Problem* problem, const std::vector<double>& lower,
                const std::vector<double>& upper,
                const std::vector<double>& last_step, double cost,
                EvaluationCounter* counter, int threads,
                std::vector<double>* theta, std::vector<double>* best,
                double* best_cost, int* probes) {
  const int n = static_cast<int>(theta->size());
  const std::vector<double> centre = *theta;
  *best = centre;
  *best_cost = cost;
  Eigen::MatrixXd jtj;
  if (!GaussNewtonMatrix(problem, n, &jtj)) return;
  std::vector<Eigen::VectorXd> directions;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(jtj);
  const double largest = eig.eigenvalues().maxCoeff();
  const Eigen::MatrixXd cov = eig.eigenvectors() *
      eig.eigenvalues()
          .unaryExpr([&](double l) { return l > 1e-14 * largest ? 1.0 / l : 0.0; })
          .asDiagonal() *
      eig.eigenvectors().transpose();
  for (int k = 0; k < n; ++k) {
    if (cov(k, k) <= 0.0) continue;
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    d[k] = std::sqrt(cov(k, k));
    directions.push_back(d);
  }
  for (int e = 0; e < n; ++e) {
    const double l = eig.eigenvalues()[e];
    if (l > 1e-14 * largest) directions.push_back(eig.eigenvectors().col(e) / std::sqrt(l));
  }
  Eigen::VectorXd step = Eigen::Map<const Eigen::VectorXd>(last_step.data(), n);
  const double curvature = step.dot(jtj * step);
  if (curvature > 0.0) directions.push_back(step / std::sqrt(curvature));
  std::vector<std::pair<double, std::vector<double>>> lower_points;
  counter->guard = false;
  for (const Eigen::VectorXd& d : directions) {
    for (double s : {0.01, 0.3, 1.0, 3.0, 10.0}) {
      for (double sign : {-1.0, 1.0}) {
        std::vector<double> point = centre;
        for (int k = 0; k < n; ++k) {
          point[k] = std::clamp(centre[k] + sign * s * d[k], lower[k], upper[k]);
        }
        const double c = CostAt(problem, point, threads, theta);
        ++*probes;
        if (c < cost) lower_points.emplace_back(c, point);
      }
    }
  }
  counter->guard = true;
  // The lowest point that passes the guard (the same cost, by the same
  // arithmetic, when it passes).
  std::sort(lower_points.begin(), lower_points.end());
  for (const auto& [c, point] : lower_points) {
    if (std::isfinite(CostAt(problem, point, threads, theta))) {
      *best_cost = c;
      *best = point;
      break;
    }
  }
  std::copy(centre.begin(), centre.end(), theta->begin());
}

// Covariance (JᵀJ)⁻¹ of the single parameter block `theta` (size n) of
// `problem` by ceres::Covariance (DENSE_SVD); the pseudo-inverse with the
// null space dropped if JᵀJ is rank deficient; NaN where neither works or
// JᵀJ is not finite. *jtj_out (if not null) receives JᵀJ (n×n; empty if
// the Jacobian could not be evaluated), for NullSpaceMembersOf.
Eigen::MatrixXd CovarianceOfTheta(ceres::Problem* problem, double* theta, int n,
                                  int threads, Eigen::MatrixXd* jtj_out) {
  Eigen::MatrixXd out =
      Eigen::MatrixXd::Constant(n, n, std::numeric_limits<double>::quiet_NaN());
  // A Jacobian with non-finite entries (a hypersensitive full-loop record
  // whose sensitivities overflow only in some entries) crashed Eigen's SVD
  // inside ceres::Covariance (SIGSEGV in JacobiSVD::compute, a probe's Y
  // axis chirp at 500 Hz): no covariance then.
  Eigen::MatrixXd jtj;
  const bool evaluated = GaussNewtonMatrix(problem, n, &jtj);
  if (jtj_out != nullptr) *jtj_out = evaluated ? jtj : Eigen::MatrixXd();
  if (!evaluated || !jtj.allFinite()) return out;
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  co.num_threads = threads;
  co.null_space_rank = 0;
  co.min_reciprocal_condition_number = 1e-14;
  const std::vector<std::pair<const double*, const double*>> pairs = {{theta, theta}};
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> c(n, n);
  ceres::Covariance covariance(co);
  if (covariance.Compute(pairs, problem)) {
    covariance.GetCovarianceBlock(theta, theta, c.data());
    out = c;
    return out;
  }
  // Rank deficient: the pseudo-inverse, with the null space dropped.
  co.null_space_rank = -1;
  ceres::Covariance pseudo(co);
  if (pseudo.Compute(pairs, problem)) {
    pseudo.GetCovarianceBlock(theta, theta, c.data());
    out = c;
  }
  return out;
}

// Free parameters (the first n_free of θ) that lie in the numerical null
// space of the weighted Jacobian whose JᵀJ over them is `jtj` (n_free ×
// n_free): the columns are scaled to unit norm (so units do not matter),
// and a parameter is in the null space if it has a component above 0.1 in
// an eigenvector of JᵀJ whose eigenvalue is below 1e-10 of the largest (or
// if its column is zero).
std::vector<bool> NullSpaceMembersOf(const Eigen::MatrixXd& jtj, int n_free) {
  std::vector<bool> out(n_free, false);
  Eigen::VectorXd scale(n_free);
  for (int k = 0; k < n_free; ++k) {
    scale[k] = jtj(k, k) > 0.0 ? 1.0 / std::sqrt(jtj(k, k)) : 0.0;
    if (jtj(k, k) <= 0.0) out[k] = true;
  }
  const Eigen::MatrixXd scaled = scale.asDiagonal() * jtj * scale.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scaled);
  const double largest = eig.eigenvalues().maxCoeff();
  for (int e = 0; e < n_free; ++e) {
    if (eig.eigenvalues()[e] > 1e-10 * largest) continue;
    for (int k = 0; k < n_free; ++k) {
      if (std::abs(eig.eigenvectors()(k, e)) > 0.1) out[k] = true;
    }
  }
  return out;
}

// NullSpaceMembersOf the Jacobian of `problem` at the current θ; every
// parameter if it cannot be evaluated there.
std::vector<bool> NullSpaceMembers(ceres::Problem* problem, int n_free) {
  Eigen::MatrixXd jtj;
  if (!GaussNewtonMatrix(problem, n_free, &jtj)) {
    return std::vector<bool>(n_free, true);
  }
  return NullSpaceMembersOf(jtj, n_free);
}

// One progress line for a continuation stage that failed, with the free
// parameters where it failed.
void ReportStageFailure(const FitJob& job, const ParameterMap& map,
                        const std::vector<double>& theta, size_t start,
                        double horizon, const std::string& message,
                        const std::string& action, std::ostream* progress) {
  if (!job.solver.progress || progress == nullptr) return;
  *progress << "start " << std::setw(2) << start << "  horizon " << std::fixed
            << std::setprecision(3) << horizon << std::defaultfloat
            << " s  failed (" << message << ") at";
  for (int k = 0; k < map.num_free(); ++k) {
    *progress << " " << job.free[k].name << " = " << map.FromInternal(k, theta[k]);
  }
  *progress << "; " << action << "\n";
}

}  // namespace

namespace {

// Appends the fixed parameters (those not in result->free_names) at their
// values in `fitted`, standard errors and intervals NaN; only those the model
// configuration uses (no per-channel sensor parameters).
void AppendFixedEstimates(AxisParams<double> fitted, FitResult* result) {
  for (const ParamInfo& info : ListParams()) {
    if (std::find(result->free_names.begin(), result->free_names.end(),
                  info.name) != result->free_names.end()) {
      continue;
    }
    if (info.name.find('.') != std::string::npos) continue;
    ParameterEstimate e;
    e.name = info.name;
    e.unit = info.unit;
    e.value = *FindParam(&fitted, info.name);
    e.initial = e.value;
    e.free = false;
    e.std_error = e.ci95_low = e.ci95_high = e.std_error_gauss_newton =
        e.std_error_bootstrap = e.bootstrap_low = e.bootstrap_high =
            std::numeric_limits<double>::quiet_NaN();
    result->parameters.push_back(e);
  }
}

// The parameters of a fit stopped before the whole record (FitResult::
// abandoned_horizon): every one at its value at θ (internal coordinates),
// no standard errors.
void AppendEstimates(const FitJob& job, const ParameterMap& map,
                     const std::vector<double>& theta, FitResult* result) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k < map.num_free(); ++k) {
    ParameterEstimate e;
    e.name = job.free[k].name;
    e.unit = job.free[k].unit;
    e.value = map.FromInternal(k, theta[k]);
    e.initial = job.free[k].initial;
    e.free = true;
    e.std_error = e.std_error_gauss_newton = e.std_error_bootstrap = e.bootstrap_low =
        e.bootstrap_high = e.ci95_low = e.ci95_high = nan;
    e.determined = false;
    result->free_names.push_back(e.name);
    result->parameters.push_back(e);
  }
  AppendFixedEstimates(map.Apply(theta.data()), result);
}

// The first of a start's recorded (stage, BIC bound) pairs whose bound
// passed `above`, or null.
const std::pair<size_t, double>* FirstPassed(
    const std::vector<std::pair<size_t, double>>& bounds, double above) {
  for (const auto& entry : bounds) {
    if (entry.second > above) return &entry;
  }
  return nullptr;
}

// Ends a stage once solver.pending_level is published and a shorter
// stage's bound recorded before (`bounds`: (stage, bound)) passed it,
// together with `abandon_above` (the job's own level): the start stops at
// that stage, and what this one would still do is not needed.
class PendingLevelStop : public ceres::IterationCallback {
 public:
  PendingLevelStop(const SharedLevel* level, double abandon_above,
                   const std::vector<std::pair<size_t, double>>* bounds)
      : level_(level), abandon_above_(abandon_above), bounds_(bounds) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    const std::optional<double> level = level_->TryAbandonAbove();
    if (!level) return ceres::SOLVER_CONTINUE;
    return FirstPassed(*bounds_, std::min(abandon_above_, *level)) != nullptr
               ? ceres::SOLVER_TERMINATE_SUCCESSFULLY
               : ceres::SOLVER_CONTINUE;
  }

 private:
  const SharedLevel* const level_;
  const double abandon_above_;
  const std::vector<std::pair<size_t, double>>* const bounds_;
};

// FitParameters without publishing to solver.publish_level.
FitResult FitAndKeepLevel(const FitJob& job, std::ostream* progress) {
  Problem p;
  p.map = std::make_unique<ParameterMap>(job.model.params, job.free);
  const int n_free = p.map->num_free();
  for (int k = 0; k < n_free; ++k) {
    const FreeParameter& f = job.free[k];
    p.theta.push_back(p.map->ToInternal(k, f.initial));
    p.lower.push_back(p.map->ToInternal(k, f.lower));
    p.upper.push_back(p.map->ToInternal(k, f.upper));
  }
  // Estimated initial states (y0, y1) follow the parameters in θ.
  std::vector<int> state_index;
  for (const FitExperiment& e : job.experiments) {
    if (!e.estimate_initial_state) {
      state_index.push_back(-1);
      continue;
    }
    state_index.push_back(static_cast<int>(p.theta.size()));
    for (int s = 0; s < 2; ++s) {
      p.theta.push_back(e.initial_state[s]);
      p.lower.push_back(-std::numeric_limits<double>::infinity());
      p.upper.push_back(std::numeric_limits<double>::infinity());
    }
  }
  const int theta_size = static_cast<int>(p.theta.size());
  double* theta = p.theta.data();

  // Horizon continuation: stages over the first h0, 2·h0, 4·h0, ... seconds
  // of every experiment, then all of it. The fitted signals ring at the gear
  // resonance from t = 0, so on long records a mistuned k_g accumulates
  // several radians of phase and the cost has a local minimum per cycle; a
  // short horizon keeps the phase error below one cycle, and each stage
  // warm-starts the next.
  std::vector<Stage> stages;
  double longest = 0.0;
  for (const FitExperiment& e : job.experiments) longest = std::max(longest, e.t.back());
  for (double h = job.solver.first_horizon; h > 0.0 && h < longest; h *= 2.0) {
    Stage stage;
    stage.horizon = h;
    for (const FitExperiment& e : job.experiments) stage.experiments.push_back(Truncate(e, h));
    stages.push_back(std::move(stage));
  }
  {
    Stage full;
    full.horizon = longest;
    full.experiments = job.experiments;
    stages.push_back(std::move(full));
  }
  // The input at the RK4 stage times (sim/simulate.h StageInputs), sampled
  // once per experiment on its whole record and shared by the shorter
  // horizons, which use its first entries.
  for (size_t j = 0; j < job.experiments.size(); ++j) {
    const FitExperiment& e = job.experiments[j];
    const std::shared_ptr<const StageInputs> table =
        MakeStageInputs(e.drive, MakeGrid(e.options, e.drive));
    for (Stage& stage : stages) stage.experiments[j].drive.stage_inputs = table;
  }
  for (Stage& stage : stages) {
    BuildStage(job, *p.map, state_index, p.lower, p.upper, theta, &p.counter, &stage);
  }
  const int num_residuals = stages.back().num_residuals;
  ceres::Problem& full_problem = *stages.back().problem;
  ceres::Solver::Options options;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = job.solver.max_iterations;
  options.function_tolerance = job.solver.function_tolerance;
  options.parameter_tolerance = job.solver.parameter_tolerance;
  options.gradient_tolerance = job.solver.gradient_tolerance;
  options.num_threads = job.solver.threads;
  options.logging_type = ceres::SILENT;
  // Start LM well damped: Ceres' default initial radius (1e4) is nearly a
  // Gauss–Newton step, which from a factor-2 start jumps by a factor ~7 in
  // log space into parameter regions where the velocity loop chatters at its
  // limits and the sensitivities overflow.
  options.initial_trust_region_radius = job.solver.initial_trust_region_radius;
  // Solves that start next to a minimum (the local restarts, the profile
  // refits) run without the projected line search along the trust-region
  // step. With bounds on the parameters Ceres runs an Armijo search along
  // every step (trust_region_minimizer.cc, DoLineSearch, skipped when
  // max_num_line_search_step_size_iterations is 0), and its cubic
  // interpolation evaluates the gradient, i.e. the whole Jacobian, at the
  // full step before the candidate's cost is evaluated there again: an
  // iteration costs two Jacobians and one simulation instead of one of
  // each. Without it the step is still projected onto the bounds (the box's
  // Plus) and judged by the trust-region ratio, as without bounds. The
  // starts keep it: from random starts far from the data it helps (without
  // it FitTest.MultiStartReachesTheTruthFromRandomStarts reached the truth
  // in 4 of its 5 seeds instead of 5). The paper job (issue 11): local
  // restarts 3.9 → 2.1 s, profile intervals 15 → 10.4 s (6.9 s with the
  // function-tolerance stop below), the estimates unchanged to every
  // printed digit and the interval ends within 0.4 % of their half-widths.
  ceres::Solver::Options near_options = options;
  near_options.max_num_line_search_step_size_iterations = 0;

  // Starting points: the job's, then random ones within the bounds.
  std::vector<std::vector<double>> starts = {p.theta};
  RandomEngine rng(job.solver.seed);
  for (int s = 0; s < job.solver.starts; ++s) {
    std::vector<double> start = p.theta;
    for (int k = 0; k < n_free; ++k) {
      // Uniform in internal coordinates = log-uniform for positive ones.
      start[k] = UniformReal(p.lower[k], p.upper[k], rng);
    }
    starts.push_back(start);
  }
  // The stages a screen of this job ran (HorizonCheckpoint), checked to be
  // this job's.
  const HorizonCheckpoint* resume = job.solver.resume.get();
  if (resume != nullptr) {
    const std::string why =
        CheckpointMismatch(*resume, stages, starts, job.solver.threads, &p.theta);
    if (!why.empty()) {
      throw std::invalid_argument(
          "solver.resume: expected a checkpoint of this job, got one with " + why);
    }
  }

  FitResult result;
  result.num_residuals = num_residuals;
  double best_cost = std::numeric_limits<double>::infinity();
  std::vector<double> best = p.theta;
  std::vector<double> best_step(theta_size, 0.0);  // the last stage's step
  ceres::Solver::Summary best_summary;
  // Progress (common/progress.h): the starts' share done, each stage weighted
  // by its horizon (a stage's simulations are as long as its horizon).
  ProgressStream* status = job.solver.progress ? AsProgressStream(progress) : nullptr;
  if (status != nullptr) status->BeginPhase("starts");
  // Where each start is between its stages.
  struct StartRun {
    std::vector<double> theta;           // its current point
    // A stage whose warm start fails to evaluate (the previous, shorter
    // horizon left a parameter it barely sees at a value where the longer
    // simulation is hypersensitive, e.g. T_p at its lower bound) is retried
    // once from the point the previous stage started from.
    std::vector<double> previous_start;
    ceres::Solver::Summary summary;
    bool usable = true;
    // Stopped by solver.abandon_above_bic: the horizon (s) and the BIC's
    // lower bound there; 0 and +inf while it runs.
    double abandoned_horizon = 0.0;
    double bic_bound = std::numeric_limits<double>::infinity();
    // Joined the path of an earlier start (see `joined` below): its index
    // and the horizon (s); −1 and 0 otherwise.
    int joined = -1;
    double joined_horizon = 0.0;
    // The stage it stopped after (abandoned_horizon > 0), and the bounds of
    // the stages it ran while a solver.pending_level was not yet known:
    // (stage, bound).
    size_t abandoned_stage = 0;
    std::vector<std::pair<size_t, double>> waiting_bounds;
  };
  std::vector<StartRun> runs(starts.size());
  // For the progress: the starts that will run the last stage, and how many have.
  size_t finals_total = starts.size();
  size_t finals_done = 0;
  double abandon_above = job.solver.abandon_above_bic;
  // With solver.pending_level the level is another fit's, published while
  // this one runs (estimation/shared_level.h SharedLevel): until then every shorter
  // stage's bound is recorded (StartRun::waiting_bounds); once it is known
  // the start stops at the first recorded stage whose bound passed it (at
  // the next stage end, or at once inside a stage: PendingLevelStop), as
  // if the level had been known from the start. A start that ends its last
  // stage first waits for the level. One start only: the joins of several
  // would depend on when the level came.
  const SharedLevel* pending = job.solver.pending_level.get();
  if (pending != nullptr && job.solver.starts != 0) {
    throw std::invalid_argument(
        "FitParameters: expected solver.starts 0 with solver.pending_level, got " +
        std::to_string(job.solver.starts));
  }
  if (pending != nullptr && job.solver.stop_after_horizon > 0.0) {
    throw std::invalid_argument(
        "FitParameters: expected no solver.stop_after_horizon with solver.pending_level (a "
        "screen's stop would not wait for the level), got " +
        std::to_string(job.solver.stop_after_horizon) + " s");
  }
  bool level_known = pending == nullptr;
  // Takes the pending level if it is published (`wait`: waits for it).
  const auto refresh_level = [&](bool wait) {
    if (level_known) return;
    const std::optional<double> level =
        wait ? std::optional<double>(pending->AbandonAbove()) : pending->TryAbandonAbove();
    if (!level) return;
    level_known = true;
    abandon_above = std::min(abandon_above, *level);
  };
  // Stops `run` at the first recorded stage whose bound passed the level.
  const auto passed_recorded = [&](StartRun* run) {
    const std::pair<size_t, double>* passed = FirstPassed(run->waiting_bounds, abandon_above);
    if (passed == nullptr) return false;
    run->abandoned_horizon = stages[passed->first].horizon;
    run->bic_bound = passed->second;
    run->abandoned_stage = passed->first;
    return true;
  };
  // Runs stage i of start s (its point in p.theta on entry and exit).
  const auto run_stage = [&](size_t s, size_t i, StartRun* run) {
    Stage& stage = stages[i];
    const std::vector<double> stage_start = p.theta;
    if (status != nullptr) {
      // Done: the shorter stages of the starts before this one (all of
      // them once the finals run), then the finals before this one.
      const size_t n = stages.size();
      double shorter = 0.0;
      for (size_t j = 0; j + 1 < n; ++j) shorter += stages[j].horizon;
      double before = 0.0;
      if (i + 1 < n) {
        before = shorter * static_cast<double>(s);
        for (size_t j = 0; j < i; ++j) before += stages[j].horizon;
      } else {
        before = shorter * static_cast<double>(starts.size()) +
                 stages[i].horizon * static_cast<double>(finals_done);
      }
      const double total = shorter * static_cast<double>(starts.size()) +
                           stages[n - 1].horizon * static_cast<double>(finals_total);
      std::ostringstream what;
      what << "fit: start " << s + 1 << " of " << starts.size() << ", horizon "
           << std::fixed << std::setprecision(3) << stage.horizon << " s (stage " << i + 1
           << " of " << n << ")";
      status->Status(what.str(), before / total);
    }
    ProgressPrinter printer(job.solver.progress ? progress : nullptr, static_cast<int>(s),
                            stage.horizon);
    if (i > 0 && i + 1 == stages.size() && p.theta != starts[s]) {
      // The chain of shorter horizons may have led away from a start that
      // is better on the whole record (a warm refit starts next to the
      // nested model's optimum, while the short horizons can pull it into
      // a higher minimum: the load_offset case's cogging refit ended at BIC
      // 9.0e6 against the base fit's 2.45e6). The last stage starts from
      // the lower of the two. Only the last: on a shorter horizon the start
      // can be lower than a chain point that leads to the better minimum
      // (applied at every stage, the coulomb_load_offset case's Coulomb
      // refit lost its way and the loop ended with cogging and motor-side
      // Coulomb friction as stand-ins).
      const std::vector<double> chain = p.theta;
      const double chain_cost = CostAt(stage.problem.get(), chain, job.solver.threads, &p.theta);
      if (!(CostAt(stage.problem.get(), starts[s], job.solver.threads, &p.theta) < chain_cost)) {
        std::copy(chain.begin(), chain.end(), p.theta.begin());
      }
    }
    ceres::Solver::Options o = options;
    o.callbacks.push_back(&printer);
    PendingLevelStop level_stop(pending, job.solver.abandon_above_bic, &run->waiting_bounds);
    if (!level_known && !run->waiting_bounds.empty()) o.callbacks.push_back(&level_stop);
    if (i + 1 < stages.size()) {
      // Intermediate horizons only deliver a warm start for the next.
      o.function_tolerance = std::max(o.function_tolerance, kStageParameterTolerance);
      o.parameter_tolerance = std::max(o.parameter_tolerance, kStageParameterTolerance);
      o.max_num_iterations = std::min(o.max_num_iterations, 30);
    }
    ceres::Solve(o, stage.problem.get(), &run->summary);
    if (!run->summary.IsSolutionUsable() && i > 0 && run->previous_start != stage_start) {
      ReportStageFailure(job, *p.map, p.theta, s, stage.horizon, run->summary.message,
                         "retrying from the previous stage's start", progress);
      std::copy(run->previous_start.begin(), run->previous_start.end(), p.theta.begin());
      ceres::Solve(o, stage.problem.get(), &run->summary);
    }
    if (!run->summary.IsSolutionUsable()) {
      ReportStageFailure(job, *p.map, p.theta, s, stage.horizon, run->summary.message,
                         "start abandoned", progress);
      run->usable = false;
      return;
    }
    run->previous_start = stage_start;
  };
  // The shorter horizons for every start first; then the whole record from
  // the solver.finalists starts lowest on the longest shorter horizon (on
  // the load_offset case the ranking after 1.6 of 2 s was the final one:
  // the last stage changed each cost by < 1 %, while the costs of the
  // starts differed by 50 % and more). Without shorter stages every start
  // is a finalist.
  const size_t last = stages.size() - 1;
  // A start that can no longer end below solver.abandon_above_bic stops.
  // A stage sums the same σ-weighted residuals as the whole record over a
  // prefix of every experiment, so at any θ its cost is at most the whole
  // record's, and 2·(the stage's minimum) + n·ln(m) bounds the BIC the start
  // can end with from below. The stage's minimum is taken as the lower of its
  // end point and the start itself (the last stage may go back to the
  // start); a local minimum makes this a heuristic bound, checked on the
  // discovery cases (tests/discovery_test.cc) and campaigns (README).
  const double bic_penalty = theta_size * std::log(static_cast<double>(num_residuals));
  // With solver.stop_after_horizon every start also stops, with its bound,
  // after the stage of that horizon (a screen of the refits: discovery/discovery.cc).
  const double stop_after = job.solver.stop_after_horizon;
  // The stage's cost at start s's own point (the stage's minimum is the
  // lower of it and the end point): from the checkpoint for a stage it holds.
  std::shared_ptr<HorizonCheckpoint> checkpoint;  // the screen's record, below
  const auto cost_at_start = [&](size_t s, size_t i) {
    if (resume != nullptr && i < resume->starts[s].stages.size()) {
      return resume->starts[s].stages[i].start_cost;
    }
    if (checkpoint != nullptr && i < checkpoint->starts[s].stages.size()) {
      return checkpoint->starts[s].stages[i].start_cost;
    }
    const std::vector<double> end = p.theta;
    const double at_start =
        CostAt(stages[i].problem.get(), starts[s], job.solver.threads, &p.theta);
    std::copy(end.begin(), end.end(), p.theta.begin());
    return at_start;
  };
  const auto passed_bound = [&](size_t s, size_t i, StartRun* run) {
    if (!run->usable) return false;
    refresh_level(false);
    if (level_known && passed_recorded(run)) return true;
    const bool screen_end = stop_after > 0.0 && stages[i].horizon >= stop_after * (1.0 - 1e-9);
    if (!screen_end && level_known &&
        !(abandon_above < std::numeric_limits<double>::infinity())) {
      return false;
    }
    const double bound =
        2.0 * std::min(run->summary.final_cost, cost_at_start(s, i)) + bic_penalty;
    if (!level_known && !screen_end) {
      run->waiting_bounds.emplace_back(i, bound);
      return false;
    }
    if (!screen_end && !(bound > abandon_above)) return false;
    run->abandoned_horizon = stages[i].horizon;
    run->bic_bound = bound;
    run->abandoned_stage = i;
    return true;
  };
  // A start whose point after a stage lies within that stage's parameter
  // tolerance of an earlier start's point after the same stage has joined
  // that start's path (the solver cannot tell the two points apart; seen on
  // the discovery cases, where most random starts meet the job's start
  // after the first or second horizon): it stops there, and only the
  // earlier start goes on. ends[s][i]: start s's point after stage i.
  std::vector<std::vector<std::vector<double>>> ends(starts.size());
  const auto joined = [&](size_t s, size_t i, StartRun* run) {
    const double tol = std::max(options.parameter_tolerance, kStageParameterTolerance);
    for (size_t j = 0; j < s; ++j) {
      if (runs[j].joined >= 0 || ends[j].size() <= i) continue;
      bool same = true;
      for (size_t k = 0; k < p.theta.size() && same; ++k) {
        same = std::abs(p.theta[k] - ends[j][i][k]) <= tol * (1.0 + std::abs(ends[j][i][k]));
      }
      if (same) {
        run->joined = static_cast<int>(j);
        run->joined_horizon = stages[i].horizon;
        return true;
      }
    }
    return false;
  };
  // The screen (solver.stop_after_horizon) records every start's stages
  // for the fit that goes on after them (solver.resume), which takes each
  // stage the checkpoint holds as run: its end point, cost and start cost,
  // the point it started from (the previous stage's end) kept for the retry
  // as run_stage keeps it. The same decisions follow (joined, passed_bound)
  // as if the stages had run again.
  if (stop_after > 0.0) {
    checkpoint = std::make_shared<HorizonCheckpoint>();
    for (size_t i = 0; i < last; ++i) checkpoint->horizons.push_back(stages[i].horizon);
    checkpoint->starts.resize(starts.size());
    for (size_t s = 0; s < starts.size(); ++s) checkpoint->starts[s].point = starts[s];
  }
  {
    PhaseTimer timer("starts", p.counter, &result);
    for (size_t s = 0; s < starts.size(); ++s) {
      StartRun& run = runs[s];
      std::copy(starts[s].begin(), starts[s].end(), p.theta.begin());
      run.previous_start = p.theta;
      for (size_t i = 0; i < last && run.usable; ++i) {
        if (resume != nullptr && i < resume->starts[s].stages.size()) {
          const HorizonCheckpoint::StageEnd& done = resume->starts[s].stages[i];
          run.previous_start = p.theta;
          std::copy(done.theta.begin(), done.theta.end(), p.theta.begin());
          run.summary.final_cost = done.cost;
          run.usable = done.usable;
          if (checkpoint != nullptr) checkpoint->starts[s].stages.push_back(done);
        } else {
          run_stage(s, i, &run);
          if (checkpoint != nullptr) {
            HorizonCheckpoint::StageEnd done;
            done.theta = p.theta;
            done.cost = run.summary.final_cost;
            done.usable = run.usable;
            if (run.usable) done.start_cost = cost_at_start(s, i);
            checkpoint->starts[s].stages.push_back(std::move(done));
          }
        }
        if (!run.usable) break;
        ends[s].push_back(p.theta);
        if (joined(s, i, &run) || passed_bound(s, i, &run)) break;
      }
      run.theta = run.abandoned_horizon > 0.0 ? ends[s][run.abandoned_stage] : p.theta;
      if (s == 0) {
        // The cost of the job's initial point on all the data.
        result.initial_cost = CostAt(&full_problem, starts[0], job.solver.threads, &p.theta);
        std::copy(run.theta.begin(), run.theta.end(), p.theta.begin());
      }
    }
    result.checkpoint = checkpoint;
  }
  std::vector<size_t> order;
  size_t abandoned = starts.size();  // the stopped start with the lowest bound
  result.start_joined.assign(starts.size(), -1);
  result.start_joined_horizon.assign(starts.size(), 0.0);
  for (size_t s = 0; s < starts.size(); ++s) {
    if (runs[s].joined >= 0) {
      result.start_joined[s] = runs[s].joined;
      result.start_joined_horizon[s] = runs[s].joined_horizon;
    } else if (runs[s].abandoned_horizon > 0.0) {
      if (abandoned == starts.size() || runs[s].bic_bound < runs[abandoned].bic_bound) {
        abandoned = s;
      }
    } else if (runs[s].usable) {
      order.push_back(s);
    }
  }
  // The result of a fit whose every start stopped: the lowest bound's.
  const auto stopped_result = [&](const StartRun& run) {
    // As before the finals (a start stopped after them under a pending
    // level ran a final stage that does not count).
    result.start_costs.clear();
    result.start_screen_costs.clear();
    result.screen_horizon = 0.0;
    result.abandoned_horizon = run.abandoned_horizon;
    result.bic = run.bic_bound;
    result.final_cost = result.aic = result.residual_variance = result.residual_dof =
        std::numeric_limits<double>::quiet_NaN();
    std::ostringstream why;
    why << "stopped at the " << run.abandoned_horizon << " s horizon: BIC >= "
        << run.bic_bound;
    if (run.bic_bound > abandon_above) why << ", above " << abandon_above;
    result.termination = why.str();
    AppendEstimates(job, *p.map, run.theta, &result);
    result.simulations = p.counter.simulations;
    result.jacobian_evaluations = p.counter.jacobians;
    return result;
  };
  if (order.empty() && abandoned < starts.size()) return stopped_result(runs[abandoned]);
  if (last > 0) {
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return runs[a].summary.final_cost < runs[b].summary.final_cost;
    });
    if (order.size() > static_cast<size_t>(job.solver.finalists)) {
      order.resize(static_cast<size_t>(job.solver.finalists));
    }
    result.screen_horizon = stages[last - 1].horizon;
  }
  result.start_costs.assign(starts.size(), std::numeric_limits<double>::quiet_NaN());
  result.start_screen_costs.assign(starts.size(), std::numeric_limits<double>::quiet_NaN());
  for (size_t s = 0; s < starts.size(); ++s) {
    if (!runs[s].usable) result.start_costs[s] = std::numeric_limits<double>::infinity();
    if (last > 0 && runs[s].usable && runs[s].abandoned_horizon == 0.0 && runs[s].joined < 0) {
      result.start_screen_costs[s] = runs[s].summary.final_cost;
    }
  }
  // The finals from the lowest cost on the screen horizon up. A finalist
  // whose cost there (the lower of its end point and its start, as for
  // solver.abandon_above_bic above) is already above the best final cost
  // cannot end below it and does not run (its start_costs entry stays NaN).
  finals_total = order.size();
  for (size_t s : order) {
    PhaseTimer timer("starts", p.counter, &result);
    StartRun& run = runs[s];
    if (last > 0 && std::isfinite(best_cost)) {
      const double at_start = cost_at_start(s, last - 1);
      if (std::min(run.summary.final_cost, at_start) > best_cost) {
        --finals_total;
        continue;
      }
    }
    std::copy(run.theta.begin(), run.theta.end(), p.theta.begin());
    run_stage(s, last, &run);
    ++finals_done;
    const double cost =
        run.usable ? run.summary.final_cost : std::numeric_limits<double>::infinity();
    result.start_costs[s] = cost;
    if (cost < best_cost) {
      best_cost = cost;
      best = p.theta;
      best_summary = run.summary;
      for (int k = 0; k < theta_size; ++k) best_step[k] = p.theta[k] - run.previous_start[k];
    }
  }
  // solver.pending_level (one start): a start that ran to the end before
  // the level came stops where the level says, as if it had been known.
  if (pending != nullptr && !runs[0].waiting_bounds.empty()) {
    refresh_level(true);
    if (passed_recorded(&runs[0])) {
      runs[0].theta = ends[0][runs[0].abandoned_stage];
      return stopped_result(runs[0]);
    }
  }
  std::copy(best.begin(), best.end(), p.theta.begin());

  // The job's start alone ended far above the noise: more likely a wrong
  // minimum of the output error than the model's own misfit (on unseen
  // data, e.g. a wrist axis fitted from the X axis's values, the
  // continuation from the job's start ended at s² = 575 and the optimum
  // check then ground through 13 probe rounds to s² = 575 still; 8 random
  // starts reached s² = 1.0 in a third of the time). Fit again with
  // solver.auto_starts random starts (the job's start among them, so the
  // result is never worse); its starts phase includes this one's.
  const int dof = std::max(1, num_residuals - theta_size);
  const double s2 = 2.0 * best_cost / dof;  // the job's start's
  if (job.solver.auto_starts > 0 && job.solver.starts == 0 && !job.discover.enabled &&
      pending == nullptr && resume == nullptr && stop_after == 0.0 &&
      !(abandon_above < std::numeric_limits<double>::infinity()) && std::isfinite(best_cost) &&
      s2 > kAutoStartsAbove) {
    if (progress != nullptr) {
      *progress << "s^2 = " << FormatNumber(s2, 4) << " after the job's start (above " << kAutoStartsAbove
                << "): fitting again with " << job.solver.auto_starts
                << " random starts (solver.auto_starts)\n";
    }
    FitJob again = job;
    again.solver.starts = job.solver.auto_starts;
    again.solver.auto_starts = 0;
    // Every start fits the whole record: the screen horizon's ranking is
    // what failed here when its cost was at the noise while the whole
    // record's is far above it (a +6 V step whose preamp leaves its limit
    // after 0.8 s of 1.5: every start's screen cost 743–775, T_p unseen
    // there; ranked, the two finalists ended at s² = 96, while with all
    // nine one random start reached s² = 1.0).
    again.solver.finalists = std::max(job.solver.finalists, again.solver.starts + 1);
    FitResult wider = FitAndKeepLevel(again, progress);
    for (const FitPhase& f : result.phases) AddPhase(f, &wider);
    wider.simulations += p.counter.simulations;
    wider.jacobian_evaluations += p.counter.jacobians;
    std::ostringstream note;
    note << "the job's start ended the continuation at s^2 = " << FormatNumber(s2, 4)
         << " (above " << kAutoStartsAbove << "), so " << job.solver.auto_starts
         << " random starts were added (solver.auto_starts)";
    // The start that ended lowest on the whole record (NaN: not a finalist).
    size_t winner = wider.start_costs.size();
    for (size_t s = 0; s < wider.start_costs.size(); ++s) {
      if (std::isfinite(wider.start_costs[s]) &&
          (winner == wider.start_costs.size() ||
           wider.start_costs[s] < wider.start_costs[winner])) {
        winner = s;
      }
    }
    if (winner < wider.start_costs.size()) {
      note << "; " << (winner == 0 ? "the job's start" : "random start " + std::to_string(winner))
           << " ended lowest";
    }
    wider.auto_starts_note = note.str();
    return wider;
  }

  // Optimum check. The cost of the model as specified is piecewise smooth:
  // besides the contacts themselves (handled exactly, sim/switched_rk4.h), a
  // contact that is only just made or missed (a ringing gear grazing the
  // edge of the backlash, a velocity reversal that barely happens) changes
  // the number of events, which puts kinks into the cost, and a kink can
  // wall off a local minimum next to a lower one. Gauss–Newton cannot see
  // past it; probing can. Each round probes around the estimate and restarts
  // the final stage from the lowest point found, until a round finds nothing
  // lower (LowerThan: by more than the solver's relative tolerance) or the
  // rounds run out.
  int probes = 0;
  const double entry_cost = best_cost;
  // With discovery on, the declared model is the one expected to miss an
  // effect: its fit (and the loop's refits, which skip the check) gets one
  // probe round, no local restarts and no likelihood-ratio scan, each of
  // which costs a few hundred simulations, and reports Gauss–Newton
  // intervals.
  const bool discovering = job.discover.enabled;
  // The cost a point must be below to count as lower than the estimate now.
  const auto lower_than_estimate = [&] {
    return LowerThan(best_cost, job.solver.function_tolerance);
  };
  const int probe_rounds =
      discovering ? std::min(job.solver.probe_rounds, 1) : job.solver.probe_rounds;
  // Restarts the final stage from `point` (cost `point_cost`) and keeps the
  // solver's end if it is no worse, else the point itself.
  auto restart_from = [&](const std::vector<double>& point, double point_cost) {
    const std::vector<double> from = best;
    std::copy(point.begin(), point.end(), p.theta.begin());
    ceres::Solver::Summary summary;
    ceres::Solve(options, stages.back().problem.get(), &summary);
    if (summary.IsSolutionUsable() && summary.final_cost <= point_cost) {
      best_cost = summary.final_cost;
      best_summary = summary;
    } else {
      std::copy(point.begin(), point.end(), p.theta.begin());
      best_cost = point_cost;
    }
    best = p.theta;
    for (int k = 0; k < theta_size; ++k) best_step[k] = best[k] - from[k];
  };
  // Runs the probe rounds from the current best point (see above); fills
  // result.optimum_*.
  auto check_optimum = [&]() {
    if (std::isfinite(best_cost) && probe_rounds > 0) {
      PhaseTimer timer("optimum check", p.counter, &result);
      ceres::Problem& last = *stages.back().problem;
      if (status != nullptr) status->BeginPhase("optimum check");
      for (int round = 0;; ++round) {
        if (status != nullptr) {
          status->Status("fit: optimum check, probe round " + std::to_string(round + 1) +
                             " (at most " + std::to_string(probe_rounds) + ")",
                         std::numeric_limits<double>::quiet_NaN());
        }
        std::vector<double> lowest;
        double lowest_cost = best_cost;
        ProbeRound(&last, p.lower, p.upper, best_step, best_cost, &p.counter,
                   job.solver.threads, &p.theta, &lowest, &lowest_cost, &probes);
        ++result.probe_rounds;
        if (!(lowest_cost < lower_than_estimate())) {
          result.optimum_verified = true;
          break;
        }
        if (round + 1 >= probe_rounds) {
          std::copy(lowest.begin(), lowest.end(), p.theta.begin());
          best_cost = lowest_cost;
          break;
        }
        restart_from(lowest, lowest_cost);
        if (job.solver.progress && progress != nullptr) {
          *progress << "optimum check round " << round + 1 << ": probe found a "
                    << "lower cost, solver restarted: cost " << best_cost << "\n";
        }
      }
      result.probe_decrease = entry_cost - best_cost;
      std::ostringstream note;
      note << (result.optimum_verified ? "optimum verified: " : "optimum NOT verified: ")
           << probes << " probes in " << result.probe_rounds << " round(s) at ±{0.01, 0.3, 1, 3, 10} "
           << "standard deviations along every parameter, principal axis and the last step";
      if (result.optimum_verified) {
        note << " found no lower cost";
      } else {
        note << " still found a lower cost after " << probe_rounds << " round(s)";
      }
      if (result.probe_decrease > 0.0) {
        note << "; the checks lowered the cost by " << result.probe_decrease << " in all";
      }
      result.optimum_check = note.str();
    } else {
      result.optimum_check = std::isfinite(best_cost) ? "optimum not checked (solver.probe_rounds: 0)"
                                                     : "optimum not checked (no start converged)";
    }
  };
  check_optimum();
  // Covariance of θ (Gauss–Newton, DENSE_SVD) and, for the likelihood-ratio
  // method, the scan of the cost along the profile directions; a scan that
  // meets a lower cost restarts the solver there and checks the optimum again.
  const double t975 = StudentTQuantile975(dof);
  const bool ratio_method =
      job.uncertainty.method == UncertaintySettings::Method::kLikelihoodRatio &&
      !discovering;
  const bool profile_method =
      job.uncertainty.method == UncertaintySettings::Method::kProfile && !discovering;
  // The scan also belongs to the optimum check (a lower point restarts the
  // solver), so it runs with the check whatever the interval method; the
  // profile's refits take its place (they meet any lower point it would).
  const bool run_scan = (ratio_method || probe_rounds > 0) && !discovering && !profile_method;
  const double local_starts = discovering ? 0.0 : job.solver.local_starts;
  static const std::vector<double> kRatioSteps = {0.5, 1, 1.5, 2, 3, 4, 6, 8, 12, 16};
  constexpr int kRatioPasses = 3;
  Eigen::MatrixXd cov_theta;
  RatioScan scan;
  ProfileScan profile;
  // JᵀJ of the last covariance and the point it was evaluated at: the null
  // space below reuses it if the estimate has not moved since (one
  // Jacobian of the whole record less).
  Eigen::MatrixXd jtj_at;
  std::vector<double> jtj_point;
  int ratio_restarts = 0;
  constexpr int kLocalPasses = 3;
  int local_passes = 0;
  for (;;) {
    result.residual_variance = 2.0 * best_cost / dof;
    result.residual_dof = dof;
    std::optional<PhaseTimer> timer(std::in_place, "covariance", p.counter, &result);
    cov_theta = std::isfinite(best_cost)
                    ? CovarianceOfTheta(&full_problem, theta, theta_size, job.solver.threads,
                                        &jtj_at)
                    : Eigen::MatrixXd::Constant(theta_size, theta_size,
                                                std::numeric_limits<double>::quiet_NaN());
    jtj_point = p.theta;
    timer.reset();
    if (!std::isfinite(best_cost)) break;
    // Local restarts: Levenberg–Marquardt from θ* ± local_starts standard
    // deviations along every principal axis of the covariance. The probes
    // above only evaluate the cost; a restart follows it downhill past the
    // kinks that wall off the estimate, and finds minima that are lower but
    // not on a probe line (on PRBS records the estimate otherwise stays on
    // the side of the start it came from).
    if (local_starts > 0.0 && probe_rounds > 0 &&
        local_passes < kLocalPasses && cov_theta.allFinite()) {
      timer.emplace("local restarts", p.counter, &result);
      ++local_passes;
      const std::vector<double> centre = best;
      std::vector<double> lowest_point;
      double lowest = best_cost;
      // The restarts begin 3 standard deviations from a minimum the
      // covariance describes: Ceres' default trust region (nearly
      // Gauss–Newton steps) instead of the job's damped start, which is
      // for starts far from the data (3 iterations instead of 8–9 on the
      // paper job, the same estimate).
      ceres::Solver::Options o = near_options;
      o.max_num_iterations = std::min(o.max_num_iterations, 50);
      o.initial_trust_region_radius = 1e4;
      AbsoluteDecreaseStop stop(kLowerAbsolute);
      o.callbacks.push_back(&stop);
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov_theta *
                                                         result.residual_variance);
      if (status != nullptr) status->BeginPhase("local restarts");
      for (int e = 0; e < theta_size; ++e) {
        const double l = eig.eigenvalues()[e];
        if (!(l > 0.0)) continue;
        for (double sign : {-1.0, 1.0}) {
          if (status != nullptr) {
            const int index = 2 * e + (sign > 0.0 ? 1 : 0);
            status->Status("fit: local restart " + std::to_string(index + 1) + " of " +
                               std::to_string(2 * theta_size) + " (pass " +
                               std::to_string(local_passes) + ")",
                           index / (2.0 * theta_size));
          }
          for (int k = 0; k < theta_size; ++k) {
            p.theta[k] = std::clamp(centre[k] + sign * local_starts *
                                                    std::sqrt(l) * eig.eigenvectors()(k, e),
                                    p.lower[k], p.upper[k]);
          }
          ceres::Solver::Summary summary;
          ceres::Solve(o, stages.back().problem.get(), &summary);
          ++result.local_starts;
          if (summary.IsSolutionUsable() && summary.final_cost < lowest) {
            lowest = summary.final_cost;
            lowest_point = p.theta;
          }
        }
      }
      std::copy(centre.begin(), centre.end(), p.theta.begin());
      timer.reset();
      if (lowest < lower_than_estimate()) {
        result.local_decrease += best_cost - lowest;
        restart_from(lowest_point, lowest);
        if (job.solver.progress && progress != nullptr) {
          *progress << "local restart found a lower cost: " << best_cost << "\n";
        }
        result.optimum_verified = false;
        check_optimum();
        continue;
      }
    }
    const double lower_than_best = lower_than_estimate();
    // The profile's refits or the line scan; either may meet a lower cost,
    // which restarts the solver there (at most kRatioPasses − 1 times).
    const bool may_restart = probe_rounds > 0 && ratio_restarts + 1 < kRatioPasses;
    double met_cost = 0.0;
    const std::vector<double>* met_point = nullptr;
    if (profile_method || run_scan) timer.emplace("intervals", p.counter, &result);
    if (profile_method) {
      // Profile refits: warm-started next to the profile, so Ceres' default
      // trust region (nearly Gauss–Newton steps) and a stop once a step
      // changes the cost by less than 1 % of the threshold (the profile's
      // ends are located to 5 % of it). The stop is Ceres' function
      // tolerance, relative to the cost: threshold/cost* = t²/dof (s² =
      // 2·cost*/dof) at any noise level, and a refit's cost is cost* plus a
      // few thresholds. Ceres tests it before it evaluates the Jacobian at
      // the accepted point (trust_region_minimizer.cc,
      // FunctionToleranceReached before HandleSuccessfulStep) and keeps the
      // point before that step, at most 1 % of the threshold higher: a
      // refit ending after one step costs one Jacobian instead of two (a
      // callback sees the iteration only after that Jacobian). The test
      // comes before the step is judged, so a rejected step that changes
      // the cost by less than that also ends the refit (before, LM shrank
      // its radius and went on). The callback stays for refits below cost*,
      // where the relative tolerance is slightly smaller. The paper job:
      // intervals 10.4 → 6.9 s (322 → 206 Jacobians), every end within
      // 0.4 % of its half-width of the callback's (issue 11).
      const double threshold = 0.5 * t975 * t975 * result.residual_variance;
      ceres::Solver::Options o = near_options;
      o.max_num_iterations = std::min(o.max_num_iterations, 50);
      o.initial_trust_region_radius = 1e4;
      o.function_tolerance = std::max(o.function_tolerance, 0.01 * t975 * t975 / dof);
      AbsoluteDecreaseStop stop(0.01 * threshold);
      o.callbacks.push_back(&stop);
      ProgressPrinter printer(status, 0, longest, false);
      if (status != nullptr) {
        o.callbacks.push_back(&printer);
        status->BeginPhase("profile intervals");
      }
      const auto on_parameter = [&](int k) {
        if (status == nullptr) return;
        status->Status("fit: profile-likelihood interval of " + job.free[k].name + " (" +
                           std::to_string(k + 1) + " of " + std::to_string(n_free) + ")",
                       static_cast<double>(k) / n_free);
      };
      profile = ProfileLikelihoodIntervals(&full_problem, o, p.lower, p.upper,
                                           cov_theta * result.residual_variance, n_free, t975,
                                           result.residual_variance, lower_than_best,
                                           may_restart, &p.theta, on_parameter);
      met_cost = profile.lowest_cost;
      met_point = &profile.lowest_point;
    } else if (run_scan) {
      if (status != nullptr) {
        status->BeginPhase("likelihood-ratio scan");
        status->Status("fit: likelihood-ratio scan of the intervals",
                       std::numeric_limits<double>::quiet_NaN());
      }
      scan = LikelihoodRatioIntervals(&full_problem, p.lower, p.upper,
                                      cov_theta * result.residual_variance, n_free, t975,
                                      result.residual_variance, kRatioSteps,
                                      job.solver.threads, &p.theta);
      met_cost = scan.lowest_cost;
      met_point = &scan.lowest_point;
    } else {
      break;
    }
    timer.reset();
    if (met_cost < lower_than_best && may_restart) {
      ++ratio_restarts;
      restart_from(*met_point, met_cost);
      if (job.solver.progress && progress != nullptr) {
        *progress << (profile_method ? "profile likelihood" : "likelihood-ratio scan")
                  << " met a lower cost, solver restarted: cost " << best_cost << "\n";
      }
      result.optimum_verified = false;
      check_optimum();
      continue;
    }
    break;
  }
  if (result.local_starts > 0) {
    std::ostringstream note;
    note << "; " << result.local_starts << " local restarts from ±" << job.solver.local_starts
         << " standard deviations along the principal axes";
    if (result.local_decrease > 0.0) {
      note << " lowered the cost by " << result.local_decrease;
    } else {
      note << " found no lower minimum";
    }
    result.optimum_check += note.str();
  }
  result.final_cost = best_cost;
  result.converged = best_summary.termination_type == ceres::CONVERGENCE;
  result.termination = best_summary.message;
  result.stop_note = QuantisedFeedbackStopNote(job, best_summary);
  result.integration = IntegrationNote(job);
  result.iterations = static_cast<int>(best_summary.iterations.size()) - 1;

  // To physical units: value_k = g(θ_k), so Cov = D·Cov_θ·D·s² (the
  // Gauss–Newton covariance; likelihood-ratio intervals replace the
  // intervals below, not this matrix).
  Eigen::MatrixXd cov = cov_theta.topLeftCorner(n_free, n_free);
  for (int i = 0; i < n_free; ++i) {
    for (int j = 0; j < n_free; ++j) {
      cov(i, j) *= p.map->Derivative(i, p.theta[i]) * p.map->Derivative(j, p.theta[j]) *
                   result.residual_variance;
    }
  }
  result.uncertainty_method = "gauss_newton";
  result.uncertainty_note = "covariance (JᵀJ)⁻¹ at the estimate (Gauss–Newton), "
                            "scaled by the residual variance";
  result.correlation = Eigen::MatrixXd::Identity(n_free, n_free);
  std::vector<bool> determined(n_free, true);
  if (std::isfinite(best_cost)) {
    PhaseTimer timer("covariance", p.counter, &result);
    const std::vector<bool> null =
        jtj_point == p.theta && jtj_at.rows() == theta_size
            ? NullSpaceMembersOf(jtj_at.topLeftCorner(n_free, n_free), n_free)
            : NullSpaceMembers(&full_problem, n_free);
    for (int i = 0; i < n_free; ++i) determined[i] = !null[i];
  }
  // Both members of a nearly collinear pair are undetermined: the pairs are
  // judged on the null-space flags alone (`outside_null`), so flagging one member
  // does not spare the other when the loop reaches it.
  const std::vector<bool> outside_null = determined;
  for (int i = 0; i < n_free; ++i) {
    for (int j = 0; j < n_free; ++j) {
      if (i == j) continue;
      const double r = cov(i, j) / std::sqrt(cov(i, i) * cov(j, j));
      result.correlation(i, j) = r;
      if (outside_null[i] && outside_null[j] && std::abs(r) > 0.99) determined[i] = false;
    }
  }
  // Likelihood-ratio intervals (estimation/uncertainty.h): the cost itself along
  // the profile directions, which JᵀJ describes only near a smooth minimum.
  const std::vector<RatioInterval> ratio =
      ratio_method     ? scan.intervals
      : profile_method ? profile.intervals
                       : std::vector<RatioInterval>();
  if (!ratio_method && ratio_restarts > 0) {
    result.optimum_check += "; the likelihood-ratio scan met a lower cost and restarted the "
                            "solver " + std::to_string(ratio_restarts) + " time(s)";
  }
  // The report's note on intervals that follow the cost (profile or line
  // scan): how they were found, the sides that never rose past the
  // threshold, and a lower cost the last pass still met.
  if ((profile_method || ratio_method) && std::isfinite(best_cost)) {
    const char* what = profile_method ? "profile" : "scan";
    const double lowest = profile_method ? profile.lowest_cost : scan.lowest_cost;
    std::ostringstream note;
    if (ratio.empty()) {
      note << (profile_method ? "profile likelihood" : "likelihood_ratio")
           << " failed (the covariance is not finite or the cost cannot be evaluated); "
           << result.uncertainty_note;
    } else {
      if (profile_method) {
        result.uncertainty_method = "profile";
        note << "profile-likelihood intervals: each end where the cost minimised over the "
             << "other parameters has risen by ½t²s² (" << profile.solves << " refits, "
             << profile.iterations << " iterations); std error = half-width / t";
      } else {
        result.uncertainty_method = "likelihood_ratio";
        note << "likelihood-ratio intervals: the cost probed along each parameter's "
             << "profile direction at ±{0.5 … 16} Gauss–Newton standard deviations ("
             << scan.evaluations << " evaluations); each end where the cost has risen by "
             << "½t²s²; std error = half-width / t";
      }
      if (ratio_restarts > 0) {
        note << "; the " << what << " met a lower cost and restarted the solver "
             << ratio_restarts << " time(s)";
      }
      std::vector<std::string> open;
      for (int k = 0; k < n_free; ++k) {
        if (!ratio[k].bounded_low) open.push_back(job.free[k].name + " (low)");
        if (!ratio[k].bounded_high) open.push_back(job.free[k].name + " (high)");
      }
      for (size_t i = 0; i < open.size(); ++i) {
        note << (i == 0 ? "; not bounded within 16 standard deviations or the bounds: " : ", ")
             << open[i];
      }
      if (lowest < lower_than_estimate()) {
        result.optimum_verified = false;
        note << "; the last " << what << " still met a cost lower by " << best_cost - lowest;
      }
    }
    result.uncertainty_note = note.str();
  }
  AxisParams<double> fitted = p.map->Apply(p.theta.data());
  for (int k = 0; k < n_free; ++k) {
    ParameterEstimate e;
    e.name = job.free[k].name;
    e.unit = job.free[k].unit;
    e.value = p.map->FromInternal(k, p.theta[k]);
    e.initial = job.free[k].initial;
    e.free = true;
    e.std_error = std::sqrt(cov(k, k));
    e.std_error_gauss_newton = std::sqrt(cov(k, k));
    e.std_error_bootstrap = e.bootstrap_low = e.bootstrap_high =
        std::numeric_limits<double>::quiet_NaN();
    e.ci95_low = e.value - t975 * e.std_error;
    e.ci95_high = e.value + t975 * e.std_error;
    if (!ratio.empty()) {
      e.ci95_low = p.map->FromInternal(k, ratio[k].low);
      e.ci95_high = p.map->FromInternal(k, ratio[k].high);
      e.std_error = (e.ci95_high - e.ci95_low) / (2.0 * t975);
    }
    e.determined = determined[k] && std::isfinite(e.std_error);
    if (!e.determined) result.undetermined.push_back(e.name);
    result.free_names.push_back(e.name);
    result.parameters.push_back(e);
  }
  AppendFixedEstimates(fitted, &result);

  // Every fitted entry of θ counts: the free parameters and the estimated
  // initial states.
  const int n = theta_size;
  result.aic = 2.0 * best_cost + 2.0 * n;
  result.bic = 2.0 * best_cost + n * std::log(static_cast<double>(num_residuals));

  {
  PhaseTimer timer("evaluation", p.counter, &result);
  for (size_t j = 0; j < job.experiments.size(); ++j) {
    FitExperiment e = job.experiments[j];
    if (state_index[j] >= 0) {
      SetArmState({p.theta[state_index[j]], p.theta[state_index[j] + 1]}, fitted.r_g, &e);
    }
    result.initial_states.push_back({e.initial_state[0], e.initial_state[1]});
    result.experiments.push_back(
        EvaluateExperiment(job.model.structure, fitted, e));
  }
  for (const FitExperiment& e : job.validate) {
    result.experiments.push_back(
        EvaluateExperiment(job.model.structure, fitted, e));
  }
  }
  result.model_note = QuasiSteadyDelayNote(job, result);
  result.residual_note = ResidualNote(result.residual_variance);
  result.simulations = p.counter.simulations;
  result.jacobian_evaluations = p.counter.jacobians;
  return result;
}

}  // namespace

double CostResolution(double cost, double function_tolerance) {
  return std::max(kLowerRelative, function_tolerance) * std::abs(cost) + kLowerAbsolute;
}

FitResult FitParameters(const FitJob& job, std::ostream* progress) {
  SharedLevel* publish = job.solver.publish_level.get();
  if (publish == nullptr) return FitAndKeepLevel(job, progress);
  // The fits waiting for this level must get one whatever happens here.
  try {
    FitResult result = FitAndKeepLevel(job, progress);
    publish->Publish(result.abandoned_horizon == 0.0 && std::isfinite(result.bic)
                         ? result.bic
                         : std::numeric_limits<double>::infinity());
    return result;
  } catch (...) {
    publish->Publish(std::numeric_limits<double>::infinity());
    throw;
  }
}

void AsWarmRefit(FitJob* job) {
  job->solver.starts = 0;
  job->solver.auto_starts = 0;
  job->solver.probe_rounds = 0;
  job->solver.first_horizon = 0.0;
  job->uncertainty.method = UncertaintySettings::Method::kGaussNewton;
}

std::vector<FitResult> FitConcurrently(const std::vector<FitJob>& jobs, int threads,
                                       std::vector<double>* seconds) {
  const size_t n = jobs.size();
  std::vector<FitResult> out(n);
  std::vector<double> wall(n, 0.0);
  const int at_once = static_cast<int>(std::min<size_t>(std::max(1, threads), std::max<size_t>(1, n)));
  const int inner = std::max(1, std::max(1, threads) / at_once);
  ForEachConcurrently(n, at_once, [&](size_t k) {
    const auto start = std::chrono::steady_clock::now();
    FitJob job = jobs[k];
    job.solver.threads = inner;
    out[k] = FitParameters(job, nullptr);
    wall[k] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  });
  if (seconds != nullptr) *seconds = wall;
  return out;
}

}  // namespace axis
