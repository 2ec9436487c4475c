// A consumer of the installed servo_axis_id package (tests/install_test.sh):
// loads a model config through the sim library, simulates a 10 V step of
// the set-velocity voltage open loop for 1 s, and checks with the fit
// library's statistics that the arm settles at the paper's steady state,
// 0.09995 m/s per volt (MODEL.md; README "Where the reconstruction
// differs"). Usage: consumer MODEL.yaml. Exit 0 if it holds, 1 if not, 2 on
// bad input.
#include <cmath>
#include <cstdio>
#include <exception>
#include <vector>

#include "common/statistics.h"
#include "sim/config.h"
#include "sim/experiment.h"
#include "sim/simulate.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer MODEL.yaml\n");
    return 2;
  }
  try {
    axis::ExperimentConfig step;
    step.model = axis::LoadAxisConfig(argv[1]);
    step.drive.input.kind = axis::InputSignal::Kind::kStep;
    step.drive.input.amplitude = 10.0;  // V
    step.options.duration = 1.0;        // s
    step.options.step = 1e-5;           // s
    step.options.output_period = 1e-3;  // s
    step.options.channels = {axis::Channel::kV};
    const axis::Trace<double> trace = axis::RunExperiment(step);
    const std::vector<double>& v = trace[axis::Channel::kV];
    // The last 0.2 s against the steady state.
    const std::vector<double> tail(v.end() - 200, v.end());
    const std::vector<double> steady(tail.size(), 10.0 * 0.09995);
    const double error = axis::RelativeErrorPercent(steady, tail);
    std::printf("samples %zu, final v %.6f m/s, steady-state error %.4f %%\n", v.size(),
                v.back(), error);
    if (v.size() != 1001 || !trace.finite || !(error < 0.5)) {
      std::fprintf(stderr, "consumer: expected 1001 finite samples settling within 0.5 %% "
                           "of 0.9995 m/s\n");
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 2;
  }
  return 0;
}
