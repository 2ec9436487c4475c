#include "discovery/internal/screen.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "estimation/fit.h"
#include "estimation/fit_control.h"
#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"

namespace axis {

std::vector<ScreenedFit> ScreenFits(std::vector<EstimationProblem> jobs, int threads) {
  for (EstimationProblem& j : jobs) {
    if (!(j.solver.first_horizon > 0.0)) {
      throw std::invalid_argument(
          "ScreenFits: expected jobs with solver.first_horizon > 0 (a horizon continuation), "
          "got " + std::to_string(j.solver.first_horizon) + " s");
    }
  }
  std::vector<FitControl> controls(jobs.size());
  for (size_t k = 0; k < jobs.size(); ++k) {
    controls[k].stop_after_horizon = ScreenHorizon(jobs[k].solver.first_horizon);
  }
  std::vector<double> seconds;
  const std::vector<FitResult> fits = FitConcurrently(jobs, threads, &seconds, controls);
  std::vector<ScreenedFit> out(fits.size());
  for (size_t k = 0; k < fits.size(); ++k) {
    out[k].bound =
        std::isfinite(fits[k].bic) ? fits[k].bic : std::numeric_limits<double>::infinity();
    out[k].seconds = seconds[k];
    out[k].checkpoint = fits[k].checkpoint;
  }
  return out;
}

double ScreenHorizon(double first_horizon) {
  return first_horizon * std::pow(2.0, kScreenStages - 1);
}

std::vector<size_t> RanksByBound(const std::vector<double>& bound) {
  const size_t n = bound.size();
  std::vector<size_t> by_bound(n);
  std::iota(by_bound.begin(), by_bound.end(), size_t{0});
  const auto key = [&](size_t b) {
    return std::isfinite(bound[b]) ? bound[b] : std::numeric_limits<double>::infinity();
  };
  std::stable_sort(by_bound.begin(), by_bound.end(),
                   [&](size_t x, size_t y) { return key(x) < key(y); });
  std::vector<size_t> rank(n);
  for (size_t r = 0; r < n; ++r) rank[by_bound[r]] = r + 1;
  return rank;
}

std::vector<bool> GoOnPastScreen(const std::vector<size_t>& score_rank,
                                 const std::vector<double>& bound, size_t top) {
  if (score_rank.size() != bound.size() || top == 0) {
    throw std::invalid_argument("GoOnPastScreen: expected score_rank and bound of one length "
                                "and top > 0, got " + std::to_string(score_rank.size()) +
                                ", " + std::to_string(bound.size()) + " and " +
                                std::to_string(top));
  }
  const size_t n = bound.size();
  std::vector<bool> goes_on(n, true);
  if (n <= 2 * top) return goes_on;
  const std::vector<size_t> screen_rank = RanksByBound(bound);
  for (size_t b = 0; b < n; ++b) {
    goes_on[b] = score_rank[b] <= top || screen_rank[b] <= top || !std::isfinite(bound[b]);
  }
  return goes_on;
}

std::string StoppedText(const FitResult& fit, double level, const std::string& level_name) {
  if (fit.abandoned_horizon == 0.0) return "";
  std::ostringstream out;
  out << std::setprecision(4) << "at the " << fit.abandoned_horizon
      << " s horizon: BIC >= " << fit.bic << " there already, more than " << kStopFactor
      << " times " << level_name << " (" << level << ")";
  return out.str();
}

}  // namespace axis
