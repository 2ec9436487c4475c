#include "discovery/accelerometer_convention.h"
#include "discovery/internal/force_map_step.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <utility>

#include <Eigen/Dense>

#include "common/format.h"
#include "discovery/channel_changes.h"
#include "discovery/diagnostics.h"
#include "discovery/internal/force_map_forms.h"
#include "discovery/internal/force_map_text.h"
#include "discovery/internal/screen.h"
#include "estimation/at_estimate.h"
#include "estimation/fit.h"
#include "estimation/fit_control.h"
#include "estimation/optimum_check.h"
#include "estimation/shared_level.h"
#include "estimation/stacked_jacobian.h"
#include "sim/force_map.h"

namespace axis {
namespace {

using Clock = std::chrono::steady_clock;

// The two-sided 95 % point of the normal distribution: the pointwise band
// of the map (its Bayesian posterior is Gaussian given s²).
constexpr double kZ975 = 1.959963984540054;

// Points of the reported curve over the knots' range.
constexpr int kCurvePoints = 201;

// The λ grid, in units of the mean information per knot (the diagonal of
// JᵀJ over the map's values): from practically unpenalised (10⁻⁶) to a map
// held nearly straight (10²).
constexpr double kLambdaGrid[] = {1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0, 10.0, 100.0};
// The first refit's λ (same units): little smoothing, so that the
// linearised choice starts from a map that follows the data.
constexpr double kFirstLambda = 1e-3;
// The anchor's weight α in units of the mean information per knot times
// the number of knots (about the data's information along a component
// spread over all knots): 10³ holds a confounded component at 10⁻³ of
// what the data alone would put there.
constexpr double kAnchorFactor = 1e3;

// How far above the BIC with an effect (`bic`) the backward pass's refit
// without it may end and still remove it: the solver's accuracy
// (CostResolution, estimation/optimum_check.h, in χ² = 2·cost units). The effect goes into
// the map whole where the map can carry it (TransferToMap: a load offset is
// a constant of f(v)), and the two models are then one function whose
// BICs differ by round-off and the solver's stop: on the velocity bump case
// 26834.934363 both ways, the sign of the difference (+6e-8 or −6e-10)
// changing with the number of threads a sum ran on. The model without it
// says the same with fewer parameters.
double RemovalTolerance(double bic, double function_tolerance) {
  return 2.0 * CostResolution(0.5 * bic, function_tolerance);
}

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The weights W(q, k) = w_k(z_q) with f(z_q) = Σ_k w_k·f_k: the spline is
// linear in its values, so w_k is the spline through the k-th unit vector
// (its second derivatives solved once per k).
Eigen::MatrixXd CardinalWeights(const std::vector<double>& knots, const std::vector<double>& z) {
  const int n = static_cast<int>(knots.size());
  Eigen::MatrixXd w(z.size(), n);
  for (int k = 0; k < n; ++k) {
    std::array<double, kMaxForceMapKnots> unit{}, m{};
    unit[k] = 1.0;
    ForceMapSecondDerivatives(knots, unit, &m);
    for (size_t q = 0; q < z.size(); ++q) w(q, k) = ForceMapValue(knots, unit, m, z[q]);
  }
  return w;
}

std::string Number(double x, int digits = 4) { return FormatNumber(x, digits); }

// Runs of `z` where `inside` holds, as "x in [a, b] m, [c, d] m".
std::string Runs(const ForceMapCurve& c, const ForceMap& map, bool rotary,
                 const std::vector<bool>& inside) {
  std::ostringstream out;
  int runs = 0;
  for (size_t j = 0; j < inside.size();) {
    if (!inside[j]) {
      ++j;
      continue;
    }
    size_t end = j;
    while (end + 1 < inside.size() && inside[end + 1]) ++end;
    out << (runs++ ? ", " : "") << "[" << Number(c.z[j]) << ", " << Number(c.z[end]) << "] "
        << VariableUnit(map, rotary);
    j = end + 1;
  }
  return runs ? std::string(VariableName(map)) + " in " + out.str() : "";
}

}  // namespace

ForceMapStep::ForceMapStep(const DiscoverySettings& settings, const DiscoveryReport& loop,
                           EstimationProblem* job, FitResult* result, std::ostream* progress)
    : settings_(settings), loop_(loop), job_(job), result_(result), progress_(progress) {}

ForceMapReport ForceMapStep::Run() {
  start_ = Clock::now();
  report_.bic_before = result_->bic;
  if (!HasBinnedStructure() || !ListForms() || !TestForms()) return report_;
  BuildFormJobs();
  RefitForms();
  if (!ChooseForm()) {
    report_.reason += "; every refit failed";
    report_.seconds = SecondsSince(start_);
    return report_;
  }
  AdoptForm();
  const double lambda = ChooseLambda();
  if (lambda != map_job_.roughness.lambda) RefitAtLambda(lambda);
  AssessMap();
  // Backward pass: the loop's effects may stand in for what the map now
  // carries.
  if (report_.kept) BackwardPass();
  RecordValues();
  RecordCurve();
  if (report_.kept) AdoptMap();
  report_.seconds = SecondsSince(start_);
  return report_;
}

// ---------------------------------------------------------------- whether to try

bool ForceMapStep::HasBinnedStructure() {
  if (loop_.verdict.verdict != "incomplete") {
    report_.reason = "not tried: the library's verdict is '" + loop_.verdict.verdict + "'";
    return false;
  }
  if (job_->model.structure.force_map.enabled) {
    report_.reason = "not tried: the model has a force map already";
    return false;
  }
  for (const ChannelDiagnostics& d : loop_.final_diagnostics) {
    for (const BinnedResidual& b : d.bins) {
      if ((b.variable == "x" || b.variable == "v") && b.p_value < loop_.verdict.threshold) {
        report_.structure.push_back(d.experiment + "/" + d.channel + ": " + b.variable +
                                    " (chi2 p " + Number(b.p_value, 3) + ")");
      }
    }
  }
  if (report_.structure.empty()) {
    report_.reason =
        "not tried: no significant binned structure of the residual against x or v "
        "(threshold " + Number(loop_.verdict.threshold, 3) + ")";
    return false;
  }
  return true;
}

bool ForceMapStep::ListForms() {
  ApplyEstimates(*result_, job_);
  // The library model's BIC from the same residuals as the map's (Assess,
  // at the fitted initial states ApplyEstimates wrote; its edf, like the
  // map's, without them, so the two compare alike).
  report_.bic_before = Assess(*job_).bic;
  const Visited visited = VisitedValues(*job_);
  const std::vector<double> x_knots = MapKnots(visited.x, settings_.force_map_knots);
  const std::vector<double> v_knots = MapKnots(visited.v, settings_.force_map_knots);
  if (!x_knots.empty()) {
    candidates_.push_back(MapCandidate(ForceMapVariable::kX, false, x_knots));
    candidates_.push_back(MapCandidate(ForceMapVariable::kX, true, x_knots));
  }
  if (!v_knots.empty()) candidates_.push_back(MapCandidate(ForceMapVariable::kV, false, v_knots));
  if (candidates_.empty()) {
    report_.reason = "not tried: the experiments do not move";
    return false;
  }
  return true;
}

bool ForceMapStep::TestForms() {
  ranking_ = RankCandidates(*job_, candidates_, settings_.alpha);
  report_.scores = ranking_.scores;
  const Score& best = ranking_.scores.front();
  threshold_ = settings_.alpha / static_cast<double>(candidates_.size());
  if (!(best.p_value < threshold_)) {
    report_.reason = "not tried: no form of the map is significant (best " + best.name +
                     ", p " + Number(best.p_value, 3) + ", threshold " + Number(threshold_, 3) +
                     ")";
    return false;
  }
  report_.tried = true;
  report_.reason = "the library's verdict is 'incomplete' with binned structure against x or v";
  return true;
}

// ---------------------------------------------------------------- the forms' refits

// Every significant form refitted at little smoothing; the lowest BIC
// wins. The score ranking alone is not trusted where the model is far
// from the data (the friction patch case: f(v) first by χ² 4.10e4
// against f(x)·sgn(v)'s 4.06e4). Those far above the leading form stop
// (on the velocity bump case f(x) and f(x)·sgn(v) ended 7 times above
// f(v)'s BIC after 30 and 12 s).
void ForceMapStep::BuildFormJobs() {
  for (const Score& score : ranking_.scores) {
    if (!(score.p_value < threshold_)) continue;
    for (const Candidate& c : candidates_) {
      if (c.name != score.name) continue;
      EstimationProblem form = MapJob(*job_, c, job_->solver.first_horizon);
      Eigen::VectorXd r0;
      Eigen::MatrixXd j0;
      StackedJacobian(form, &r0, &j0);
      const int k = static_cast<int>(c.force_map.knots.size());
      info_.push_back(j0.rightCols(k).colwise().squaredNorm().mean());
      form.roughness.lambda = kFirstLambda * info_.back();
      form.roughness.anchor = kAnchorFactor * info_.back() * k;
      jobs_.push_back(std::move(form));
    }
  }
}

std::string ForceMapStep::FormName(size_t f) const {
  return "force_map." + ForceMapKind(jobs_[f].model.structure.force_map);
}

// The first form by score publishes its BIC as the level (discovery/internal/screen.h
// SharedLevel); the others run beside it and stop where they would have
// stopped had they run after it against that level (kStopFactor times
// it), so that a form far above the leader stops once the leader ends,
// and one that is not runs as if there were no level. Map steps (s),
// velocity bump / friction patch case: 55.9 / 67.1 with every form run
// to the end, 27.3 / 55.7 so. Tried: as the loop's candidates, a screen
// of the first horizons choosing the leader, which then ran alone on
// both threads, the others after it: 23.9 / 77.2, the friction patch's
// slowest form starting only after the screen and the leader. The fits
// run with a control each (the jobs keep no level).
void ForceMapStep::RefitForms() {
  const int threads = std::max(1, job_->solver.threads);
  const auto shared_level = std::make_shared<SharedLevel>(kStopFactor);
  std::vector<FitControl> controls(jobs_.size());
  for (size_t f = 0; f < controls.size(); ++f) {
    if (f == 0) {
      controls[f].publish_level = shared_level;
    } else {
      controls[f].pending_level = shared_level;
    }
  }
  fits_ = FitConcurrently(jobs_, threads, &seconds_, controls);
}

bool ForceMapStep::ChooseForm() {
  double level = std::numeric_limits<double>::infinity();
  std::string level_name;
  if (fits_[0].abandoned_horizon == 0.0 && std::isfinite(fits_[0].bic)) {
    level = fits_[0].bic;
    level_name = FormName(0) + "'s fit BIC (2·cost + n·ln m)";
  }
  winner_ = jobs_.size();
  for (size_t f = 0; f < jobs_.size(); ++f) RecordForm(f, level, level_name);
  return winner_ != jobs_.size();
}

// Form f's refit in the report (its BIC with the edf, or the bound it
// stopped at); the winner so far in winner_.
void ForceMapStep::RecordForm(size_t f, double level, const std::string& level_name) {
  ForceMapForm form;
  form.name = FormName(f);
  form.seconds = seconds_[f];
  form.bic = std::numeric_limits<double>::infinity();
  form.stopped = StoppedText(fits_[f], level, level_name);
  if (!form.stopped.empty()) {
    form.bic = fits_[f].bic;
  } else if (std::isfinite(fits_[f].final_cost)) {
    ApplyEstimates(fits_[f], &jobs_[f]);
    const Assessment a = Assess(jobs_[f]);
    form.bic = a.bic;
    form.edf = a.edf;
    if (winner_ == jobs_.size() || form.bic < report_.forms[winner_].bic) winner_ = f;
  }
  report_.forms.push_back(form);
  if (progress_) {
    *progress_ << "force map: " << form.name << " at lambda " << jobs_[f].roughness.lambda
               << ": BIC " << (form.stopped.empty() ? "" : ">= ") << form.bic;
    if (form.stopped.empty()) {
      *progress_ << ", edf " << form.edf;
    } else {
      *progress_ << ": stopped " << form.stopped;
    }
    *progress_ << " (" << Number(form.seconds, 3) << " s)\n";
  }
}

void ForceMapStep::AdoptForm() {
  map_job_ = std::move(jobs_[winner_]);
  fit_ = std::move(fits_[winner_]);
  report_.kind = ForceMapKind(map_job_.model.structure.force_map);
  report_.map = map_job_.model.structure.force_map;
  report_.rotary = map_job_.model.structure.motion == Motion::kRotary;
  k_map_ = static_cast<int>(report_.map.knots.size());
}

// ---------------------------------------------------------------- λ, removals, figures

// The λ of the lowest linearised BIC over the grid (report_.grid), to be
// refitted there.
double ForceMapStep::ChooseLambda() {
  Eigen::VectorXd r;
  Eigen::MatrixXd j;
  StackedJacobian(map_job_, &r, &j);
  const double log_m = std::log(static_cast<double>(r.size()));
  const Eigen::VectorXd theta = ThetaOf(map_job_);
  double best_bic = std::numeric_limits<double>::infinity();
  double lambda = map_job_.roughness.lambda;
  EstimationProblem trial = map_job_;
  for (double g : kLambdaGrid) {
    SmoothingChoice choice;
    trial.roughness.lambda = choice.lambda = g * info_[winner_];
    const Penalised at = AtPenalty(r, j, PenaltyMatrix(trial, static_cast<int>(j.cols())), theta,
                                   true);
    choice.edf = at.edf;
    choice.chi2 = at.chi2;
    choice.bic = choice.chi2 + choice.edf * log_m;
    report_.grid.push_back(choice);
    if (choice.bic < best_bic) {
      best_bic = choice.bic;
      lambda = choice.lambda;
    }
  }
  return lambda;
}

void ForceMapStep::RefitAtLambda(double lambda) {
  EstimationProblem refit_job = map_job_;
  refit_job.roughness.lambda = lambda;
  refit_job.solver.first_horizon = 0.0;  // next to its optimum
  const Clock::time_point refit_start = Clock::now();
  FitResult refit = FitParameters(refit_job, nullptr);
  if (progress_) {
    *progress_ << "force map: refit at lambda " << lambda << " ("
               << Number(SecondsSince(refit_start), 3) << " s)\n";
  }
  if (std::isfinite(refit.final_cost)) {
    ApplyEstimates(refit, &refit_job);
    refit_job.solver.first_horizon = map_job_.solver.first_horizon;
    map_job_ = std::move(refit_job);
    fit_ = std::move(refit);
  }
}

void ForceMapStep::AssessMap() {
  report_.lambda = map_job_.roughness.lambda;
  at_ = Assess(map_job_);
  report_.bic_after = at_.bic;
  report_.kept = report_.bic_after < report_.bic_before;
  if (progress_) {
    *progress_ << "force map " << report_.kind << ": lambda " << report_.lambda
               << " 1/N^2, edf " << at_.edf << ", BIC " << report_.bic_before << " -> "
               << report_.bic_after << (report_.kept ? " (kept)" : " (not kept)") << "\n";
  }
}

void ForceMapStep::BackwardPass() {
  const std::vector<std::string>& selected = loop_.selected;
  for (auto it = selected.rbegin(); it != selected.rend(); ++it) {
    const std::string& effect = *it;
    if (IsConventionStep(effect)) continue;  // no parameter to move into the map
    if (std::find(loop_.removed.begin(), loop_.removed.end(), effect) != loop_.removed.end()) {
      continue;
    }
    if (RefinedInModel(effect, map_job_.model.structure)) continue;
    TryWithout(effect);
  }
  report_.bic_after = at_.bic;
}

// The map's model refitted without `effect` (its force moved into the
// map); it goes if BIC does not rise beyond the solver's accuracy.
void ForceMapStep::TryWithout(const std::string& effect) {
  EstimationProblem without = JobWithout(map_job_, effect);
  TransferToMap(effect, &without);
  // From the map's optimum with the effect's force moved into the map: next
  // to its optimum, as the refit at the chosen λ, so no horizon
  // continuation. On the friction patch case the three removals end at
  // the same BICs to the last digit as with the continuation, in 0.8–2.7 s
  // instead of 9–10 s each.
  const double first_horizon = without.solver.first_horizon;
  without.solver.first_horizon = 0.0;
  const Clock::time_point refit_start = Clock::now();
  FitResult refit = FitParameters(without, nullptr);
  const double refit_seconds = SecondsSince(refit_start);
  ForceMapRemoval removal;
  removal.effect = effect;
  removal.bic_with = at_.bic;
  removal.bic_without = std::numeric_limits<double>::infinity();
  if (std::isfinite(refit.final_cost) && refit.abandoned_horizon == 0.0) {
    ApplyEstimates(refit, &without);
    const Assessment a = Assess(without);
    removal.bic_without = a.bic;
    // Not higher than with the effect beyond the solver's accuracy: a
    // tie (see RemovalTolerance), which parsimony decides.
    if (a.bic < at_.bic + RemovalTolerance(at_.bic, without.solver.function_tolerance)) {
      removal.removed = true;
      without.solver.first_horizon = first_horizon;  // the job's own, as RefitAtLambda keeps it
      map_job_ = std::move(without);
      fit_ = std::move(refit);
      at_ = a;
    }
  }
  if (progress_) {
    *progress_ << "force map: without " << effect << ": BIC " << removal.bic_with << " -> "
               << removal.bic_without << (removal.removed ? " (removed" : " (stays") << ", "
               << Number(refit_seconds, 3) << " s)\n";
  }
  report_.removals.push_back(removal);
}

void ForceMapStep::RecordValues() {
  report_.edf = at_.edf;
  report_.s2 = at_.s2;
  cov_ = at_.s2 * at_.inverse.bottomRightCorner(k_map_, k_map_);
  for (int k = 0; k < k_map_; ++k) {
    report_.values.push_back(map_job_.model.params.f_map[k]);
    report_.std_errors.push_back(std::sqrt(std::max(0.0, cov_(k, k))));
  }
  report_.channels = ChannelChanges(*result_, fit_);
}

// The curve with its band, and where the band excludes zero.
void ForceMapStep::RecordCurve() {
  const std::vector<double>& kn = report_.map.knots;
  const Eigen::Map<const Eigen::VectorXd> values(report_.values.data(), k_map_);
  std::vector<bool> nonzero;
  for (int q = 0; q < kCurvePoints; ++q) {
    report_.curve.z.push_back(kn.front() + (kn.back() - kn.front()) * q / (kCurvePoints - 1));
  }
  const Eigen::MatrixXd weights = CardinalWeights(kn, report_.curve.z);
  for (int q = 0; q < kCurvePoints; ++q) {
    const Eigen::VectorXd wv = weights.row(q).transpose();
    const double f = wv.dot(values);
    const double sd = std::sqrt(std::max(0.0, wv.dot(cov_ * wv)));
    report_.curve.force.push_back(f);
    report_.curve.low.push_back(f - kZ975 * sd);
    report_.curve.high.push_back(f + kZ975 * sd);
    nonzero.push_back(std::abs(f) > kZ975 * sd);
  }
  const std::string runs = Runs(report_.curve, report_.map, report_.rotary, nonzero);
  if (!runs.empty()) report_.significant.push_back(runs);
}

// The map's figures: the data's χ² (the fit's cost holds the roughness
// penalty too) over m − edf, as the verdict's s² test needs them, the
// estimated initial states counted as FitParameters counts them (edf
// has no columns for them, StackedJacobian).
void ForceMapStep::AdoptMap() {
  const double states = EstimatedStateCount(map_job_);
  const double m = fit_.num_residuals;
  fit_.bic = at_.bic + states * std::log(m);
  fit_.aic = at_.chi2 + 2.0 * (at_.edf + states);
  fit_.residual_dof = std::max(1.0, m - at_.edf - states);
  fit_.residual_variance = at_.chi2 / fit_.residual_dof;
  *job_ = std::move(map_job_);
  *result_ = std::move(fit_);
  report_.diagnostics = DiagnoseResiduals(*job_);
  report_.verdict = JudgeResiduals(report_.diagnostics, *result_, settings_.alpha);
}

}  // namespace axis
