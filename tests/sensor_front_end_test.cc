// The sensor front end of MODEL.md §6 (sim/sensor_front_end.h): the
// low-pass filters against their closed-form ramp responses, their first-
// order branch against the exact one, autodiff of the time constant against
// central differences, and the model config's keys. In the simulator:
// tests/sensor_effects_test.cc.
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
#include "io/yaml_util.h"

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
  EXPECT_TRUE(IsFrontEndEffect("accelerometer.instant"));
  EXPECT_FALSE(IsFrontEndEffect("coulomb"));
  const std::string bad = model + "effects:\n  sensor_lowpass: {tach: -1e-4}\n";
  EXPECT_THROW(ParseAxisConfig(ParseYamlText(bad, "bad.yaml"), "bad.yaml"),
               std::invalid_argument);
}

}  // namespace
}  // namespace axis
