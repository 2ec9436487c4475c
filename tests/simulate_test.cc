// Simulate (sim/simulate.h): the open-loop input looked up at the RK4 stage
// times (Drive::stage_inputs) gives the very trace its evaluation gives.
#include <algorithm>
#include <cmath>
#include <memory>
#include <type_traits>
#include <vector>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "sim/simulate.h"

namespace axis {
namespace {

using Jet2 = ceres::Jet<double, 2>;

// A recorded input column as a fit reads it: ±5 V at 2 Hz sampled at 1 kHz,
// interpolated linearly between the samples (so every stage time needs a
// table lookup and a division), 0.6 s of the X axis with the paper's values:
// the velocity reverses twice and crosses the backlash (events located
// inside steps), the preamp saturates near the crests.
Drive SampledSineDrive() {
  Drive drive;
  drive.input.kind = InputSignal::Kind::kTable;
  for (int k = 0; k <= 600; ++k) {
    const double t = 1e-3 * k;
    drive.input.times.push_back(t);
    drive.input.values.push_back(5.0 * std::sin(2.0 * M_PI * 2.0 * t));
  }
  return drive;
}

SimulationOptions Options() {
  SimulationOptions options;
  options.duration = 0.6;
  options.step = 1e-5;
  options.output_period = 1e-3;
  options.channels = {Channel::kU, Channel::kA, Channel::kTach, Channel::kI, Channel::kX};
  return options;
}

template <typename T>
AxisParams<T> ParamsWithDerivatives() {
  AxisParams<T> p = AxisParams<double>().cast<T>();
  if constexpr (!std::is_same<T, double>::value) {
    p.B_a.v[0] = 1.0;  // two unknowns carry derivative parts, as in a fit
    p.k_g.v[1] = 1.0;
  }
  return p;
}

template <typename T>
void ExpectSameTrace(const Trace<T>& a, const Trace<T>& b, const SimulationOptions& o) {
  ASSERT_EQ(a.t.size(), b.t.size());
  for (Channel c : o.channels) {
    ASSERT_EQ(a[c].size(), b[c].size());
    for (size_t k = 0; k < a[c].size(); ++k) {
      if constexpr (std::is_same<T, double>::value) {
        ASSERT_EQ(a[c][k], b[c][k]) << ChannelName(c) << " sample " << k;
      } else {
        ASSERT_EQ(a[c][k].a, b[c][k].a) << ChannelName(c) << " sample " << k;
        ASSERT_EQ(a[c][k].v[0], b[c][k].v[0]) << ChannelName(c) << " sample " << k;
        ASSERT_EQ(a[c][k].v[1], b[c][k].v[1]) << ChannelName(c) << " sample " << k;
      }
    }
  }
}

template <typename T>
void CheckLookupGivesTheSameTrace() {
  const AxisStructure structure;  // gear coupling with backlash: events
  const AxisParams<T> p = ParamsWithDerivatives<T>();
  const SimulationOptions options = Options();
  Drive evaluated = SampledSineDrive();
  const SimulationGrid grid = MakeGrid(options, evaluated);
  Drive looked_up = evaluated;
  looked_up.stage_inputs = MakeStageInputs(looked_up, grid);
  ASSERT_NE(looked_up.stage_inputs, nullptr);
  const AxisState<T> y0 = AxisState<T>::Zero();
  const Trace<T> a = Simulate(structure, p, y0, evaluated, options, grid);
  const Trace<T> b = Simulate(structure, p, y0, looked_up, options, grid);
  ASSERT_TRUE(a.finite);
  ExpectSameTrace(a, b, options);

  // Each of the three columns is what the simulation reads at its stage:
  // one of them scaled by 1.01 changes the trace.
  const std::shared_ptr<const StageInputs> sampled = looked_up.stage_inputs;
  for (int column = 0; column < 3; ++column) {
    auto other = std::make_shared<StageInputs>(*sampled);
    std::vector<double>* v = column == 0   ? &other->at_start
                             : column == 1 ? &other->at_half
                                           : &other->at_end;
    for (double& u : *v) u *= 1.01;
    looked_up.stage_inputs = other;
    const Trace<T> c = Simulate(structure, p, y0, looked_up, options, grid);
    double largest = 0.0;
    for (size_t k = 0; k < a[Channel::kTach].size(); ++k) {
      largest = std::max(largest, std::abs(ScalarValue(c[Channel::kTach][k]) -
                                           ScalarValue(a[Channel::kTach][k])));
    }
    EXPECT_GT(largest, 1e-5) << "column " << column;  // V; the tach reaches about 0.5 V
  }
}

TEST(SimulateTest, StageInputLookupGivesTheSameTraceInDouble) {
  CheckLookupGivesTheSameTrace<double>();
}

TEST(SimulateTest, StageInputLookupGivesTheSameTraceInJet) {
  CheckLookupGivesTheSameTrace<Jet2>();
}

// A table sampled on another step (as many entries as the grid), or too
// short for the grid, is not used (the trace is still the evaluated
// input's), and held, step or closed-loop drives get none.
TEST(SimulateTest, StageInputsOfAnotherGridAreIgnored) {
  const AxisStructure structure;
  const AxisParams<double> p;
  const SimulationOptions options = Options();
  Drive evaluated = SampledSineDrive();
  const SimulationGrid grid = MakeGrid(options, evaluated);
  const Trace<double> a = Simulate(structure, p, AxisState<double>::Zero().eval(), evaluated,
                                   options, grid);
  SimulationOptions coarse = options;
  coarse.step = 2e-5;
  coarse.duration = 1.2;  // as many entries as the grid: only the step differs
  Drive wrong_step = evaluated;
  wrong_step.stage_inputs = MakeStageInputs(wrong_step, MakeGrid(coarse, wrong_step));
  ExpectSameTrace(a, Simulate(structure, p, AxisState<double>::Zero().eval(), wrong_step,
                              options, grid), options);
  SimulationOptions shorter = options;
  shorter.duration = 0.3;
  Drive too_short = evaluated;
  too_short.stage_inputs = MakeStageInputs(too_short, MakeGrid(shorter, too_short));
  ExpectSameTrace(a, Simulate(structure, p, AxisState<double>::Zero().eval(), too_short,
                              options, grid), options);

  Drive held = evaluated;
  held.input.hold = true;
  EXPECT_EQ(MakeStageInputs(held, grid), nullptr);
  Drive step;
  step.input.kind = InputSignal::Kind::kStep;
  EXPECT_EQ(MakeStageInputs(step, grid), nullptr);
  Drive closed = evaluated;
  closed.closed_loop = true;
  EXPECT_EQ(MakeStageInputs(closed, grid), nullptr);
}

}  // namespace
}  // namespace axis
