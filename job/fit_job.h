// A fit job (configs/jobs/*.yaml): the model, the recorded experiments and
// how their columns map to MODEL.md §6 channels, which parameters are free,
// and the solver settings. One strict loader; the format is described in
// configs/README.md.
#ifndef JOB_FIT_JOB_H_
#define JOB_FIT_JOB_H_

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "job/benchmark_settings.h"
#include "job/design_settings.h"
#include "job/tune_settings.h"
#include "job/discovery_settings.h"
#include "job/published_reference.h"
#include "job/solver_settings.h"
#include "sim/config.h"
#include "sim/simulate.h"

namespace axis {


// A fitted channel and the σ its residual is divided by (channel unit).
struct FittedChannel {
  Channel channel;
  double sigma = 1.0;  // the channel's noise σ (channel unit), > 0
  // Per-sample σ_k (channel unit, one per sample, each ≥ sigma) where the
  // model itself is uncertain at some samples, else empty (σ_k = sigma):
  // set by the fit at its estimate, never by the job (estimation/
  // instant_sample_sigma.h, MODEL.md §6).
  std::vector<double> sample_sigma;
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
  // say (a piecewise-constant column held; job/load_fit_job.cc ParseDriveSignal), and
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
  DesignSettings design;       // `design:` key (design/experiment_design.h)
  TuneSettings tune;           // `tune:` key (tune/analog_loop_tuner.h)
  PublishedReference published;  // `published:` key (report/published.h)
  BenchmarkSettings benchmark;    // `benchmark:` key (run/benchmark.h)
  // Set by the force-map step of the discovery loop (discovery/force_map.h), not
  // a job key: λ (1/N²) of the roughness penalty ½λ‖D·f‖² on the second
  // differences of a free force map's values; 0 for none.
  double force_map_lambda = 0.0;
  // Weight (1/N²) of the rows that hold the map's components that a free
  // parameter produces exactly (its mean with F_0, its slope with B_a or
  // k_x; estimation/roughness_cost.h ConfoundedComponents) at zero; 0 for none.
  double force_map_anchor = 0.0;
  // With `current_loop: quasi_steady`: the shift of the estimate against
  // the full loop, in standard errors, past which fit-params refits with
  // the full loop (key simulation.full_loop_refit_above; run/job_run.h RunJob,
  // estimation/current_loop_check.h); > 0, +inf never refits.
  double full_loop_refit_above = 1.0;
  // How that refit gets its optimum check and intervals (key
  // simulation.full_loop_intervals; estimation/full_loop_refit.h):
  // kCarried, a local solve from the bias-corrected estimate whose
  // intervals are the quasi-steady fit's carried over (widened by the ratio
  // of the two models' Gauss–Newton standard errors where the full loop's
  // is larger); kRefitted, the job's
  // own optimum check and uncertainty method run again on the full loop
  // (ten times the cost per simulation).
  enum class FullLoopIntervals { kCarried, kRefitted };
  FullLoopIntervals full_loop_intervals = FullLoopIntervals::kCarried;
  std::string out_dir;  // from output.dir (relative to the job file) or --out
};

// How many initial states the job's fit estimates: 2 (y0, y1) per fitted
// experiment with `initial_state: estimate`; they follow the free
// parameters in θ (estimation/fit.h FitParameters).
int EstimatedStateCount(const FitJob& job);


}  // namespace axis

#endif  // JOB_FIT_JOB_H_
