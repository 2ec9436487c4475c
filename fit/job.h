// A fit job (configs/jobs/*.yaml): the model, the recorded experiments and
// how their columns map to MODEL.md §6 channels, which parameters are free,
// and the solver settings. One strict loader; the format is described in
// configs/README.md.
#ifndef FIT_JOB_H_
#define FIT_JOB_H_

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "fit/benchmark.h"
#include "fit/design_settings.h"
#include "fit/discovery_settings.h"
#include "fit/horizon_checkpoint.h"
#include "fit/published.h"
#include "sim/config.h"
#include "sim/simulate.h"

namespace axis {

class SharedLevel;  // fit/screen.h

// A fitted channel and the σ its residual is divided by (channel unit).
struct FittedChannel {
  Channel channel;
  double sigma = 1.0;
};

// One recorded experiment, loaded and cut to its window. Times are relative
// to the first sample in the window (the simulation starts there).
struct FitExperiment {
  std::string name;
  std::string role = "fit";  // "fit" or "validate"
  std::string data_path;
  Drive drive;                       // input or controller, times relative
  std::vector<double> t;             // s, relative, first = 0
  double t_offset = 0.0;             // s, absolute time of the first sample
  std::vector<Channel> measured_channels;
  std::vector<std::vector<double>> measured;  // per measured channel, per sample
  std::vector<FittedChannel> fitted;          // subset of measured_channels
  bool estimate_initial_state = false;  // y0, y1 free per experiment
  AxisState<double> initial_state = AxisState<double>::Zero();
  SimulationOptions options;  // duration, step, output period = data period
  // How data columns driving the experiment were read where the job did not
  // say (a piecewise-constant column held; fit/job.cc ParseDriveSignal), and
  // in the quick form the σ of each fitted channel (MakeQuickJob), one
  // sentence each naming the key or channel.
  std::vector<std::string> input_notes;

  // Measured samples of channel c (throws std::invalid_argument if absent).
  const std::vector<double>& Measured(Channel c) const;
};

// The longest sample period (s) of a record LoadFitJob accepts: slower than
// 50 Hz a record sees none of a servo axis's dynamics (the 5 ms controller,
// the gear resonance, T_p: milliseconds), and it is most likely one whose
// time column is in ms (1–20 kHz records then read as periods of 1–0.05).
constexpr double kMaxSamplePeriod = 0.02;

// A free parameter: a VisitParams name, its initial value and bounds.
// Positive parameters (lower > 0) are optimised as log(value); the others as
// value/scale.
struct FreeParameter {
  std::string name;
  std::string unit;
  double initial = 0.0;
  double lower = 0.0;
  double upper = 0.0;
  double scale = 1.0;
  bool log = false;
};

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
  // many `starts`, each a finalist (fit/fit.cc FitParameters;
  // FitResult::auto_starts_note).
  // Not with discovery on (its declared model is expected to miss an
  // effect) nor in the loop's refits; 0 never adds any.
  int auto_starts = 8;
  // Starts that fit the whole record: after the shorter horizons of the
  // continuation (every start), the `finalists` lowest there continue
  // (fit/fit.cc FitParameters); ≥ 1.
  int finalists = 2;
  double initial_trust_region_radius = 1.0;  // LM damping at the start (1/μ)
  // Horizon continuation (fit/fit.h): first window in s, doubled per stage
  // up to the whole record; 0 fits the whole record at once.
  double first_horizon = 0.05;
  int threads = 2;              // Ceres evaluation threads
  std::uint64_t seed = 1;       // for the random starts
  // Optimum check (fit/fit.h, FitParameters): rounds of probing the cost
  // around the estimate, each followed by a Levenberg–Marquardt run from the
  // lowest point found; 0 skips the check; at most 1 with discovery on.
  int probe_rounds = 8;
  // Local restarts after the probe rounds (fit/fit.cc): Levenberg–Marquardt
  // from the estimate ± this many standard deviations along every principal
  // axis of the covariance (2n runs, n = size of θ), repeated (at most 3
  // times) while one ends lower; 0 skips them. Need probe_rounds > 0;
  // skipped when discovery is enabled (fit/fit.cc).
  double local_starts = 3.0;
  bool progress = true;         // print one line per iteration
  // Set by the discovery loop (fit/discovery.cc), not a job key: a refit
  // that can no longer reach a BIC below this is stopped on a shorter
  // horizon (fit/fit.h FitParameters, FitResult::abandoned_horizon);
  // +inf never stops.
  double abandon_above_bic = std::numeric_limits<double>::infinity();
  // Set by the discovery loop's screen of its refits, not a job key: if
  // > 0, every start stops after the shorter horizon of this length (s) as
  // if it had passed abandon_above_bic there, the result carrying that
  // horizon and its BIC's lower bound; 0 fits to the end.
  double stop_after_horizon = 0.0;
  // Set by the discovery loop, not a job key: the shorter horizons this
  // job's screen ran (FitResult::checkpoint of the same job with
  // stop_after_horizon), which the fit takes as done and goes on after
  // (fit/fit.h FitParameters); null runs every stage.
  std::shared_ptr<const HorizonCheckpoint> resume;
  // Set by the force map's forms (fit/force_map.cc), not job keys: the
  // level of competing refits that run side by side (fit/screen.h
  // SharedLevel). publish_level: this fit publishes its BIC there when it
  // ends. pending_level: this fit stops as if abandon_above_bic were that
  // level (the lower of the two), its shorter horizons' bounds checked once
  // the level is published (waiting for it at the end if need be); one
  // start only (solver.starts 0, else FitParameters throws
  // std::invalid_argument).
  std::shared_ptr<SharedLevel> publish_level;
  std::shared_ptr<const SharedLevel> pending_level;
};

