// The time and evaluations of a fit's phases (FitResult::phases:
// starts, optimum check, local restarts, intervals, covariance,
// evaluation). Internal to estimation/.
#ifndef ESTIMATION_INTERNAL_PHASE_TIMER_H_
#define ESTIMATION_INTERNAL_PHASE_TIMER_H_

#include <chrono>
#include <string>

#include "estimation/experiment_cost.h"
#include "estimation/fit_result.h"

namespace axis {

// Adds `phase`'s time and evaluations to the phase of that name in
// result->phases (appended, in first-run order, if it has none yet).
void AddPhase(const FitPhase& phase, FitResult* result);

// Adds the wall time and evaluations between construction and destruction
// to the phase `name` of *result (FitResult::phases).
class PhaseTimer {
 public:
  PhaseTimer(const char* name, const EvaluationCounter& counter, FitResult* result)
      : name_(name), counter_(counter), result_(result),
        start_(std::chrono::steady_clock::now()),
        simulations_(counter.simulations), jacobians_(counter.jacobians) {}
  ~PhaseTimer() {
    AddPhase(FitPhase{name_,
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_)
                          .count(),
                      counter_.simulations - simulations_, counter_.jacobians - jacobians_},
             result_);
  }
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;

 private:
  std::string name_;
  const EvaluationCounter& counter_;
  FitResult* result_;
  std::chrono::steady_clock::time_point start_;
  int simulations_;
  int jacobians_;
};

}  // namespace axis

#endif  // ESTIMATION_INTERNAL_PHASE_TIMER_H_
