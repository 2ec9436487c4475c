// One fit of a job as a sequence of named steps, its state in members (as
// Ceres's TrustRegionMinimizer): the problem and its horizon stages, the
// starts over the shorter horizons, the finalists on the whole record, the
// automatic random starts, the optimum check, the covariance with the local
// restarts and the intervals, and the result with its notes. FitParameters
// (estimation/fit.h) is the public entry; this class is internal to
// estimation/. What each step does and why: estimation/fit.h FitParameters,
// estimation/solver_settings.h SolverSettings, estimation/fit_control.h.
#ifndef ESTIMATION_INTERNAL_FITTER_H_
#define ESTIMATION_INTERNAL_FITTER_H_

#include <limits>
#include <memory>
#include <ostream>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <ceres/ceres.h>

#include "common/progress.h"
#include "estimation/fit_control.h"
#include "estimation/internal/fit_problem.h"
#include "estimation/fit_result.h"
#include "estimation/horizon_checkpoint.h"
#include "estimation/internal/rough_optimum.h"
#include "estimation/shared_level.h"
#include "estimation/internal/smooth_scale.h"
#include "estimation/likelihood_ratio.h"
#include "estimation/profile_likelihood.h"
#include "estimation/estimation_problem.h"

namespace axis {

class Fitter {
 public:
  // `job`, `control` and `progress` (may be null) must outlive the fitter.
  Fitter(const EstimationProblem& job, const FitControl& control, std::ostream* progress);
  Fitter(const Fitter&) = delete;
  Fitter& operator=(const Fitter&) = delete;

  // Runs the fit once (FitParameters without publishing to
  // control.publish_level). Throws std::invalid_argument as FitParameters.
  FitResult Run();

  // What RunStarts leaves: the lowest whole-record end of the given starts.
  struct StartsOutcome {
    std::vector<double> best;  // θ at the lowest end (the first start's
                               // point if none ended)
    double cost = 0.0;         // its cost, +inf if no start ended
    ceres::Solver::Summary summary;
    std::vector<double> step;  // the last stage's step to it
    // start_costs, start_screen_costs, start_joined(_horizon), phases.
    FitResult result;
    int simulations = 0;
    int jacobians = 0;
  };

  // Runs only the starts: every one of `starts` (θ, internal coordinates)
  // over the shorter horizons and the whole record (each a finalist if
  // job.solver.finalists allows), no optimum check nor uncertainty. The
  // automatic random starts of another fit of the same job (AutoStarts).
  // `prior_path`: the job's start's point after each stage, run by the
  // calling fitter; a start that joins it stops there (reported as joining
  // kJoinedPrior).
  StartsOutcome RunStarts(const std::vector<std::vector<double>>& starts,
                          const std::vector<std::vector<double>>& prior_path);
  static constexpr int kJoinedPrior = std::numeric_limits<int>::max();

 private:
  // Where each start is between its stages.
  struct StartRun {
    std::vector<double> theta;  // its current point
    // A stage whose warm start fails to evaluate (the previous, shorter
    // horizon left a parameter it barely sees at a value where the longer
    // simulation is hypersensitive, e.g. T_p at its lower bound) is retried
    // once from the point the previous stage started from.
    std::vector<double> previous_start;
    // The trust-region radius (Ceres' 1/μ of Levenberg–Marquardt) its last
    // stage's solve ended with, at most kNearTrustRegionRadius; 0 before
    // its first stage. The next, longer stage starts from it (at least the
    // job's initial_trust_region_radius): it continues the same descent on
    // more of the record, and from the job's well-damped radius its solve
    // spent its first iterations, a Jacobian each, widening the trust
    // region again by at most a factor 3 each (Ceres' LM), where a step too
    // long costs a rejected trial point, a simulation in double. On the
    // independent square + sweep and PRBS discovery jobs 25 % fewer
    // derivative simulations, the same selections and estimates within
    // 1e-4 standard errors.
    double radius = 0.0;
    ceres::Solver::Summary summary;
    bool usable = true;
    // Stopped by control.abandon_above_bic: the horizon (s) and the BIC's
    // lower bound there; 0 and +inf while it runs.
    double abandoned_horizon = 0.0;
    double bic_bound = std::numeric_limits<double>::infinity();
    // Joined the path of an earlier start (Joined): its index and the
    // horizon (s); −1 and 0 otherwise.
    int joined = -1;
    double joined_horizon = 0.0;
    // The stage it stopped after (abandoned_horizon > 0), and the bounds of
    // the stages it ran while a control.pending_level was not yet known:
    // (stage, bound).
    size_t abandoned_stage = 0;
    std::vector<std::pair<size_t, double>> waiting_bounds;
  };

