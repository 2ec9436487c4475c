// What steers one fit from inside the tool, apart from the user's solver
// settings (estimation/solver_settings.h): the discovery loop's early stops, its
// screen of refits and the resumption after it, and the shared level of
// competing refits run side by side (the force map's forms). A fit with the
// default FitControl runs as the job says. Passed to FitParameters
// (estimation/fit.h) and, one per job, to FitConcurrently.
#ifndef ESTIMATION_FIT_CONTROL_H_
#define ESTIMATION_FIT_CONTROL_H_

#include <limits>
#include <memory>

#include "estimation/horizon_checkpoint.h"
#include "estimation/shared_level.h"

namespace axis {

struct FitControl {
  // A refit that can no longer reach a BIC below this is stopped on a
  // shorter horizon (FitResult::abandoned_horizon); +inf never stops. Set
  // by the discovery loop (discovery/internal/discovery_loop.cc).
  double abandon_above_bic = std::numeric_limits<double>::infinity();
  // If > 0, every start stops after the shorter horizon of this length (s)
  // as if it had passed abandon_above_bic there, the result carrying that
  // horizon and its BIC's lower bound (a screen: discovery/internal/screen.h); 0 fits
  // to the end.
  double stop_after_horizon = 0.0;
  // If true, every start stops so after the last shorter horizon of its
  // continuation, before the whole record (where the continuation has no
  // shorter horizon the fit runs to the end): the discovery loop's starts
  // of one candidate, of which only the lowest there go on
  // (discovery/internal/discovery_loop.cc). Not with pending_level nor with
  // stop_after_horizon > 0 (FitParameters throws std::invalid_argument).
  bool stop_before_whole_record = false;
  // The shorter horizons this job's screen ran (FitResult::checkpoint of
  // the same job with stop_after_horizon or stop_before_whole_record),
  // which the fit takes as done and goes on after; null runs every stage.
  std::shared_ptr<const HorizonCheckpoint> resume;
  // The level of competing refits that run side by side (SharedLevel).
  // publish_level: this fit publishes its BIC there when it ends (also when
  // it throws: +inf). pending_level: this fit stops as if abandon_above_bic
  // were that level (the lower of the two), its shorter horizons' bounds
  // checked once the level is published (waiting for it at the end if need
  // be); one start only (solver.starts 0, no stop_after_horizon and no
  // stop_before_whole_record, else FitParameters throws
  // std::invalid_argument).
  std::shared_ptr<SharedLevel> publish_level;
  std::shared_ptr<const SharedLevel> pending_level;
};

}  // namespace axis

#endif  // ESTIMATION_FIT_CONTROL_H_
