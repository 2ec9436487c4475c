// The force-map step as a sequence of named steps, its state in members (as
// estimation/internal/fitter.h Fitter): whether to try, the forms and their score
// tests, the forms' refits beside the leader's level and the choice of
// form, the choice of λ, the backward pass over the loop's effects, the
// map's values, its curve, and the model adopted with the map. AddForceMap
// (discovery/force_map.h) is the public entry; this class is internal to
// discovery/. What each step does and why: discovery/force_map.h.
#ifndef DISCOVERY_INTERNAL_FORCE_MAP_STEP_H_
#define DISCOVERY_INTERNAL_FORCE_MAP_STEP_H_

#include <chrono>
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "discovery/candidates.h"
#include "discovery/discovery_report.h"
#include "discovery/force_map_report.h"
#include "discovery/internal/force_map_penalty.h"
#include "discovery/score_test.h"
#include "estimation/fit_result.h"
#include "discovery/discovery_settings.h"
#include "estimation/estimation_problem.h"

namespace axis {

class ForceMapStep {
 public:
  // `settings`, `loop`, `job`, `result` and `progress` (may be null) must
  // outlive the step; `job` and `result` are replaced by the model with the
  // map if it is kept.
  ForceMapStep(const DiscoverySettings& settings, const DiscoveryReport& loop, EstimationProblem* job,
               FitResult* result, std::ostream* progress);
  ForceMapStep(const ForceMapStep&) = delete;
  ForceMapStep& operator=(const ForceMapStep&) = delete;

  // Runs the step once (AddForceMap). Throws as AddForceMap.
  ForceMapReport Run();

 private:
  using Clock = std::chrono::steady_clock;

  // ---- whether to try; each false sets report_.reason
  bool HasBinnedStructure();  // the loop's verdict and diagnostics
  bool ListForms();           // the knots over the visited values
  bool TestForms();           // the forms' score tests

  // ---- the forms' refits
  void BuildFormJobs();
  std::string FormName(size_t f) const;
  void RefitForms();
  bool ChooseForm();  // the lowest BIC (edf); false if every refit failed
  void RecordForm(size_t f, double level, const std::string& level_name);
  void AdoptForm();

  // ---- the map's λ, the backward pass, the figures
  double ChooseLambda();  // the λ of the lowest linearised BIC over the grid
  void RefitAtLambda(double lambda);
  void AssessMap();
  void BackwardPass();
  void TryWithout(const std::string& effect);
  void RecordValues();
  void RecordCurve();
  void AdoptMap();  // the model with the map, if it is kept

  const DiscoverySettings& settings_;
  const DiscoveryReport& loop_;
  EstimationProblem* job_;
  FitResult* result_;
  std::ostream* progress_;
  Clock::time_point start_;
  ForceMapReport report_;

  std::vector<Candidate> candidates_;  // the forms
  Ranking ranking_;
  double threshold_ = 0.0;  // alpha / number of forms
  std::vector<EstimationProblem> jobs_;  // the significant forms' refits
  std::vector<double> info_;  // mean information per knot of each form
  std::vector<FitResult> fits_;
  std::vector<double> seconds_;
  size_t winner_ = 0;

  EstimationProblem map_job_;  // the winning form's job, then at the chosen λ
  FitResult fit_;
  int k_map_ = 0;  // number of knots
  Assessment at_;
  Eigen::MatrixXd cov_;  // the map's values' covariance (N²)
};

}  // namespace axis

#endif  // DISCOVERY_INTERNAL_FORCE_MAP_STEP_H_
