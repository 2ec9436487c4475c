// The estimator's settings a user chooses: the solver (job key `solver:`)
// and the uncertainty (job key `uncertainty:`), each with its strict loader
// (io/settings_reader.h). What steers one fit from inside the tool (the
// discovery loop's levels, screens and resumes) is estimation/fit_control.h.
#ifndef ESTIMATION_SOLVER_SETTINGS_H_
#define ESTIMATION_SOLVER_SETTINGS_H_

#include <cstdint>

#include "io/settings_reader.h"
#include "io/yaml_util.h"

namespace axis {


// The s² (residual variance in units of the declared σ²) above which a fit
// from the job's start alone adds SolverSettings::auto_starts random
// starts, and above which the report warns (FitResult::residual_note): the
// residual RMS more than twice the noise the job declares. With the right
// minimum of the right model s² is 1 ± √(2/(m − n)) (0.02 for 4000
// samples) plus the model's own error; the wrong minima met on unseen data
// ended at s² = 95–575.
constexpr double kAutoStartsAbove = 4.0;

struct SolverSettings {
  int max_iterations = 100;
  double function_tolerance = 1e-8;   // relative cost change to stop
  double parameter_tolerance = 1e-8;  // relative step to stop
  double gradient_tolerance = 1e-10;
  int starts = 0;               // extra random starts (log-uniform in bounds)
  // Random starts added when `starts` is 0 and the job's own start ends the
  // continuation with s² = Σr²/(m − n) above kAutoStartsAbove (the residual
  // RMS more than twice the declared σ): the fit is run again with this
  // many `starts`, each a finalist (estimation/fit.cc FitParameters;
  // FitResult::auto_starts_note).
  // Not with discovery on (its declared model is expected to miss an
  // effect) nor in the loop's refits; 0 never adds any.
  int auto_starts = 8;
  // Starts that fit the whole record: after the shorter horizons of the
  // continuation (every start), the `finalists` lowest there continue
  // (estimation/fit.cc FitParameters); ≥ 1.
  int finalists = 2;
  double initial_trust_region_radius = 1.0;  // LM damping at the start (1/μ)
  // Horizon continuation (estimation/fit.h): first window in s, doubled per stage
  // up to the whole record; 0 fits the whole record at once.
  double first_horizon = 0.05;
  int threads = 2;              // Ceres evaluation threads
  std::uint64_t seed = 1;       // for the random starts
  // Optimum check (estimation/fit.h, FitParameters): rounds of probing the cost
  // around the estimate, each followed by a Levenberg–Marquardt run from the
  // lowest point found; 0 skips the check; at most 1 with discovery on.
  int probe_rounds = 8;
  // Local restarts after the probe rounds (estimation/fit.cc): Levenberg–Marquardt
  // from the estimate ± this many standard deviations along every principal
  // axis of the covariance (2n runs, n = size of θ), repeated (at most 3
  // times) while one ends lower; 0 skips them. Need probe_rounds > 0;
  // skipped when discovery is enabled, and where the probes showed the cost
  // quadratic out to their distance (ProbeRoundResult::quadratic_reach,
  // estimation/internal/fitter.cc LocalRestarts).
  double local_starts = 3.0;
  bool progress = true;         // print one line per iteration

  // The keys of `solver:` (io/settings_reader.h); `progress` is no key.
  template <typename Archive>
  void Serialize(Archive* a) {
    using Range = YamlMap::Range;
    a->Visit("max_iterations", &max_iterations, 1, 100000);
    a->Visit("function_tolerance", &function_tolerance, Range::kNonNegative);
    a->Visit("parameter_tolerance", &parameter_tolerance, Range::kNonNegative);
    a->Visit("gradient_tolerance", &gradient_tolerance, Range::kNonNegative);
    a->Visit("starts", &starts, 0, 10000);
    a->Visit("auto_starts", &auto_starts, 0, 10000);
    a->Visit("finalists", &finalists, 1, 10001);
    a->Visit("first_horizon", &first_horizon, Range::kNonNegative);
    a->Visit("initial_trust_region_radius", &initial_trust_region_radius, Range::kPositive);
    a->Visit("threads", &threads, 1, 256);
    a->Visit("probe_rounds", &probe_rounds, 0, 1000);
    a->Visit("local_starts", &local_starts, Range::kNonNegative);
    a->Visit("seed", &seed, 0, 1L << 62);
  }
};

// Reads the `solver:` mapping into `s` (its keys as SolverSettings::Serialize
// names them), then checks function_tolerance ≤ 0.01 (the optimum check
// counts a point as lower only beyond this relative tolerance: 1 or more
// would make it pass always) and finishes the map. Throws
// std::invalid_argument naming file, line and key (io/yaml_util.h).
void ReadSolverSettings(YamlMap* map, SolverSettings* s);

// How the estimate's uncertainty is computed (job key `uncertainty:`;
// estimation/uncertainty.h). The report names the method. With discovery enabled
// the fits use Gauss–Newton whatever `method` says.
struct UncertaintySettings {
  enum class Method {
    kGaussNewton,      // ±t·σ from (JᵀJ)⁻¹ at the estimate
    kLikelihoodRatio,  // where the cost rises by ½t²s² along the profile
                       // directions (estimation/uncertainty.h)
    kProfile,          // where the profile cost (the others refitted)
                       // rises by ½t²s² (estimation/uncertainty.h)
  };
  // Default profile likelihood: on the issue 9 campaign (PRBS records,
  // README) it held the truth more often than the Gauss–Newton and
  // line-scan intervals (82–87 %, T_p 70 %), T_p most of all.
  Method method = Method::kProfile;
  // Residual bootstrap cross-check (estimation/uncertainty.h): refits of the
  // fitted trace plus the residuals resampled in blocks of `block` samples
  // (0 = off).
  int bootstrap = 0;
  int block = 50;        // samples per bootstrap block (1 = i.i.d. resampling)
  std::uint64_t seed = 1;

  // The keys of `uncertainty:` (io/settings_reader.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("method", &method,
             {{"gauss_newton", Method::kGaussNewton},
              {"likelihood_ratio", Method::kLikelihoodRatio},
              {"profile", Method::kProfile}});
    a->Visit("bootstrap", &bootstrap, 0, 10000);
    a->Visit("block", &block, 1, 1000000);
    a->Visit("seed", &seed, 0, 1L << 62);
  }
};

// Reads the `uncertainty:` mapping into `u` and finishes it. Throws
// std::invalid_argument naming file, line and key (io/yaml_util.h).
void ReadUncertaintySettings(YamlMap* map, UncertaintySettings* u);

}  // namespace axis

#endif  // ESTIMATION_SOLVER_SETTINGS_H_
