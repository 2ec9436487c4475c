// The sensor front end of MODEL.md §6 (sim/sensor_front_end.h): the
// low-pass filters against their closed-form ramp responses, their first-
// order branch against the exact one, autodiff of the time constant against
// central differences, a negative delay, and the instant accelerometer
// against its definition from v and against y1' where y1' is smooth.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "sim/axis_params.h"
#include "sim/config.h"
#include "sim/sensor_front_end.h"
#include "sim/simulate.h"
#include "sim/yaml_util.h"

namespace axis {
namespace {

constexpr int kA = static_cast<int>(Channel::kA);
constexpr int kTach = static_cast<int>(Channel::kTach);

std::vector<double> Ramp(double h, int n) {
  std::vector<double> s(n + 1);
  for (int k = 0; k <= n; ++k) s[k] = k * h;
  return s;
}

// A ramp is linear between grid points, so the discretisation is exact:
// the filtered ramp matches the closed form to round-off (1e-12 of t).
TEST(SensorFrontEndTest, FirstOrderRampMatchesTheClosedForm) {
  const double h = 1e-4, tau = 3.7e-4;
  const std::vector<double> y = LowPassOnGrid(Ramp(h, 200), h, 1, tau, 1.0);
  for (int k = 0; k <= 200; ++k) {
    const double t = k * h;
    EXPECT_NEAR(y[k], t - tau * (1.0 - std::exp(-t / tau)), 1e-12) << k;
  }
}

// y = t − 2ζτ + e^{−ζt/τ}·(2ζτ·cos ω_d t + (2ζ² − 1)/ω_d·sin ω_d t),
// ω_d = √(1 − ζ²)/τ (underdamped); critically damped t − 2τ + (t + 2τ)e^{−t/τ}.
TEST(SensorFrontEndTest, SecondOrderRampMatchesTheClosedForm) {
  const double h = 1e-4, tau = 2.5e-4;
  for (double zeta : {0.3, 1.0 / std::sqrt(2.0)}) {
    const std::vector<double> y = LowPassOnGrid(Ramp(h, 300), h, 2, tau, zeta);
    const double wd = std::sqrt(1.0 - zeta * zeta) / tau;
    for (int k = 0; k <= 300; ++k) {
      const double t = k * h;
      const double expected = t - 2 * zeta * tau +
                              std::exp(-zeta * t / tau) *
                                  (2 * zeta * tau * std::cos(wd * t) +
                                   (2 * zeta * zeta - 1) / wd * std::sin(wd * t));
      EXPECT_NEAR(y[k], expected, 1e-12) << "zeta " << zeta << " k " << k;
    }
  }
  const std::vector<double> y = LowPassOnGrid(Ramp(h, 300), h, 2, tau, 1.0);
  for (int k = 0; k <= 300; ++k) {
    const double t = k * h;
    EXPECT_NEAR(y[k], t - 2 * tau + (t + 2 * tau) * std::exp(-t / tau), 1e-12) << k;
  }
}

// At the switch to the first-order branch (τ = 10⁻³·h) both branches agree
// to the neglected second order: (τ/h)² of the signal's step-to-step change.
TEST(SensorFrontEndTest, FirstOrderBranchMeetsTheExactOne) {
  const double h = 1e-4;
  std::vector<double> s(400);
  for (size_t k = 0; k < s.size(); ++k) s[k] = std::sin(2 * M_PI * 50.0 * k * h);
  for (int order : {1, 2}) {
    const double tau = kFirstOrderTauFraction * h;
    const std::vector<double> below = LowPassOnGrid(s, h, order, tau * (1 - 1e-9), 0.7);
    const std::vector<double> above = LowPassOnGrid(s, h, order, tau * (1 + 1e-9), 0.7);
    const double change = 2 * M_PI * 50.0 * h;  // max |s_n − s_{n−1}|
    for (size_t k = 0; k < s.size(); ++k) {
      EXPECT_NEAR(below[k], above[k], 10 * kFirstOrderTauFraction * change) << order << " " << k;
    }
  }
}

// d/dτ by ceres::Jet against central differences (step 1e-4 of τ: the
// truncation error ~1e-8 relative), at τ in the exact branch; at τ = 0 the
// derivative is minus g times the grid's backward slope.
TEST(SensorFrontEndTest, TimeConstantDerivativeMatchesCentralDifferences) {
  using Jet = ceres::Jet<double, 1>;
  const double h = 1e-4;
  std::vector<double> s(300);
  for (size_t k = 0; k < s.size(); ++k) s[k] = std::sin(2 * M_PI * 80.0 * k * h) + 0.3 * k * h;
  std::vector<Jet> js(s.begin(), s.end());
  for (int order : {1, 2}) {
    for (double tau : {3e-5, 4e-4}) {
      const std::vector<Jet> y = LowPassOnGrid(js, h, order, Jet(tau, 0), Jet(0.6));
      const double d = 1e-4 * tau;
      const std::vector<double> up = LowPassOnGrid(s, h, order, tau + d, 0.6);
      const std::vector<double> down = LowPassOnGrid(s, h, order, tau - d, 0.6);
      for (size_t k = 0; k < s.size(); ++k) {
        const double fd = (up[k] - down[k]) / (2 * d);
        EXPECT_NEAR(y[k].v[0], fd, 1e-6 * (1.0 + std::abs(fd))) << order << " " << tau << " " << k;
      }
    }
    const std::vector<Jet> at0 = LowPassOnGrid(js, h, order, Jet(0.0, 0), Jet(0.6));
    const double g = order == 1 ? 1.0 : 1.2;
    for (size_t k = 1; k < s.size(); ++k) {
      EXPECT_DOUBLE_EQ(at0[k].a, s[k]);
      EXPECT_NEAR(at0[k].v[0], -g * (s[k] - s[k - 1]) / h, 1e-9) << k;
    }
  }
}

Trace<double> StepRun(const AxisStructure& s, const AxisParams<double>& p, double output_period,
                      std::vector<Channel> channels = {Channel::kTach, Channel::kV}) {
  Drive drive;
  drive.input.kind = InputSignal::Kind::kStep;
  drive.input.amplitude = 10.0;
  drive.input.start = 0.01;
  SimulationOptions options;
  options.duration = 0.3;
  options.step = 1e-5;
  options.output_period = output_period;
  options.channels = std::move(channels);
  return Simulate(s, p, AxisState<double>::Zero().eval(), drive, options,
                  MakeGrid(options, drive));
}

// A negative τ_d advances the channel: the sample at t_k is the plain
// run's at t_k + 2.5 ms (a whole number of RK4 steps), the last one held.
TEST(SensorFrontEndTest, NegativeDelayAdvancesItsChannel) {
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
TEST(SensorFrontEndTest, LowPassInTheSimulatorMatchesAnIndependentIntegration) {
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

// The instant accelerometer is (v(t_k + h) − v(t_k − h))/(2h) of the run's
// own v on the RK4 grid.
TEST(SensorFrontEndTest, InstantAccelerometerIsTheCentredMeanOfV) {
  AxisStructure s;
  s.accelerometer = AccelerometerSampling::kInstant;
  AxisParams<double> p;
  const Trace<double> every = StepRun(AxisStructure{}, p, 1e-5, {Channel::kV, Channel::kA});
  const Trace<double> inst = StepRun(s, p, 1e-3, {Channel::kV, Channel::kA});
  const std::vector<double>& v = every[Channel::kV];
  ASSERT_EQ(inst[Channel::kA].size(), 301u);
  for (size_t k = 1; k + 1 < inst[Channel::kA].size(); ++k) {
    const size_t n = 100 * k;
    EXPECT_NEAR(inst[Channel::kA][k], (v[n + 1] - v[n - 1]) / 2e-5, 1e-9) << k;
  }
  // Without backlash y1' is smooth: the centred mean is y1'(t_k) to
  // O(h^2 y1'''/6), checked against the fourth-order stencil of the same v
  // (y1' to O(h^4)): within 1e-3 of the largest |y1'|.
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

// The model config takes the front end: a negative delay, the first-order
// low-pass, the second-order one as τ or {tau, zeta}; written back and read
// again it is the same.
TEST(SensorFrontEndTest, ConfigReadsAndWritesTheFrontEnd) {
  std::ifstream in(std::string(PROJECT_SOURCE_DIR) + "/configs/axes/x_axis.yaml");
  const std::string model((std::istreambuf_iterator<char>(in)), {});
  const std::string text =
      model +
      "effects:\n"
      "  sensor_delay: {tach: -0.0004}\n"
      "  sensor_lowpass: {tach: 0.0004}\n"
      "  sensor_lowpass2: {a: {tau: 0.00064, zeta: 0.6}, v: 0.0002}\n";
  const AxisConfig c = ParseAxisConfig(ParseYamlText(text, "fe.yaml"), "fe.yaml");
  EXPECT_TRUE(c.structure.sensors.delay[kTach]);
  EXPECT_DOUBLE_EQ(c.params.tau_d[kTach], -0.0004);
  EXPECT_TRUE(c.structure.sensors.lowpass[kTach]);
  EXPECT_DOUBLE_EQ(c.params.tau_lp[kTach], 0.0004);
  EXPECT_TRUE(c.structure.sensors.lowpass2[kA]);
  EXPECT_DOUBLE_EQ(c.params.tau_lp2[kA], 0.00064);
  EXPECT_DOUBLE_EQ(c.params.zeta_lp2[kA], 0.6);
  const int kV = static_cast<int>(Channel::kV);
  EXPECT_DOUBLE_EQ(c.params.zeta_lp2[kV], 1.0 / std::sqrt(2.0));
  const AxisConfig again =
      ParseAxisConfig(ParseYamlText(AxisConfigToYaml(c), "again.yaml"), "again.yaml");
  EXPECT_EQ(EnabledEffectNames(again.structure), EnabledEffectNames(c.structure));
  EXPECT_DOUBLE_EQ(again.params.zeta_lp2[kA], 0.6);
  EXPECT_DOUBLE_EQ(again.params.tau_d[kTach], -0.0004);
  EXPECT_TRUE(IsFrontEndEffect("sensor_lowpass2.a"));
  EXPECT_FALSE(IsFrontEndEffect("coulomb"));
  const std::string bad = model + "effects:\n  sensor_lowpass: {tach: -1e-4}\n";
  EXPECT_THROW(ParseAxisConfig(ParseYamlText(bad, "bad.yaml"), "bad.yaml"),
               std::invalid_argument);
}

}  // namespace
}  // namespace axis
