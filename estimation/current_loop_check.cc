#include "estimation/current_loop_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/format.h"
#include "estimation/at_estimate.h"
#include "estimation/evaluate_experiment.h"
#include "estimation/fit.h"
#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"
#include "sim/channels.h"
#include "sim/preflight.h"

namespace axis {

EstimationProblem WithFullLoop(const EstimationProblem& job, double* step) {
  EstimationProblem full = job;
  full.model.structure.current_loop = CurrentLoop::kFull;
  const Rk4StabilityLimit limit = Rk4StabilityLimitOf(full.model.structure, full.model.params);
  const double largest = std::min(kFullLoopStep, kFullLoopStabilityMargin * limit.max_step);
  if (!(limit.max_step > 0.0) || !(largest >= kMinFullLoopStep)) {
    std::ostringstream why;
    why << "the full current loop is stable here only below an RK4 step of "
        << FormatNumber(limit.max_step, 3) << " s (eigenvalue "
        << FormatNumber(limit.eigenvalue.real(), 3) << " 1/s); expected at least "
        << FormatNumber(kMinFullLoopStep / kFullLoopStabilityMargin, 3) << " s";
    throw std::runtime_error(why.str());
  }
  double smallest = largest;
  for (std::vector<FitExperiment>* list : {&full.experiments, &full.validate}) {
    for (FitExperiment& e : *list) {
      // The job's step divides the sample period and, in closed loop, the
      // controller's period T_s: a whole fraction of it divides both.
      const double steps = std::ceil(e.options.step / largest * (1.0 - 1e-12));
      e.options.step /= std::max(1.0, steps);
      smallest = std::min(smallest, e.options.step);
    }
  }
  if (step != nullptr) *step = smallest;
  return full;
}

CurrentLoopCheck CheckCurrentLoop(const EstimationProblem& job, const FitResult& result) {
  CurrentLoopCheck check;
  const AxisStructure& s = job.model.structure;
  if (s.amplifier != Amplifier::kAnalogVelocityLoop ||
      s.current_loop != CurrentLoop::kQuasiSteady || result.parameters.empty()) {
    return check;
  }
  check.ran = true;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const size_t n_free = job.free.size();
  for (const FreeParameter& f : job.free) check.names.push_back(f.name);
  check.shift.assign(n_free, nan);
  check.shift_in_se.assign(n_free, nan);
  // The quasi-steady job at the estimate, its fitted records replaced by the
  // full loop's noise-free traces there.
  EstimationProblem refit = AtEstimate(job, result);
  try {
    const EstimationProblem full = WithFullLoop(refit, &check.full_step);
    for (size_t i = 0; i < refit.experiments.size(); ++i) {
      FitExperiment& e = refit.experiments[i];
      const ExperimentFit trace =
          EvaluateExperiment(full.model.structure, full.model.params, full.experiments[i]);
      for (size_t c = 0; c < e.measured_channels.size(); ++c) {
        const std::string name = ChannelName(e.measured_channels[c]);
        for (const ChannelFit& f : trace.channels) {
          if (f.channel != name) continue;
          if (f.simulated.size() != e.measured[c].size()) {
            throw std::runtime_error("the full loop's " + name + " trace of " + e.name +
                                     " has another length than the record");
          }
          for (double v : f.simulated) {
            if (!std::isfinite(v)) {
              throw std::runtime_error("the full loop's " + name + " trace of " + e.name +
                                       " leaves the finite numbers");
            }
          }
          e.measured[c] = f.simulated;
        }
      }
    }
    AsWarmRefit(&refit);
    // The refit's minimum lies a shift of about a standard error from the
    // estimate it starts at: Gauss–Newton steps from the start, as a local
    // restart runs (EstimationProblem::start_near_minimum).
    refit.start_near_minimum = true;
    refit.solver.progress = false;
    const FitResult moved = FitParameters(refit, nullptr);
    if (!std::isfinite(moved.final_cost)) {
      throw std::runtime_error("the quasi-steady refit to the full loop's traces failed (" +
                               moved.termination + ")");
    }
    for (size_t k = 0; k < n_free; ++k) {
      double before = nan, after = nan, se = nan;
      for (const ParameterEstimate& p : result.parameters) {
        if (p.name == check.names[k]) {
          before = p.value;
          se = p.std_error;
        }
      }
      for (const ParameterEstimate& p : moved.parameters) {
        if (p.name == check.names[k]) after = p.value;
      }
      check.shift[k] = after - before;
      check.shift_in_se[k] = se > 0.0 ? check.shift[k] / se : nan;
      if (std::isfinite(check.shift_in_se[k])) {
        check.measured = true;
        check.largest = std::max(check.largest, std::abs(check.shift_in_se[k]));
      }
    }
  } catch (const std::exception& e) {
    check.shift.assign(n_free, nan);
    check.shift_in_se.assign(n_free, nan);
    check.largest = 0.0;
    check.measured = false;
    check.note = std::string("the quasi-steady current loop could not be checked against the "
                             "full loop at the estimate: ") + e.what();
    return check;
  }
  if (check.largest > kLoopShiftNote) {
    std::ostringstream note;
    note << "the quasi-steady current loop shifts the estimate by up to "
         << FormatNumber(check.largest, 3) << " standard errors against the full loop on these "
         << "records (";
    bool first = true;
    for (size_t k = 0; k < n_free; ++k) {
      if (!(std::abs(check.shift_in_se[k]) > kLoopShiftNote)) continue;
      note << (first ? "" : ", ") << check.names[k] << " " << FormatNumber(check.shift_in_se[k], 3);
      first = false;
    }
    note << "; the quasi-steady fit of the full loop's trace at the estimate, minus the "
            "estimate): fit the full loop (configuration: {current_loop: full}, simulation: "
            "{step: "
         << FormatNumber(check.full_step, 3)
         << ", quasi_steady_screen: off}) for estimates and intervals free of it";
    check.note = note.str();
  }
  return check;
}

}  // namespace axis
