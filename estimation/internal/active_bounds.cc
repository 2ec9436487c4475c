#include "estimation/internal/active_bounds.h"

#include <algorithm>
#include <iterator>

#include <ceres/manifold.h>

#include "estimation/cost_at.h"
#include "estimation/internal/optimistic_solve.h"

namespace axis {
namespace {

// Rounds of the active set at most: each adds or releases entries, and a
// box has few entries that press on a bound at once.
constexpr int kMaxRounds = 8;
// A crawl: this many successful steps in a row, each with an entry on a
// bound and a ratio of actual to predicted decrease below kCrawlRatio (a
// step whose prediction the projection spoiled by half or more; a
// Gauss–Newton model of a smooth cost predicts a short step's decrease to
// within its square).
constexpr int kCrawlSteps = 3;
constexpr double kCrawlRatio = 0.5;

bool OnBound(const double* theta, size_t k, const std::vector<double>& lower,
             const std::vector<double>& upper) {
  return theta[k] <= lower[k] || theta[k] >= upper[k];
}

// Whether an entry not in `held` (sorted) is on a bound.
bool FreeOnBound(const double* theta, const std::vector<int>& held,
                 const std::vector<double>& lower, const std::vector<double>& upper) {
  for (size_t k = 0; k < lower.size(); ++k) {
    if (OnBound(theta, k, lower, upper) &&
        !std::binary_search(held.begin(), held.end(), static_cast<int>(k))) {
      return true;
    }
  }
  return false;
}

// Stops a run that crawls along a bound (kCrawlSteps, kCrawlRatio), the
// state read each iteration (Solver::Options::update_state_every_iteration).
class BoundCrawl : public ceres::IterationCallback {
 public:
  BoundCrawl(const double* theta, const std::vector<int>& held, const std::vector<double>& lower,
             const std::vector<double>& upper)
      : theta_(theta), held_(held), lower_(lower), upper_(upper) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (s.iteration == 0 || !s.step_is_successful) return ceres::SOLVER_CONTINUE;
    const bool slow = s.relative_decrease < kCrawlRatio && FreeOnBound(theta_, held_, lower_, upper_);
    slow_steps_ = slow ? slow_steps_ + 1 : 0;
    if (slow_steps_ < kCrawlSteps) return ceres::SOLVER_CONTINUE;
    crawled_ = true;
    return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
  }
  bool crawled() const { return crawled_; }
  void Reset() {
    slow_steps_ = 0;
    crawled_ = false;
  }

 private:
  const double* theta_;
  const std::vector<int>& held_;
  const std::vector<double>& lower_;
  const std::vector<double>& upper_;
  int slow_steps_ = 0;
  bool crawled_ = false;
};

// ∂cost/∂θ at θ (the problem without a manifold); empty if it cannot be
// evaluated.
std::vector<double> Gradient(ceres::Problem* problem, int threads) {
  double cost = 0.0;
  std::vector<double> gradient;
  if (!problem->Evaluate(EvaluateOn(threads), &cost, nullptr, &gradient, nullptr)) return {};
  return gradient;
}

void AppendRun(const ceres::Solver::Summary& run, bool first, ceres::Solver::Summary* total) {
  if (first) {
    *total = run;
    return;
  }
  const int offset = total->iterations.empty() ? 0 : total->iterations.back().iteration;
  for (size_t i = 1; i < run.iterations.size(); ++i) {
    total->iterations.push_back(run.iterations[i]);
    total->iterations.back().iteration += offset;
  }
  total->num_successful_steps += run.num_successful_steps;
  total->num_unsuccessful_steps += run.num_unsuccessful_steps;
  total->num_inner_iteration_steps += run.num_inner_iteration_steps;
  total->num_line_search_steps += run.num_line_search_steps;
  total->num_residual_evaluations += run.num_residual_evaluations;
  total->num_jacobian_evaluations += run.num_jacobian_evaluations;
  total->num_linear_solves += run.num_linear_solves;
  total->minimizer_time_in_seconds += run.minimizer_time_in_seconds;
  total->total_time_in_seconds += run.total_time_in_seconds;
  total->final_cost = run.final_cost;
  total->termination_type = run.termination_type;
  total->message = run.message;
}

}  // namespace

