#include "estimation/fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>

#include "common/concurrency.h"
#include "estimation/fit_control.h"
#include "estimation/fit_result.h"
#include "estimation/internal/fitter.h"
#include "estimation/shared_level.h"
#include "estimation/estimation_problem.h"
#include "estimation/solver_settings.h"

namespace axis {

FitResult FitParameters(const EstimationProblem& job, std::ostream* progress, const FitControl& control) {
  SharedLevel* publish = control.publish_level.get();
  if (publish == nullptr) return Fitter(job, control, progress).Run();
  // The fits waiting for this level must get one whatever happens here.
  try {
    FitResult result = Fitter(job, control, progress).Run();
    publish->Publish(result.abandoned_horizon == 0.0 && std::isfinite(result.bic)
                         ? result.bic
                         : std::numeric_limits<double>::infinity());
    return result;
  } catch (...) {
    publish->Publish(std::numeric_limits<double>::infinity());
    throw;
  }
}

void AsWarmRefit(EstimationProblem* job) {
  job->solver.starts = 0;
  job->solver.auto_starts = 0;
  job->solver.probe_rounds = 0;
  job->solver.first_horizon = 0.0;
  job->uncertainty.method = UncertaintySettings::Method::kGaussNewton;
  job->no_line_search = true;
}

std::vector<FitResult> FitConcurrently(
    const std::vector<EstimationProblem>& jobs, int threads, std::vector<double>* seconds,
    const std::vector<FitControl>& controls,
    const std::function<void(size_t done, size_t total)>& on_done) {
  const size_t n = jobs.size();
  if (!controls.empty() && controls.size() != n) {
    throw std::invalid_argument("FitConcurrently: expected no controls or one per job (" +
                                std::to_string(n) + "), got " +
                                std::to_string(controls.size()));
  }
  std::vector<FitResult> out(n);
  std::vector<double> wall(n, 0.0);
  const int at_once =
      static_cast<int>(std::min<size_t>(std::max(1, threads), std::max<size_t>(1, n)));
  // Twice the fair share of evaluation threads, at most all: while every
  // fit of the batch runs the cores are oversubscribed at most twofold, and
  // as the batch thins (its last refits run alone for tens of seconds:
  // the force map's slowest form, a discovery step's last candidate) the
  // fits still running use the cores the others freed.
  const int cores = std::max(1, threads);
  const int inner = std::min(cores, 2 * std::max(1, cores / at_once));
  const FitControl none;
  std::mutex done_lock;
  size_t done = 0;
  ForEachConcurrently(n, at_once, [&](size_t k) {
    const auto start = std::chrono::steady_clock::now();
    EstimationProblem job = jobs[k];
    job.solver.threads = inner;
    out[k] = FitParameters(job, nullptr, controls.empty() ? none : controls[k]);
    wall[k] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (on_done) {
      const std::lock_guard<std::mutex> hold(done_lock);
      on_done(++done, n);
    }
  });
  if (seconds != nullptr) *seconds = wall;
  return out;
}

}  // namespace axis
