// What the shorter horizons of a fit's continuation left, so that a later
// fit of the same job can go on after them instead of running them again
// (estimation/fit.h FitParameters; the discovery loop's screen of its refits and
// the refits after it, discovery/internal/discovery_loop.cc).
#ifndef ESTIMATION_HORIZON_CHECKPOINT_H_
#define ESTIMATION_HORIZON_CHECKPOINT_H_

#include <vector>

namespace axis {

// Written by a fit stopped by control.stop_after_horizon or
// control.stop_before_whole_record (FitResult::checkpoint), read by a fit
// given it as control.resume. The points are in
// the internal coordinates of the job's free parameters (estimation/fit.cc
// ParameterMap: log for positive parameters, then the estimated initial
// states), so a checkpoint belongs to one job: the same model, free
// parameters with their bounds and initial values, experiments and solver
// settings; only control.abandon_above_bic, stop_after_horizon,
// stop_before_whole_record, threads and progress may differ. FitParameters throws std::invalid_argument for one
// that does not fit the job: another number of starts or size of θ, other
// start points (initial values, bounds, seed), other horizons, more stages
// than the job's shorter ones, or another cost at the first start on the
// first horizon (other data or model; relative tolerance 1e-9, for a cost
// summed on another number of threads).
struct HorizonCheckpoint {
  // A start after one stage (a horizon shorter than the whole record).
  struct StageEnd {
    std::vector<double> theta;  // its point after the stage (internal coordinates)
    double cost = 0.0;          // the stage's cost there (Ceres' final_cost)
    double start_cost = 0.0;    // the stage's cost at the start's own point
    bool usable = true;         // false: the stage failed and the start stopped
    // The trust-region radius its solve ended with, which the next stage
    // starts from (estimation/internal/fitter.h StartRun::radius); 0: the
    // job's initial_trust_region_radius.
    double radius = 0.0;
  };
  struct Start {
    std::vector<double> point;     // where it started (internal coordinates)
    std::vector<StageEnd> stages;  // the stages it ran, in order from the first
  };
  // The horizons (s) of the job's stages shorter than the whole record.
  std::vector<double> horizons;
  // Every start of the fit (the job's initial point, then its
  // solver.starts random ones); a start's stages end where the fit stopped
  // it (the screen's horizon, a failed stage, a start it joined).
  std::vector<Start> starts;
};

}  // namespace axis

#endif  // ESTIMATION_HORIZON_CHECKPOINT_H_
