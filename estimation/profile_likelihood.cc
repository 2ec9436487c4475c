#include "estimation/profile_likelihood.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <ceres/manifold.h>

#include "estimation/cost_at.h"
#include "estimation/internal/optimistic_solve.h"

namespace axis {
namespace {

constexpr double kMaxSd = 16.0;     // furthest point, in GN standard deviations
constexpr int kRefinements = 4;
constexpr double kClose = 0.05;     // |P − cost* − threshold| / threshold
constexpr double kRetry = 3.0;      // refits ending up to kRetry·threshold are retried

}  // namespace

ProfileScan ProfileLikelihoodIntervals(ceres::Problem* problem, const ProfileOptions& options,
                                       std::vector<double>* theta) {
  return ProfileLikelihood(problem, options, theta).Run();
}

ProfileLikelihood::ProfileLikelihood(ceres::Problem* problem, const ProfileOptions& options,
                                     std::vector<double>* theta)
    : problem_(problem),
      options_(options.solver),
      counter_(options.counter),
      lower_(options.basis.lower),
      upper_(options.basis.upper),
      cov_theta_(options.basis.cov_theta),
      n_free_(options.basis.n_free),
      t975_(options.basis.t975),
      residual_variance_(options.basis.residual_variance),
      lowest_allowed_(options.lowest_allowed),
      stop_at_lower_(options.stop_at_lower),
      theta_(theta),
      on_parameter_(options.on_parameter),
      n_(static_cast<int>(theta->size())),
      centre_(*theta) {}

ProfileScan ProfileLikelihood::Run() {
  scan_.lowest_point = centre_;
  scan_.lowest_cost = std::numeric_limits<double>::infinity();
  if (cov_theta_.rows() != n_ || cov_theta_.cols() != n_ || !cov_theta_.allFinite()) {
    return scan_;
  }
  c0_ = CostAt(problem_, centre_, options_.num_threads, theta_);
  scan_.lowest_cost = c0_;
  if (!std::isfinite(c0_)) {
    *theta_ = centre_;
    return scan_;
  }
  threshold_ = 0.5 * t975_ * t975_ * residual_variance_;
  std::vector<RatioInterval> intervals;
  for (int k = 0; k < n_free_ && !stopped_; ++k) intervals.push_back(Parameter(k));
  if (!stopped_) scan_.intervals = std::move(intervals);
  *theta_ = centre_;
  return scan_;
}

// ---------------------------------------------------------------- per parameter

RatioInterval ProfileLikelihood::Parameter(int k) {
  if (on_parameter_) on_parameter_(k);
  RatioInterval interval;
  const double sd = std::sqrt(cov_theta_(k, k));
  if (!(sd > 0.0)) {
    interval.low = interval.high = centre_[k];
    return interval;
  }
  k_ = k;
  sd_ = sd;
  refits_.clear();
  slope_ = cov_theta_.col(k) / cov_theta_(k, k);  // dθ/dθ_k
  // With θ_k the only entry there is nothing to refit: P is the cost.
  refit_ = n_ > 1;
  if (refit_) problem_->SetManifold(theta_->data(), new ceres::SubsetManifold(n_, {k}));
  for (double sign : {-1.0, 1.0}) {
    if (!Side(sign, &interval)) {
      stopped_ = true;
      break;
    }
  }
  if (refit_) problem_->SetManifold(theta_->data(), nullptr);
  return interval;
}

bool ProfileLikelihood::Side(double sign, RatioInterval* interval) {
  const double bound = sign < 0 ? lower_[k_] : upper_[k_];
  xs_ = {centre_[k_]};
  rises_ = {0.0};
  points_ = {centre_};
  WalkOut(sign, bound);
  RetryInward();
  if (MetLower()) return false;
  // The end lies between the furthest point still below the threshold and
  // the next one out.
  const size_t j = FurthestBelow();
  const bool bounded = j + 1 < xs_.size();
  double end = xs_[j];
  if (bounded && !Refine(j, &end)) return false;
  if (sign < 0) {
    interval->low = end;
    interval->bounded_low = bounded;
  } else {
    interval->high = end;
    interval->bounded_high = bounded;
  }
  return true;
}

// ---------------------------------------------------------------- one side

// The profile at t, 2t, 4t and 8t Gauss–Newton standard deviations
// (clipped to the bound), each refit warm-started from the previous point.
void ProfileLikelihood::WalkOut(double sign, double bound) {
  for (double m = t975_; m <= kMaxSd; m *= 2.0) {
    double x = centre_[k_] + sign * m * sd_;
    if (sign * (x - bound) >= 0.0) x = bound;
    std::vector<double> solved;
    const double rise = ProfileAt(x, xs_.size() - 1, -1, &solved);
    xs_.push_back(x);
    rises_.push_back(rise);
    points_.push_back(solved);
    if (MetLower() || x == bound) break;
  }
}

// Inward, points just above the threshold once more from the solved point
// outside them.
void ProfileLikelihood::RetryInward() {
  for (size_t i = xs_.size() - 1; i-- > 1 && !MetLower();) {
    if (NearThreshold(rises_[i]) && std::isfinite(rises_[i + 1])) {
      LowerFrom(xs_[i], i + 1, &rises_[i], &points_[i]);
    }
  }
}

size_t ProfileLikelihood::FurthestBelow() const {
  size_t j = 0;
  for (size_t i = 0; i < xs_.size(); ++i) {
    if (rises_[i] <= threshold_) j = i;
  }
  return j;
}

// Regula falsi on z = √rise, linear in x where P is quadratic; refits
// warm-started from the point below. The bracket's ends are kept as solved
// points (indices into xs_).
bool ProfileLikelihood::Refine(size_t j, double* end) {
  size_t below = j, above = j + 1;
  const double target = std::sqrt(threshold_);
  for (int it = 0;; ++it) {
    const double z_below = std::sqrt(std::max(rises_[below], 0.0));
    const double z_above =
        std::isfinite(rises_[above]) ? std::sqrt(rises_[above]) : 2.0 * target;
    *end = xs_[below] + (xs_[above] - xs_[below]) * (target - z_below) / (z_above - z_below);
    if (it == kRefinements || std::abs(rises_[above] - threshold_) <= kClose * threshold_) {
      break;
    }
    std::vector<double> solved;
    const double rise = ProfileAt(*end, below, static_cast<int>(above), &solved);
    if (MetLower()) return false;
    xs_.push_back(*end);
    rises_.push_back(rise);
    points_.push_back(solved);
    (rise > threshold_ ? above : below) = xs_.size() - 1;
    // Close enough: one more interpolation in the narrowed bracket (free)
    // rather than the refit point itself, which may lie up to kClose inside
    // or outside the crossing.
    it = std::abs(rise - threshold_) <= kClose * threshold_ ? kRefinements - 1 : it;
  }
  return true;
}

// ---------------------------------------------------------------- a refit at a point

double ProfileLikelihood::RiseAt(double x, double from_x, const std::vector<double>& from,
                                 std::vector<double>* solved) {
  std::vector<double> start = from;
  for (int i = 0; i < n_; ++i) {
    start[i] = std::clamp(from[i] + (x - from_x) * slope_[i], lower_[i], upper_[i]);
  }
  start[k_] = x;
  double cost = 0.0;
  if (!refit_) {
    cost = CostAt(problem_, start, options_.num_threads, theta_);
  } else {
    cost = Refit(start);
  }
  *solved = *theta_;
  if (!std::isfinite(cost)) return std::numeric_limits<double>::infinity();
  if (cost < scan_.lowest_cost) {
    scan_.lowest_cost = cost;
    scan_.lowest_point = *theta_;
  }
  return cost - c0_;
}

double ProfileLikelihood::Refit(const std::vector<double>& start) {
  for (const RefitMemory& m : refits_) {
    if (m.start == start) {
      *theta_ = m.end;
      ++scan_.repeated;
      return m.cost;
    }
  }
  std::copy(start.begin(), start.end(), theta_->begin());
  ceres::Solver::Summary summary;
  SolveOptimistically(options_, problem_, theta_->data(), n_, counter_, &summary);
  ++scan_.solves;
  scan_.iterations += static_cast<int>(summary.iterations.size()) - 1;
  const double cost = summary.IsSolutionUsable() ? summary.final_cost
                                                 : std::numeric_limits<double>::infinity();
  refits_.push_back({start, cost, *theta_});
  return cost;
}

// P at x refitted from solved point `warm`; where that ends near the
// threshold (above it, at most kRetry times it) or fails, also from the
// estimate and, if still near the threshold, from solved point `outer`
// (−1: none); the lowest counts. The cost is piecewise smooth with small
// jumps (the encoder quantiser, backlash contacts moving across controller
// samples), so one local refit can stop in a local minimum up to about half
// the threshold above the profile (issue 9, seed 24 of the PRBS campaign); a
// refit from another side of the bump finds it. A refit ending further
// above than kRetry thresholds is not retried: a bump of that size cannot
// bring it below the threshold, and the walk-out's points far out (4t to
// 16t standard deviations) all end there on a smooth profile.
double ProfileLikelihood::ProfileAt(double x, size_t warm, int outer,
                                    std::vector<double>* solved) {
  double rise = RiseAt(x, xs_[warm], points_[warm], solved);
  if (warm != 0 && !MetLower() && (NearThreshold(rise) || !std::isfinite(rise))) {
    LowerFrom(x, 0, &rise, solved);
  }
  if (outer >= 0 && std::isfinite(rises_[outer]) && !MetLower() && NearThreshold(rise)) {
    LowerFrom(x, static_cast<size_t>(outer), &rise, solved);
  }
  return rise;
}

void ProfileLikelihood::LowerFrom(double x, size_t from, double* rise,
                                  std::vector<double>* solved) {
  std::vector<double> other;
  const double again = RiseAt(x, xs_[from], points_[from], &other);
  if (again < *rise) {
    *rise = again;
    *solved = std::move(other);
  }
}

bool ProfileLikelihood::NearThreshold(double rise) const {
  return rise > threshold_ && rise <= kRetry * threshold_;
}

// ---------------------------------------------------------------- restart bookkeeping

bool ProfileLikelihood::MetLower() const {
  return stop_at_lower_ && scan_.lowest_cost < lowest_allowed_;
}

}  // namespace axis
