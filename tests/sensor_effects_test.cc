// The sensor effects of MODEL.md §7 in the simulator itself (sim/simulate.h),
// against the same run without them: sensor_bias adds b.<channel> to every
// sample; sensor_delay records the channel at t − tau_d.<channel> (the value
// at t = 0 before the start). With tau_d a multiple of the RK4 step the
// delayed sample is an undelayed one, so both are compared to round-off.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "sim/axis_params.h"
#include "sim/simulate.h"

namespace axis {
namespace {

constexpr int kTach = static_cast<int>(Channel::kTach);

Trace<double> StepRun(const AxisStructure& s, const AxisParams<double>& p, double output_period) {
  Drive drive;
  drive.input.kind = InputSignal::Kind::kStep;
  drive.input.amplitude = 10.0;
  drive.input.start = 0.01;
  SimulationOptions options;
  options.duration = 0.3;
  options.step = 1e-5;
  options.output_period = output_period;
  options.channels = {Channel::kTach, Channel::kV};
  return Simulate(s, p, AxisState<double>::Zero().eval(), drive, options,
                  MakeGrid(options, drive));
}

TEST(SensorEffectsTest, BiasAddsItsValueToItsChannelOnly) {
  const AxisStructure plain;
  const AxisParams<double> p;
  AxisStructure biased = plain;
  biased.sensors.bias[kTach] = true;
  AxisParams<double> q = p;
  q.b[kTach] = 0.05;
  const Trace<double> a = StepRun(plain, p, 1e-3), b = StepRun(biased, q, 1e-3);
  ASSERT_EQ(a[Channel::kTach].size(), 301u);
  for (size_t k = 0; k < a[Channel::kTach].size(); ++k) {
    EXPECT_NEAR(b[Channel::kTach][k], a[Channel::kTach][k] + 0.05, 1e-15) << k;
    EXPECT_EQ(b[Channel::kV][k], a[Channel::kV][k]) << k;
  }
}

TEST(SensorEffectsTest, DelayShiftsItsChannelByTauD) {
  const AxisStructure plain;
  const AxisParams<double> p;
  AxisStructure delayed = plain;
  delayed.sensors.delay[kTach] = true;
  AxisParams<double> q = p;
  // 2.5 ms: half an output period beyond two, a whole number of RK4 steps;
  // the undelayed reference is recorded at 2 kHz.
  q.tau_d[kTach] = 0.0025;
  const Trace<double> fine = StepRun(plain, p, 5e-4);
  const Trace<double> d = StepRun(delayed, q, 1e-3);
  const std::vector<double>& tach = d[Channel::kTach];
  const std::vector<double>& ref = fine[Channel::kTach];
  ASSERT_EQ(tach.size(), 301u);
  ASSERT_EQ(ref.size(), 601u);
  double scale = 0.0;
  for (double x : ref) scale = std::max(scale, std::abs(x));
  ASSERT_GT(scale, 0.1);
  for (size_t k = 0; k < tach.size(); ++k) {
    // t_k − 2.5 ms = t_{2k−5} of the 2 kHz grid; before the start, y(0).
    const double expected = 2 * k >= 5 ? ref[2 * k - 5] : ref[0];
    EXPECT_NEAR(tach[k], expected, 1e-9 * scale) << k;
    EXPECT_EQ(d[Channel::kV][k], fine[Channel::kV][2 * k]) << k;
  }
}

}  // namespace
}  // namespace axis