  // ---- the problem
  void BuildProblem();   // θ, bounds, estimated initial states
  void BuildStages();    // the horizon continuation's problems
  void SetSolverOptions();
  void DrawStarts();     // the job's start, then random ones
  // `count` random starts about `origin` (uniform in the bounds in internal
  // coordinates, job.solver.seed), the entries past the free ones
  // (initial states) as in `origin`.
  std::vector<std::vector<double>> RandomStarts(const std::vector<double>& origin,
                                                int count) const;
  void CheckControl();   // a resume of this job; pending_level's rules

  // ---- the starts
  void RunShorterStages();            // every start over the shorter horizons
  void RunStage(size_t s, size_t i, StartRun* run);
  void ShowStageStatus(size_t s, size_t i) const;
  double CostAtStart(size_t s, size_t i);
  // CostAt `point` on `problem` in double (the guard off); leaves p_.theta
  // at `point`.
  double PlainCostAt(ceres::Problem* problem, const std::vector<double>& point);
  bool PassedBound(size_t s, size_t i, StartRun* run);
  bool Joined(size_t s, size_t i, StartRun* run);
  void RefreshLevel(bool wait);
  bool PassedRecorded(StartRun* run);
  // The starts that go on to the whole record (order_), and the stopped
  // start with the lowest bound (abandoned_); false if every start stopped.
  bool RankFinalists();
  void RunFinalists();
  // The result of a fit whose every start stopped: `run`'s lowest bound.
  FitResult StoppedResult(const StartRun& run);

  // ---- far above the noise: more starts
  bool NeedsAutoStarts() const;
  // The random starts: kMisfitProbeStarts first (estimation/internal/start_agreement.h),
  // the rest of solver.auto_starts only unless those landed at the job's
  // cost; the lowest end becomes the estimate (FitResult::auto_starts_note).
  void AutoStarts();
  // A batch of random starts in another fitter of the same job; merges its
  // start costs and phases into result_ (the starts numbered from `first`)
  // and takes its end if lower. Returns the cost each start ended at (a
  // start that joined a path: that path's end; NaN if not continued).
  std::vector<double> RunRandomBatch(const std::vector<std::vector<double>>& starts,
                                     size_t first);

  // ---- the instant accelerometer at the contacts
  // Per-sample σ_k on the whole record's stage (at the start too where that
  // stage is the only one: a warm refit) for the samples of `a` whose window holds a contact
  // (estimation/internal/instant_sample_sigma.h) at the estimate, and the final stage
  // re-solved from it under them if they moved; again from its end while some σ_k moved by
  // more than 10 % of σ, kReweightPasses times at most. Fills
  // result_.sample_sigma_note.
  void WeighInstantSamples();
  bool SetInstantSampleSigmas(const std::vector<double>& theta);  // true if some σ_k moved

  // ---- the optimum check and the uncertainty
  void ChooseChecks();         // what they run (discovery: less)
  double LowerThanEstimate() const;
  // `near`: with near_options_ (a point next to the minimum), else options_.
  void RestartFrom(const std::vector<double>& point, double point_cost, bool near = false);
  void CheckOptimum();
  void EstimateUncertainty();  // covariance, local restarts, intervals
  bool LocalRestarts();        // true if one ended lower (then checked again)
  bool Intervals();            // true if they met a lower cost (likewise)

