// What the estimator estimates (estimation/fit.h FitParameters): the model,
// the recorded experiments mapped to its channels, the free parameters with
// their bounds, and the options of the fit (solver, uncertainty, the cost's
// roughness penalty). Nothing of the layers above: a fit job
// (run/fit_job.h) holds one of these beside the settings of discovery,
// design, tuning and reporting. As acados's OCP description holds its
// solver options, the problem holds its own, so that a refit is a copy with
// a change (estimation/fit.h AsWarmRefit).
#ifndef ESTIMATION_ESTIMATION_PROBLEM_H_
#define ESTIMATION_ESTIMATION_PROBLEM_H_

#include <string>
#include <vector>

#include "estimation/parameter_tie.h"
#include "estimation/solver_settings.h"
#include "sim/auto_step.h"
#include "sim/axis_config.h"
#include "sim/channels.h"
#include "sim/simulate.h"

namespace axis {

// A fitted channel and the σ its residual is divided by (channel unit).
struct FittedChannel {
  Channel channel;
  double sigma = 1.0;  // the channel's noise σ (channel unit), > 0
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
  // say (a piecewise-constant column held; run/load_fit_job.cc ParseDriveSignal), and
  // in the quick form the σ of each fitted channel (MakeQuickJob), one
  // sentence each naming the key or channel.
  std::vector<std::string> input_notes;

  // Measured samples of channel c (throws std::invalid_argument if absent).
  const std::vector<double>& Measured(Channel c) const;
};

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

// The roughness penalty ½λ‖D·f‖² + ½a‖C·f‖² of a free force map
// (estimation/roughness_cost.h): part of the cost, set by the force-map
// step of the discovery loop (discovery/force_map.h) for the fits it asks
// for; zero for none.
struct RoughnessPenalty {
  // λ (1/N²) on the second differences of the map's values.
  double lambda = 0.0;
  // Weight (1/N²) of the rows that hold the map's components that a free
  // parameter produces exactly (its mean with F_0, its slope with B_a or
  // k_x; estimation/roughness_cost.h ConfoundedComponents) at zero.
  double anchor = 0.0;
};

struct EstimationProblem {
  std::string path;  // the file the problem came from (for messages), or ""
  AxisConfig model;
  std::vector<FitExperiment> experiments;  // role "fit"
  std::vector<FitExperiment> validate;     // role "validate"
  std::vector<FreeParameter> free;
  // Parameters that take another's value (job key `tie:`;
  // estimation/parameter_tie.h): never free, kept equal to their source
  // wherever the fit sets parameters.
  std::vector<ParameterTie> ties;
  SolverSettings solver;
  UncertaintySettings uncertainty;
  RoughnessPenalty roughness;
  // An exploratory fit, of a model expected to miss an effect (the declared
  // model and the refits of a search for what it misses): no automatic
  // random starts, at most one probe round of the optimum check, no local
  // restarts, and Gauss–Newton intervals whatever uncertainty.method says
  // (estimation/internal/fitter.cc ChooseChecks), each of which would cost a few
  // hundred simulations on a model about to change.
  bool exploratory = false;
  // The free parameters' initial values lie next to the minimum (a refit
  // from a nearby estimate: estimation/full_loop_refit.h): the start runs
  // as the local restarts do, from Ceres' default trust region (nearly
  // Gauss–Newton steps) and without the projected line search that costs a
  // second Jacobian per iteration (estimation/internal/fitter.cc
  // SetSolverOptions); solver.initial_trust_region_radius is not used.
  bool start_near_minimum = false;
  // The solve runs without Ceres' projected line search along each
  // trust-region step (estimation/internal/fitter.cc SetSolverOptions): one
  // Jacobian per iteration instead of two. For refits that start at an
  // estimate, or at one with an effect added or a delay freed
  // (estimation/fit.h AsWarmRefit); unlike start_near_minimum the first
  // horizon's first steps stay damped by solver.initial_trust_region_radius
  // (the longer horizons go on from the trust region it ended with,
  // docs/numerics.md "Horizon continuation"; a delay freed
  // at 0 may sit several samples from its minimum: with Ceres' default
  // radius the sampling check's refit of a 5-sample delay jumped to another
  // minimum). start_near_minimum implies it.
  bool no_line_search = false;
};

// The longest output period (s) of the experiments of `problem` that fit
// channel `c`, 0 if none fits it. Never throws.
double FittedPeriod(const EstimationProblem& problem, Channel c);

// The experiment of `list` named `name`, or nullptr. Never throws.
const FitExperiment* FindExperiment(const std::vector<FitExperiment>& list,
                                    const std::string& name);

// How many initial states the problem's fit estimates: 2 (y0, y1) per
// fitted experiment with `initial_state: estimate`; they follow the free
// parameters in θ (estimation/fit.h FitParameters).
int EstimatedStateCount(const EstimationProblem& problem);

// The ranges the free parameters take (their bounds), and a parameter tied
// to a free one its source's (EstimationProblem::ties): what the automatic
// step's limit is taken over (sim/auto_step.h AutoStepLimit). Never throws
// but std::bad_alloc.
std::vector<ParameterRange> FreeParameterRanges(const EstimationProblem& problem);

}  // namespace axis

#endif  // ESTIMATION_ESTIMATION_PROBLEM_H_
