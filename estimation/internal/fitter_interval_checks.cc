// Fitter's checks of its intervals (estimation/internal/fitter.h, issue 42):
// intervals that are artifacts of a rough cost, replaced by the covariance
// at the smooth scale (estimation/internal/smooth_scale.h), and intervals under
// misspecification, with the sandwich standard errors beside them
// (estimation/internal/sandwich_covariance.h).
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "estimation/cost_at.h"
#include "estimation/fit_notes.h"
#include "estimation/internal/fitter.h"
#include "estimation/optimum_check.h"
#include "estimation/parameter_tie.h"
#include "estimation/internal/phase_timer.h"
#include "estimation/internal/sandwich_covariance.h"
#include "estimation/internal/smooth_scale.h"

namespace axis {

void Fitter::SmoothScaleIntervals(const std::vector<RatioInterval>& ratio) {
  if (discovering_ || !std::isfinite(best_cost_) || !cov_theta_.allFinite()) return;
  std::vector<std::string> at_end;
  if (profile_method_ && !ratio.empty()) {
    for (int k = 0; k < n_free_; ++k) {
      if (ratio[k].bounded_low && ratio[k].bounded_high &&
          EstimateAtIntervalEnd(p_.theta[k], ratio[k].low, ratio[k].high)) {
        at_end.push_back(job_.free[k].name);
      }
    }
  }
  // Profile refits that still ended below the estimate, by less than the
  // profile's own threshold ½t²s²: lower points within the interval's
  // scale, the cost rough where the profile starts (a larger gain is a
  // lower minimum, which FinishIntervalNote reports).
  const double gain = best_cost_ - profile_.lowest_cost;
  const bool profile_lower =
      profile_method_ && !ratio.empty() &&
      gain > CostResolution(best_cost_, job_.solver.function_tolerance) &&
      gain < 0.5 * t975_ * t975_ * result_.residual_variance;
  if (at_end.empty() && !profile_lower && !rough_.rough()) return;
  PhaseTimer timer("intervals", p_.counter, &result_);
  smooth_ = SmoothScaleCovariance(full_problem_, p_.theta, cov_theta_ * result_.residual_variance,
                                  p_.lower, p_.upper, result_.residual_variance, &p_.counter,
                                  job_.solver.threads, &p_.theta);
  std::ostringstream why;
  if (rough_.rough()) why << "the cost is rough below the standard-error scale (optimum check)";
  if (!at_end.empty()) {
    why << (why.tellp() > 0 ? "; " : "") << "the estimate is at an end of its own "
        << (profile_method_ ? "profile-likelihood" : "") << " interval:";
    for (size_t i = 0; i < at_end.size(); ++i) why << (i == 0 ? " " : ", ") << at_end[i];
  }
  if (profile_lower) {
    why << (why.tellp() > 0 ? "; " : "") << "profile refits ended below the estimate by "
        << best_cost_ - profile_.lowest_cost;
  }
  std::ostringstream note;
  if (!smooth_.ok) {
    note << result_.uncertainty_note << "; intervals may be artifacts of roughness (" << why.str()
         << "), and the Jacobian at the smooth scale could not be evaluated";
    result_.uncertainty_note = note.str();
    return;
  }
  smooth_used_ = true;
  result_.uncertainty_method = "gauss_newton_smooth_scale";
  note << "Gauss-Newton at the smooth scale: s^2·(JᵀJ)⁻¹ with J by central differences at "
          "about one standard error (" << smooth_.passes << " pass(es)), because the "
       << (profile_method_ ? "profile-likelihood" : ratio_method_ ? "likelihood-ratio" : "Gauss-Newton")
       << " intervals are artifacts of roughness here (" << why.str()
       << "); intervals θ ± t·SD in the "
       << "internal coordinates, std error = half-width / t; compare the bootstrap "
          "(uncertainty.bootstrap)";
  result_.uncertainty_note = note.str();
}

void Fitter::MisspecificationCheck() {
  const double s2 = result_.residual_variance;
  if (discovering_ || !(s2 > kMisspecifiedS2) || !std::isfinite(best_cost_)) return;
  const std::vector<std::string> structured = StructuredChannels(result_);
  if (structured.empty()) return;
  PhaseTimer timer("covariance", p_.counter, &result_);
  Eigen::MatrixXd j;
  Eigen::VectorXd r;
  if (smooth_used_) {
    j = smooth_.jacobian.leftCols(theta_size_);
    r = smooth_.residuals;
  } else {
    ceres::CRSMatrix crs;
    double cost = 0.0;
    std::vector<double> residuals;
    if (!full_problem_->Evaluate(EvaluateOn(job_.solver.threads), &cost, &residuals, nullptr,
                                 &crs)) {
      return;
    }
    j = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
    for (int row = 0; row < crs.num_rows; ++row) {
      for (int a = crs.rows[row]; a < crs.rows[row + 1]; ++a) j(row, crs.cols[a]) = crs.values[a];
    }
    r = Eigen::Map<const Eigen::VectorXd>(residuals.data(),
                                          static_cast<Eigen::Index>(residuals.size()));
  }
  // One series per fitted channel of every experiment, in the problem's
  // order (estimation/internal/fit_problem.h BuildStage); a force map's penalty rows
  // after them as one more.
  std::vector<int> series;
  long rows = 0;
  for (const FitExperiment& e : job_.experiments) {
    for (const FittedChannel& f : e.fitted) {
      series.push_back(static_cast<int>(e.Measured(f.channel).size()));
      rows += series.back();
    }
  }
  if (rows > r.size()) return;
  if (rows < r.size()) series.push_back(static_cast<int>(r.size() - rows));
  const int lags = std::max(1, job_.uncertainty.block);
  const Eigen::MatrixXd cov = NeweyWestCovariance(j, r, series, lags);
  for (int k = 0; k < n_free_; ++k) {
    result_.parameters[k].std_error_sandwich =
        std::sqrt(cov(k, k)) * std::abs(p_.map->Derivative(k, p_.theta[k]));
  }
  CopyTiedUncertainty(&result_);
  result_.misspecification_note = MisspecificationNote(result_, s2, structured, lags);
}

}  // namespace axis