  // ---- the result
  FitResult Finish();
  void FinishOptimumNote();
  Eigen::MatrixXd PhysicalCovariance() const;
  std::vector<bool> Determined(const Eigen::MatrixXd& cov);
  void FinishIntervalNote(const std::vector<RatioInterval>& ratio);
  // Intervals that are artifacts of roughness (the estimate at an end of
  // its own profile interval, profile refits below the estimate by less
  // than ½t²s², a rough optimum check): the covariance at the smooth scale
  // replaces them
  // (smooth_), and the note says why. Not with discovery on.
  void SmoothScaleIntervals(const std::vector<RatioInterval>& ratio);
  // s² above kMisspecifiedS2 with structured residuals (Ljung–Box): the
  // intervals are conditional on the model; the sandwich standard errors
  // (FitResult::misspecification_note, ParameterEstimate::std_error_sandwich).
  void MisspecificationCheck();
  void AppendFreeEstimates(const Eigen::MatrixXd& cov, const std::vector<bool>& determined,
                           const std::vector<RatioInterval>& ratio);
  void EvaluateExperiments(const AxisParams<double>& fitted);

  const EstimationProblem& job_;
  const FitControl& control_;
  std::ostream* progress_;
  ProgressStream* status_ = nullptr;  // the terminal's status line, if any

  FitProblem p_;
  std::vector<int> state_index_;  // per experiment: its y0 in θ, −1 if fixed
  int n_free_ = 0;
  int theta_size_ = 0;
  double longest_ = 0.0;  // s, the longest experiment
  std::vector<HorizonStage> stages_;
  size_t last_ = 0;  // the whole record's stage
  int num_residuals_ = 0;
  ceres::Problem* full_problem_ = nullptr;
  ceres::Solver::Options options_;
  // Solves that start next to a minimum (the local restarts, the profile
  // refits): without the projected line search (SetSolverOptions).
  ceres::Solver::Options near_options_;
  std::vector<std::vector<double>> starts_;
  const HorizonCheckpoint* resume_ = nullptr;

  FitResult result_;
  std::vector<StartRun> runs_;
  std::vector<std::vector<std::vector<double>>> ends_;  // [start][stage] point
  std::vector<std::vector<double>> prior_path_;        // RunStarts' prior_path
  std::shared_ptr<HorizonCheckpoint> checkpoint_;      // the screen's record
  size_t finals_total_ = 0;
  size_t finals_done_ = 0;
  double abandon_above_ = std::numeric_limits<double>::infinity();
  const SharedLevel* pending_ = nullptr;
  bool level_known_ = true;
  double bic_penalty_ = 0.0;  // n·ln(m)
  double stop_after_ = 0.0;
  std::vector<size_t> order_;  // the finalists, lowest on the screen first
  size_t abandoned_ = 0;

  double best_cost_ = std::numeric_limits<double>::infinity();
  std::vector<double> best_;
  std::vector<double> best_step_;  // the last stage's step
  ceres::Solver::Summary best_summary_;
  int dof_ = 1;  // m − n

  bool discovering_ = false;
  int probe_rounds_ = 0;
  int probes_ = 0;
  // The last verified probe round's ProbeRoundResult::quadratic_reach
  // (standard deviations; 0 if none): LocalRestarts are not run within it.
  double quadratic_reach_ = 0.0;
  double entry_cost_ = 0.0;
  double t975_ = 0.0;
  bool ratio_method_ = false;
  bool profile_method_ = false;
  bool run_scan_ = false;
  double local_starts_ = 0.0;
  Eigen::MatrixXd cov_theta_;
  RatioScan scan_;
  ProfileScan profile_;
  // JᵀJ of the last covariance and the point it was evaluated at: the null
  // space reuses it if the estimate has not moved since.
  Eigen::MatrixXd jtj_at_;
  std::vector<double> jtj_point_;
  int ratio_restarts_ = 0;
  int local_passes_ = 0;

  // Issue 42: the probe rounds' gains (a rough cost), the covariance at the
  // smooth scale where it replaces the intervals, the start that ended
  // lowest (0: the job's) and the evaluations of the random starts' fitters.
  RoughRounds rough_;
  SmoothScale smooth_;
  bool smooth_used_ = false;
  size_t winner_ = 0;
  int extra_simulations_ = 0;
  int extra_jacobians_ = 0;
  double sigma_log_term_ = 0.0;  // SampleSigmaLogTerm of the final stage
  int weighted_samples_ = 0;       // samples with σ_k above σ by 0.5 %
  bool weights_changed_ = false;   // since best_cost_ was last evaluated
  double largest_sigma_ratio_ = 1.0;
};

}  // namespace axis

#endif  // ESTIMATION_INTERNAL_FITTER_H_
