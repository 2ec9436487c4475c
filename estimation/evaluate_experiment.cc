#include "estimation/evaluate_experiment.h"

#include <algorithm>
#include <limits>
#include <vector>

#include "common/statistics.h"
#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"
#include "sim/channels.h"
#include "sim/simulate.h"

namespace axis {

ExperimentFit EvaluateExperiment(const AxisStructure& structure,
                                 const AxisParams<double>& params,
                                 const FitExperiment& e) {
  ExperimentFit out;
  out.name = e.name;
  out.role = e.role;
  out.t = e.t;
  const SimulationGrid grid = MakeGrid(e.options, e.drive);
  const Trace<double> trace =
      Simulate(structure, params, e.initial_state, e.drive, e.options, grid);
  // A record simulated past its last fitted sample (a tail left unfitted:
  // estimation/record_prefix.h) is compared over its samples only.
  std::vector<double> u = trace[Channel::kU];
  if (u.size() > e.t.size()) u.resize(e.t.size());
  for (size_t j = 0; j < e.measured_channels.size(); ++j) {
    const Channel c = e.measured_channels[j];
    ChannelFit f;
    f.channel = ChannelName(c);
    f.unit = ChannelUnit(c, structure.motion == Motion::kRotary);
    for (const FittedChannel& fc : e.fitted) {
      if (fc.channel == c) {
        f.fitted = true;
        f.sigma = fc.sigma;
      }
    }
    f.measured = e.measured[j];
    f.simulated = trace[c];
    if (f.simulated.size() > f.measured.size()) f.simulated.resize(f.measured.size());
    if (!trace.finite) {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      f.rms = f.fit_percent = f.max_error = f.mae = f.relative_error_percent = nan;
      f.ljung_box_q = f.ljung_box_p = nan;
      out.channels.push_back(f);
      continue;
    }
    std::vector<double> residual(f.measured.size());
    for (size_t k = 0; k < residual.size(); ++k) {
      residual[k] = f.simulated[k] - f.measured[k];
    }
    f.rms = Rms(f.measured, f.simulated);
    f.fit_percent = FitPercent(f.measured, f.simulated);
    f.max_error = MaxAbsError(f.measured, f.simulated);
    f.mae = MeanAbsError(f.measured, f.simulated);
    f.relative_error_percent = RelativeErrorPercent(f.measured, f.simulated);
    const int lags = std::min<int>(20, static_cast<int>(residual.size()) - 2);
    const LjungBox lb = LjungBoxTest(residual, lags);
    f.ljung_box_q = lb.q;
    f.ljung_box_lags = lb.lags;
    f.ljung_box_p = lb.p_value;
    const CrossCorrelation xc = PeakCrossCorrelation(residual, u, lags);
    f.input_xcorr_peak = xc.peak;
    f.input_xcorr_lag = xc.lag;
    out.channels.push_back(f);
  }
  return out;
}

}  // namespace axis
