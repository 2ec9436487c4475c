#include "estimation/residual_bootstrap.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/progress.h"
#include "estimation/at_estimate.h"
#include "estimation/fit.h"
#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"
#include "estimation/parameter_tie.h"
#include "sim/random.h"

namespace axis {

void ResidualBootstrap(const EstimationProblem& job, FitResult* fit, std::ostream* progress) {
  const int replicates = job.uncertainty.bootstrap;
  if (replicates <= 0) return;
  if (fit->experiments.size() < job.experiments.size()) {
    throw std::invalid_argument("ResidualBootstrap: expected a fit of the job's " +
                                std::to_string(job.experiments.size()) +
                                " experiment(s), got " +
                                std::to_string(fit->experiments.size()));
  }
  const int n_free = static_cast<int>(job.free.size());
  EstimationProblem base = AtEstimate(job, *fit);  // the estimate and the estimated initial states
  AsWarmRefit(&base);
  base.solver.progress = false;
  base.uncertainty.bootstrap = 0;
  base.validate.clear();
  RandomEngine rng(job.uncertainty.seed);
  std::vector<std::vector<double>> values(n_free);
  int converged = 0;
  ProgressStream* status = job.solver.progress ? AsProgressStream(progress) : nullptr;
  if (status != nullptr) status->BeginPhase("bootstrap");
  for (int b = 0; b < replicates; ++b) {
    if (status != nullptr) {
      status->Status("bootstrap refit " + std::to_string(b + 1) + " of " +
                         std::to_string(replicates),
                     static_cast<double>(b) / replicates);
    }
    EstimationProblem replicate = base;
    for (size_t j = 0; j < job.experiments.size(); ++j) {
      FitExperiment& e = replicate.experiments[j];
      const ExperimentFit& f = fit->experiments[j];
      if (f.channels.size() != e.measured_channels.size()) {
        throw std::invalid_argument("ResidualBootstrap: expected " +
                                    std::to_string(e.measured_channels.size()) +
                                    " channels in experiment '" + e.name + "', got " +
                                    std::to_string(f.channels.size()));
      }
      for (size_t i = 0; i < e.measured_channels.size(); ++i) {
        const ChannelFit& c = f.channels[i];
        if (!c.fitted) continue;
        const size_t n = c.measured.size();
        const size_t block = std::min<size_t>(job.uncertainty.block, n);
        std::vector<double>& y = e.measured[i];
        for (size_t k = 0; k < n;) {
          const size_t s0 = UniformIndex(0, n - block, rng);
          for (size_t m = 0; m < block && k < n; ++m, ++k) {
            y[k] = c.simulated[k] + (c.measured[s0 + m] - c.simulated[s0 + m]);
          }
        }
      }
    }
    const FitResult r = FitParameters(replicate, nullptr);
    const bool ok = std::isfinite(r.final_cost);
    if (ok) {
      ++converged;
      for (int k = 0; k < n_free; ++k) values[k].push_back(r.parameters[k].value);
    }
    if (progress != nullptr && job.solver.progress) {
      *progress << "bootstrap refit " << b + 1 << "/" << replicates << ": cost "
                << r.final_cost << (ok ? "" : " (failed, dropped)") << "\n";
    }
  }
  fit->bootstrap_replicates = converged;
  for (int k = 0; k < n_free; ++k) {
    std::vector<double>& v = values[k];
    ParameterEstimate& p = fit->parameters[k];
    if (v.size() < 2) continue;
    double mean = 0.0;
    for (double x : v) mean += x / static_cast<double>(v.size());
    double var = 0.0;
    for (double x : v) var += (x - mean) * (x - mean) / static_cast<double>(v.size() - 1);
    p.std_error_bootstrap = std::sqrt(var);
    std::sort(v.begin(), v.end());
    // Percentiles by linear interpolation between order statistics.
    auto percentile = [&](double q) {
      const double pos = q * static_cast<double>(v.size() - 1);
      const size_t i = static_cast<size_t>(pos);
      const double f = pos - static_cast<double>(i);
      return i + 1 < v.size() ? v[i] + f * (v[i + 1] - v[i]) : v[i];
    };
    p.bootstrap_low = percentile(0.025);
    p.bootstrap_high = percentile(0.975);
  }
  CopyTiedUncertainty(fit);
}

}  // namespace axis