std::vector<int> PressedBounds(const double* theta, const std::vector<double>& gradient,
                               const std::vector<double>& lower,
                               const std::vector<double>& upper) {
  std::vector<int> pressed;
  for (size_t k = 0; k < lower.size() && k < gradient.size(); ++k) {
    if ((theta[k] <= lower[k] && gradient[k] > 0.0) ||
        (theta[k] >= upper[k] && gradient[k] < 0.0)) {
      pressed.push_back(static_cast<int>(k));
    }
  }
  return pressed;
}

void SolveWithinBounds(const ceres::Solver::Options& options, ceres::Problem* problem,
                       double* theta, const std::vector<double>& lower,
                       const std::vector<double>& upper, EvaluationCounter* counter,
                       ceres::Solver::Summary* summary, double* final_radius) {
  const int n = static_cast<int>(lower.size());
  std::vector<int> held;
  bool watch = true;  // off after a crawl that no pressed bound explains
  int used = 0;
  for (int round = 0;; ++round) {
    if (!held.empty()) problem->SetManifold(theta, new ceres::SubsetManifold(n, held));
    ceres::Solver::Options o = options;
    o.update_state_every_iteration = true;
    o.max_num_iterations = std::max(0, options.max_num_iterations - used);
    BoundCrawl crawl(theta, held, lower, upper);
    if (watch) o.callbacks.push_back(&crawl);
    // Ceres leaves the parameters at the run's start when the run is not
    // usable; with the state written every iteration they would hold its
    // last iterate instead.
    const std::vector<double> start(theta, theta + n);
    ceres::Solver::Summary run;
    SolveOptimistically(o, problem, theta, n, counter, &run, [&crawl] { crawl.Reset(); });
    if (!run.IsSolutionUsable()) std::copy(start.begin(), start.end(), theta);
    if (!held.empty()) problem->SetManifold(theta, nullptr);
    // A later round that fails leaves the earlier rounds' end standing
    // (θ is back there): its cost and termination are the summary's.
    const ceres::Solver::Summary before =
        round > 0 && !run.IsSolutionUsable() ? *summary : ceres::Solver::Summary();
    AppendRun(run, round == 0, summary);
    if (round > 0 && !run.IsSolutionUsable()) {
      summary->final_cost = before.final_cost;
      summary->termination_type = before.termination_type;
      summary->message = before.message;
      return;
    }
    if (final_radius != nullptr && run.IsSolutionUsable() && !run.iterations.empty()) {
      *final_radius = run.iterations.back().trust_region_radius;
    }
    used += static_cast<int>(run.iterations.size()) - 1;
    if (!run.IsSolutionUsable() || round + 1 >= kMaxRounds ||
        used >= options.max_num_iterations) {
      return;
    }
    // A caller's callback ended the run, or it ended by itself with
    // nothing held: its end stands.
    if (!crawl.crawled() && (held.empty() || run.termination_type == ceres::USER_SUCCESS ||
                             run.termination_type == ceres::USER_FAILURE)) {
      return;
    }
    const std::vector<int> pressed =
        PressedBounds(theta, Gradient(problem, options.num_threads), lower, upper);
    std::vector<int> next;
    if (crawl.crawled()) {
      // Hold what presses outward now; keep holding the held that still do.
      next = pressed;
    } else {
      // Release the held entries whose gradient turned inward.
      std::set_intersection(held.begin(), held.end(), pressed.begin(), pressed.end(),
                            std::back_inserter(next));
    }
    if (next == held) {
      if (!crawl.crawled()) return;
      watch = false;
    }
    // Every entry held: nothing left to solve for.
    if (static_cast<int>(next.size()) == n) return;
    held = std::move(next);
  }
}

}  // namespace axis