// How the estimate's uncertainty is computed (job key `uncertainty:`;
// fit/uncertainty.h). The report names the method. With discovery enabled
// the fits use Gauss–Newton whatever `method` says.
struct UncertaintySettings {
  enum class Method {
    kGaussNewton,      // ±t·σ from (JᵀJ)⁻¹ at the estimate
    kLikelihoodRatio,  // where the cost rises by ½t²s² along the profile
                       // directions (fit/uncertainty.h)
    kProfile,          // where the profile cost (the others refitted)
                       // rises by ½t²s² (fit/uncertainty.h)
  };
  // Default profile likelihood: on the issue 9 campaign (PRBS records,
  // README) it held the truth more often than the Gauss–Newton and
  // line-scan intervals (82–87 %, T_p 70 %), T_p most of all.
  Method method = Method::kProfile;
  // Residual bootstrap cross-check (fit/uncertainty.h): refits of the
  // fitted trace plus the residuals resampled in blocks of `block` samples
  // (0 = off).
  int bootstrap = 0;
  int block = 50;        // samples per bootstrap block (1 = i.i.d. resampling)
  std::uint64_t seed = 1;
};

struct FitJob {
  std::string path;
  std::string title;
  AxisConfig model;
  std::vector<FitExperiment> experiments;  // role "fit"
  std::vector<FitExperiment> validate;     // role "validate"
  std::vector<FreeParameter> free;
  SolverSettings solver;
  UncertaintySettings uncertainty;
  DiscoverySettings discover;  // `discover:` key (enabled if present)
  DesignSettings design;       // `design:` key (fit/experiment_design.h)
  PublishedReference published;  // `published:` key (fit/published.h)
  BenchmarkSettings benchmark;    // `benchmark:` key (fit/benchmark.h)
  // Set by the force-map step of the discovery loop (fit/force_map.h), not
  // a job key: λ (1/N²) of the roughness penalty ½λ‖D·f‖² on the second
  // differences of a free force map's values; 0 for none.
  double force_map_lambda = 0.0;
  // Weight (1/N²) of the rows that hold the map's components that a free
  // parameter produces exactly (its mean with F_0, its slope with B_a or
  // k_x; fit/force_map.h ConfoundedComponents) at zero; 0 for none.
  double force_map_anchor = 0.0;
  // With `current_loop: quasi_steady`: the shift of the estimate against
  // the full loop, in standard errors, past which fit-params refits with
  // the full loop (key simulation.full_loop_refit_above; fit/fit.h RunJob,
  // fit/current_loop_check.h); > 0, +inf never refits.
  double full_loop_refit_above = 1.0;
  std::string out_dir;  // from output.dir (relative to the job file) or --out
};

// How many initial states the job's fit estimates: 2 (y0, y1) per fitted
// experiment with `initial_state: estimate`; they follow the free
// parameters in θ (fit/fit.h FitParameters).
int EstimatedStateCount(const FitJob& job);

// Loads and checks a job: all files, columns and names are resolved here, so
// that fitting cannot fail on input. An experiment's `data:` is a CSV file,
// or a MAT file if its name ends in .mat (ReadDataTable, sim/data_table.h:
// variables are columns). Throws std::invalid_argument naming the file, line
// and key (YAML), file and line (CSV) or file and variable (MAT): unknown
// keys, a missing column, NaN or empty cells, time not strictly increasing,
// a sample period above kMaxSamplePeriod (time not in seconds), an empty
// file, a MAT variable that is not a vector as long as the time, a free
// parameter the model does not have, reversed bounds, an initial value
// outside its bounds, a fitted channel that is not measured, two
// experiments (fitted or validated) of the same name.
FitJob LoadFitJob(const std::string& path);

// Whether `name` may name outputs (an experiment's fit_<name>.csv, a
// benchmark criterion's folder): non-empty, of letters, digits, '_', '-',
// '.'. Never throws.
bool IsOutputName(const std::string& name);

// As LoadFitJob, from a parsed YAML document; `path` names it in messages
// and relative file names are resolved against `base_dir`.
FitJob ParseFitJob(const YAML::Node& root, const std::string& path,
                   const std::string& base_dir);

// The quick form of fit-params: one experiment from `data_path` (CSV, or MAT
// if named *.mat; time column "t", every other column whose name is a
// channel is measured), open loop
// with input column `input_column`, fitting `fit_channels` each with σ the
// noise estimated from its record (fit/statistics.h DifferenceNoiseSd),
// at least 1e-4 of the signal's standard deviation (a noise-free record),
// 1 for a constant channel, so that s² ≈ 1 at a fit down to the noise and the
// score tests of --discover mean what they say; each σ and how it was found
// is a note of the experiment (FitExperiment::input_notes, printed and
// reported). Frees `free_names` with initial values from the model and
// bounds [value/10, value·10]. Throws std::invalid_argument.
FitJob MakeQuickJob(const std::string& model_path, const std::string& data_path,
                    const std::string& input_column,
                    const std::vector<std::string>& fit_channels,
                    const std::vector<std::string>& free_names);

}  // namespace axis

#endif  // FIT_JOB_H_
