// The sensor effects of MODEL.md §6–§7 in the simulator itself
// (sim/simulate.h), against the same run without them: sensor_bias adds
// b.<channel> to every sample; sensor_delay records the channel at
// t − tau_d.<channel> (the value at t = 0 before the start, the last one
// after the end). With tau_d a multiple of the RK4 step the delayed sample
// is an undelayed one, so both are compared to round-off. The low-pass
// against an independent integration of its ODE; the instant accelerometer
// against its definition from v and a fourth-order stencil.
#include <algorithm>
#include <utility>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "sim/axis_params.h"
#include "sim/simulate.h"

namespace axis {
namespace {

constexpr int kTach = static_cast<int>(Channel::kTach);

Trace<double> StepRun(const AxisStructure& s, const AxisParams<double>& p, double output_period,
                      std::vector<Channel> channels = {Channel::kTach, Channel::kV},
                      double step = 1e-5) {
  Drive drive;
  drive.input.kind = InputSignal::Kind::kStep;
  drive.input.amplitude = 10.0;
  drive.input.start = 0.01;
  SimulationOptions options;
  options.duration = 0.3;
  options.step = step;
  options.output_period = output_period;
  options.channels = std::move(channels);
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

// A negative τ_d advances the channel: the sample at t_k is the plain
// run's at t_k + 2.5 ms (a whole number of RK4 steps), the last one held.
TEST(SensorEffectsTest, NegativeDelayAdvancesItsChannel) {
  const AxisStructure plain;
  const AxisParams<double> p;
  AxisStructure advanced = plain;
  advanced.sensors.delay[kTach] = true;
  AxisParams<double> q = p;
  q.tau_d[kTach] = -0.0025;
  const Trace<double> fine = StepRun(plain, p, 5e-4);
  const Trace<double> d = StepRun(advanced, q, 1e-3);
  const std::vector<double>& tach = d[Channel::kTach];
  const std::vector<double>& ref = fine[Channel::kTach];
  ASSERT_EQ(tach.size(), 301u);
  for (size_t k = 0; k < tach.size(); ++k) {
    const size_t j = std::min(2 * k + 5, ref.size() - 1);
    EXPECT_NEAR(tach[k], ref[j], 1e-9) << k;
  }
}

// The filter in the simulator against an independent integration of its
// ODE (RK4 with 20 sub-steps per step on the linearly interpolated tach
// recorded at every step): agreement to 1e-6 of the signal (RK4's error
// at h/τ = 0.0125 per sub-step is ~1e-12; the interpolation is the same).
TEST(SensorEffectsTest, LowPassInTheSimulatorMatchesAnIndependentIntegration) {
  const AxisStructure plain;
  const AxisParams<double> p;
  const Trace<double> every_step = StepRun(plain, p, 1e-5);
  AxisStructure filtered = plain;
  filtered.sensors.lowpass2[kTach] = true;
  AxisParams<double> q = p;
  q.tau_lp2[kTach] = 4e-4;
  q.zeta_lp2[kTach] = 0.5;
  const Trace<double> f = StepRun(filtered, q, 1e-3);
  const std::vector<double>& s = every_step[Channel::kTach];
  const double h = 1e-5, tau = 4e-4, zeta = 0.5;
  double y = s[0], dy = 0.0, scale = 0.0;
  std::vector<double> out(s.size());
  out[0] = y;
  const int sub = 20;
  const double dt = h / sub;
  for (size_t n = 0; n + 1 < s.size(); ++n) {
    for (int m = 0; m < sub; ++m) {
      const auto input = [&](double frac) { return s[n] + frac * (s[n + 1] - s[n]); };
      const auto rhs = [&](double frac, double a, double b, double* da, double* db) {
        *da = b;
        *db = (input(frac) - a - 2 * zeta * tau * b) / (tau * tau);
      };
      const double f0 = static_cast<double>(m) / sub, f1 = (m + 0.5) / sub, f2 = (m + 1.0) / sub;
      double k1a, k1b, k2a, k2b, k3a, k3b, k4a, k4b;
      rhs(f0, y, dy, &k1a, &k1b);
      rhs(f1, y + 0.5 * dt * k1a, dy + 0.5 * dt * k1b, &k2a, &k2b);
      rhs(f1, y + 0.5 * dt * k2a, dy + 0.5 * dt * k2b, &k3a, &k3b);
      rhs(f2, y + dt * k3a, dy + dt * k3b, &k4a, &k4b);
      y += dt / 6 * (k1a + 2 * k2a + 2 * k3a + k4a);
      dy += dt / 6 * (k1b + 2 * k2b + 2 * k3b + k4b);
    }
    out[n + 1] = y;
    scale = std::max(scale, std::abs(s[n + 1]));
  }
  const std::vector<double>& tach = f[Channel::kTach];
  ASSERT_EQ(tach.size(), 301u);
  for (size_t k = 0; k < tach.size(); ++k) {
    EXPECT_NEAR(tach[k], out[100 * k], 1e-6 * scale) << k;
  }
}

// The instant accelerometer is (v(t_k + w) − v(t_k − w))/(2w) of the run's
// own v on the RK4 grid, w = instant_window in whole steps (MODEL.md §6).
TEST(SensorEffectsTest, InstantAccelerometerIsTheCentredMeanOfV) {
  AxisParams<double> p;
  const Trace<double> every = StepRun(AxisStructure{}, p, 1e-5, {Channel::kV, Channel::kA});
  const std::vector<double>& v = every[Channel::kV];
  for (const auto& [window, steps] : {std::pair{1e-4, 10}, std::pair{1e-5, 1}}) {
    AxisStructure s;
    s.accelerometer = AccelerometerSampling::kInstant;
    s.instant_window = window;
    const Trace<double> inst = StepRun(s, p, 1e-3, {Channel::kV, Channel::kA});
    ASSERT_EQ(inst[Channel::kA].size(), 301u);
    for (size_t k = 1; k + 1 < inst[Channel::kA].size(); ++k) {
      const size_t n = 100 * k;
      EXPECT_NEAR(inst[Channel::kA][k], (v[n + steps] - v[n - steps]) / (2.0 * window), 1e-9)
          << window << " " << k;
    }
  }
  // Without backlash y1' is smooth: the centred mean over ±10 µs is y1'(t_k)
  // to O(w^2 y1'''/6), checked against the fourth-order stencil of the same
  // v (y1' to O(h^4)): within 1e-3 of the largest |y1'|.
  AxisStructure s;
  s.accelerometer = AccelerometerSampling::kInstant;
  s.instant_window = 1e-5;
  AxisParams<double> smooth = p;
  smooth.H = 0.0;
  const Trace<double> v_smooth = StepRun(AxisStructure{}, smooth, 1e-5, {Channel::kV});
  const Trace<double> a_inst = StepRun(s, smooth, 1e-3, {Channel::kA});
  const std::vector<double>& w = v_smooth[Channel::kV];
  double peak = 0.0;
  for (double a : a_inst[Channel::kA]) peak = std::max(peak, std::abs(a));
  ASSERT_GT(peak, 1.0);
  for (size_t k = 2; k + 1 < a_inst[Channel::kA].size(); ++k) {
    const size_t n = 100 * k;
    const double fourth = (-w[n + 2] + 8 * w[n + 1] - 8 * w[n - 1] + w[n - 2]) / (12 * 1e-5);
    EXPECT_NEAR(a_inst[Channel::kA][k], fourth, 1e-3 * peak) << k;
  }
}

// The window belongs to the sensor: runs at RK4 steps of 10 and 20 µs see
// the same ±100 µs mean, within the two runs' integration difference (the
// largest difference of their v channels, over the window 2w).
TEST(SensorEffectsTest, InstantWindowDoesNotDependOnTheStep) {
  AxisStructure s;
  s.accelerometer = AccelerometerSampling::kInstant;
  s.instant_window = 1e-4;
  AxisParams<double> p;
  const Trace<double> fine = StepRun(s, p, 1e-3, {Channel::kV, Channel::kA}, 1e-5);
  const Trace<double> coarse = StepRun(s, p, 1e-3, {Channel::kV, Channel::kA}, 2e-5);
  ASSERT_EQ(fine[Channel::kA].size(), coarse[Channel::kA].size());
  double dv = 0.0, peak = 0.0;
  for (size_t k = 0; k < fine[Channel::kV].size(); ++k) {
    dv = std::max(dv, std::abs(fine[Channel::kV][k] - coarse[Channel::kV][k]));
    peak = std::max(peak, std::abs(fine[Channel::kA][k]));
  }
  ASSERT_GT(peak, 1.0);
  for (size_t k = 1; k + 1 < fine[Channel::kA].size(); ++k) {
    EXPECT_NEAR(fine[Channel::kA][k], coarse[Channel::kA][k], 2.0 * dv / 2e-4 + 1e-9 * peak)
        << k;
  }
}

}  // namespace
}  // namespace axis
