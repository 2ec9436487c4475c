// The Ceres iteration callbacks of a fit (estimation/internal/fitter.h): the
// progress printer, the absolute-decrease stop of refits near a minimum,
// and the stop of a refit once a competing fit's level is published
// (estimation/shared_level.h). Internal to estimation/.
#ifndef ESTIMATION_INTERNAL_FIT_CALLBACKS_H_
#define ESTIMATION_INTERNAL_FIT_CALLBACKS_H_

#include <ostream>
#include <utility>
#include <vector>

#include <ceres/ceres.h>

#include "common/progress.h"
#include "estimation/shared_level.h"

namespace axis {

// Prints iteration, cost, relative decrease and step norm: one line per
// iteration, or on a terminal (ProgressStream) the detail of its status
// line. `plain_lines` false: nothing but that detail (the refits of the
// profile, which printed nothing before issue 14).
class ProgressPrinter : public ceres::IterationCallback {
 public:
  ProgressPrinter(std::ostream* out, int start, double horizon, bool plain_lines = true)
      : out_(out), progress_(AsProgressStream(out)), start_(start), horizon_(horizon),
        plain_lines_(plain_lines) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override;

 private:
  std::ostream* out_;
  ProgressStream* progress_;
  int start_;
  double horizon_;
  bool plain_lines_;
};

// Stops a Levenberg–Marquardt run once a successful step lowers the cost by
// less than `tolerance` (absolute): Ceres' function_tolerance is relative,
// and near a zero-residual optimum (noise-free records) the relative
// decrease stays large down to round-off.
class AbsoluteDecreaseStop : public ceres::IterationCallback {
 public:
  explicit AbsoluteDecreaseStop(double tolerance) : tolerance_(tolerance) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (s.iteration > 0 && s.step_is_successful && s.cost_change < tolerance_) {
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  double tolerance_;
};

// The first of a start's recorded (stage, BIC bound) pairs whose bound
// passed `above`, or null.
const std::pair<size_t, double>* FirstPassed(
    const std::vector<std::pair<size_t, double>>& bounds, double above);

// Ends a stage once FitControl::pending_level is published and a shorter
// stage's bound recorded before (`bounds`: (stage, bound)) passed it,
// together with `abandon_above` (the job's own level): the start stops at
// that stage, and what this one would still do is not needed.
class PendingLevelStop : public ceres::IterationCallback {
 public:
  PendingLevelStop(const SharedLevel* level, double abandon_above,
                   const std::vector<std::pair<size_t, double>>* bounds)
      : level_(level), abandon_above_(abandon_above), bounds_(bounds) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    const std::optional<double> level = level_->TryAbandonAbove();
    if (!level) return ceres::SOLVER_CONTINUE;
    return FirstPassed(*bounds_, std::min(abandon_above_, *level)) != nullptr
               ? ceres::SOLVER_TERMINATE_SUCCESSFULLY
               : ceres::SOLVER_CONTINUE;
  }

 private:
  const SharedLevel* const level_;
  const double abandon_above_;
  const std::vector<std::pair<size_t, double>>* const bounds_;
};


}  // namespace axis

#endif  // ESTIMATION_INTERNAL_FIT_CALLBACKS_H_
