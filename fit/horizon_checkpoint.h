// What the shorter horizons of a fit's continuation left, so that a later
// fit of the same job can go on after them instead of running them again
// (fit/fit.h FitParameters; the discovery loop's screen of its refits and
// the refits after it, fit/discovery.cc).
#ifndef FIT_HORIZON_CHECKPOINT_H_
#define FIT_HORIZON_CHECKPOINT_H_

#include <vector>

namespace axis {

// Written by a fit stopped by solver.stop_after_horizon (FitResult::
// checkpoint), read by a fit given it as solver.resume. The points are in
// the internal coordinates of the job's free parameters (fit/fit.cc
// ParameterMap: log for positive parameters, then the estimated initial
// states), so a checkpoint belongs to one job: the same model, free
// parameters with their bounds and initial values, experiments and solver
// settings; only solver.abandon_above_bic, stop_after_horizon, threads and
// progress may differ. FitParameters throws std::invalid_argument for one
// whose shape (starts, size of θ, stages) does not fit the job.
struct HorizonCheckpoint {
  // A start after one stage (a horizon shorter than the whole record).
  struct StageEnd {
    std::vector<double> theta;  // its point after the stage (internal coordinates)
    double cost = 0.0;          // the stage's cost there (Ceres' final_cost)
    double start_cost = 0.0;    // the stage's cost at the start's own point
    bool usable = true;         // false: the stage failed and the start stopped
  };
  // [start][stage]: every start of the fit (the job's initial point, then
  // its solver.starts random ones), the stages it ran in order from the
  // first horizon; a start stops where the fit stopped it (the screen's
  // horizon, a failed stage, a start it joined).
  std::vector<std::vector<StageEnd>> starts;
};

}  // namespace axis

#endif  // FIT_HORIZON_CHECKPOINT_H_
