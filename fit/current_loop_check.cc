#include "fit/current_loop_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "fit/discovery.h"
#include "fit/fit.h"
#include "fit/report.h"
#include "sim/channels.h"

namespace axis {

CurrentLoopCheck CheckCurrentLoop(const FitJob& job, const FitResult& result) {
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
  FitJob refit = AtEstimate(job, result);
  AxisStructure full = refit.model.structure;
  full.current_loop = CurrentLoop::kFull;
  try {
    for (FitExperiment& e : refit.experiments) {
      FitExperiment fine = e;
      fine.options.step = std::min(fine.options.step, kFullLoopStep);
      const ExperimentFit trace = EvaluateExperiment(full, refit.model.params, fine);
      for (size_t c = 0; c < e.measured_channels.size(); ++c) {
        const std::string name = ChannelName(e.measured_channels[c]);
        for (const ChannelFit& f : trace.channels) {
          if (f.channel == name && f.simulated.size() == e.measured[c].size()) {
            e.measured[c] = f.simulated;
          }
        }
      }
    }
    AsWarmRefit(&refit);
    refit.solver.progress = false;
    const FitResult moved = FitParameters(refit, nullptr);
    bool finite = false;
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
        finite = true;
        check.largest = std::max(check.largest, std::abs(check.shift_in_se[k]));
      }
    }
    if (!finite && !std::isfinite(moved.final_cost)) throw std::runtime_error("the refit failed");
  } catch (const std::exception& e) {
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
            "{step: 1.0e-5}) for estimates and intervals free of it";
    check.note = note.str();
  }
  return check;
}

}  // namespace axis
