#include "estimation/likelihood_ratio.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "estimation/cost_at.h"

namespace axis {

RatioScan LikelihoodRatioIntervals(ceres::Problem* problem, const RatioScanOptions& options,
                                   std::vector<double>* theta) {
  const std::vector<double>& lower = options.basis.lower;
  const std::vector<double>& upper = options.basis.upper;
  const Eigen::MatrixXd& cov_theta = options.basis.cov_theta;
  const int n_free = options.basis.n_free;
  const double t975 = options.basis.t975;
  const double residual_variance = options.basis.residual_variance;
  const std::vector<double>& steps = options.steps;
  const int threads = options.threads;
  const int n = static_cast<int>(theta->size());
  const std::vector<double> centre = *theta;
  RatioScan scan;
  scan.lowest_point = centre;
  scan.lowest_cost = std::numeric_limits<double>::infinity();
  if (cov_theta.rows() != n || cov_theta.cols() != n || !cov_theta.allFinite() ||
      steps.empty()) {
    return scan;
  }
  const double c0 = CostAt(problem, centre, threads, theta);
  ++scan.evaluations;
  scan.lowest_cost = c0;
  if (!std::isfinite(c0)) {
    *theta = centre;
    return scan;
  }
  std::vector<RatioInterval>& out = scan.intervals;
  const double threshold = 0.5 * t975 * t975 * residual_variance;
  for (int k = 0; k < n_free; ++k) {
    RatioInterval interval;
    const double sd = std::sqrt(cov_theta(k, k));
    if (!(sd > 0.0)) {
      interval.low = interval.high = centre[k];
      out.push_back(interval);
      continue;
    }
    const Eigen::VectorXd d = cov_theta.col(k) / sd;
    for (double sign : {-1.0, 1.0}) {
      // Rise of the cost above c0 at each step (+∞ where it fails).
      double end = 0.0, previous_step = 0.0, previous_rise = 0.0;
      bool bounded = false;
      for (double s : steps) {
        std::vector<double> point = centre;
        for (int i = 0; i < n; ++i) {
          point[i] = std::clamp(centre[i] + sign * s * d[i], lower[i], upper[i]);
        }
        const double c = CostAt(problem, point, threads, theta);
        ++scan.evaluations;
        if (c < scan.lowest_cost) {
          scan.lowest_cost = c;
          scan.lowest_point = point;
        }
        const double rise = c - c0;
        if (rise <= threshold) {
          end = s;
          bounded = false;
        } else if (!bounded) {
          // First step above the threshold after one below it (or after
          // the centre): the end lies between them.
          end = std::isfinite(rise)
                    ? previous_step + (s - previous_step) *
                                          (threshold - previous_rise) /
                                          (rise - previous_rise)
                    : previous_step;
          bounded = true;
        }
        previous_step = s;
        previous_rise = std::isfinite(rise) ? std::min(rise, threshold) : threshold;
      }
      // The furthest crossing counts: a step below the threshold beyond a
      // bump reopens the side (bounded = false above) and moves the end.
      const double value = centre[k] + sign * end * sd;
      if (sign < 0) {
        interval.low = std::max(value, lower[k]);
        interval.bounded_low = bounded;
      } else {
        interval.high = std::min(value, upper[k]);
        interval.bounded_high = bounded;
      }
    }
    out.push_back(interval);
  }
  *theta = centre;
  return scan;
}

}  // namespace axis
