// The frequency response (common/spectral.h, sim/linearisation.h,
// sim/operating_point.h, discovery/frequency_response.h) against closed
// forms: FFTW's Welch spectra against a direct DFT; the H1 estimate of
// white noise through a known second-order filter against its transfer
// function within the estimator's random error; coherence 1 on a
// noise-free linear record; the band criterion on inputs that excite one
// and inputs that do not; the linearisation's resonance and
// anti-resonance of a two-mass axis and its response against the
// fourth-order linear axis of sim/linear_model.h; the delta method's
// interval against its closed form and its scaling with the covariance;
// the whole analysis on a simulated record.
#include <cmath>
#include <complex>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/LU>
#include <gtest/gtest.h>

#include "common/spectral.h"
#include "discovery/frequency_response.h"
#include "io/csv.h"
#include "run/job_run.h"
#include "run/load_fit_job.h"
#include "sim/axis_config.h"
#include "sim/input_signal.h"
#include "sim/linear_model.h"
#include "sim/linearisation.h"
#include "sim/operating_point.h"
#include "sim/simulate.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;
constexpr double kPi = 3.14159265358979323846;
using Complex = std::complex<double>;

std::vector<double> WhiteNoise(size_t n, unsigned seed, double sigma = 1.0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, sigma);
  std::vector<double> x(n);
  for (double& v : x) v = normal(rng);
  return x;
}

// y[n] = b0·u[n] + b1·u[n−1] + b2·u[n−2] − a1·y[n−1] − a2·y[n−2].
struct Biquad {
  double b0, b1, b2, a1, a2;
  std::vector<double> Filter(const std::vector<double>& u) const {
    std::vector<double> y(u.size(), 0.0);
    for (size_t n = 0; n < u.size(); ++n) {
      y[n] = b0 * u[n];
      if (n >= 1) y[n] += b1 * u[n - 1] - a1 * y[n - 1];
      if (n >= 2) y[n] += b2 * u[n - 2] - a2 * y[n - 2];
    }
    return y;
  }
  Complex At(double f, double dt) const {
    const Complex z1 = std::exp(Complex(0.0, -2.0 * kPi * f * dt));
    return (b0 + b1 * z1 + b2 * z1 * z1) / (1.0 + a1 * z1 + a2 * z1 * z1);
  }
};

// A resonator: poles at 0.9·exp(±j2π·0.05), unit gain at DC.
Biquad Resonator() {
  const double r = 0.9, theta = 2.0 * kPi * 0.05;
  Biquad b{0.0, 0.0, 0.0, -2.0 * r * std::cos(theta), r * r};
  b.b0 = 1.0 + b.a1 + b.a2;
  return b;
}

TEST(SpectralTest, WelchMatchesADirectDft) {
  const std::vector<double> u = WhiteNoise(64, 1), y = WhiteNoise(64, 2);
  const double dt = 0.01;
  WelchOptions options;
  options.segment_length = 16;
  const WelchSpectra s = ComputeWelchSpectra(u, y, dt, options);
  ASSERT_EQ(s.averages, 7);  // (64 − 16)/8 + 1
  ASSERT_EQ(s.frequency.size(), 9u);
  const int n = 16;
  double window_power = 0.0;
  std::vector<double> w(n);
  for (int j = 0; j < n; ++j) {
    w[j] = 0.5 - 0.5 * std::cos(2 * kPi * j / n);
    window_power += w[j] * w[j];
  }
  for (int k = 0; k <= n / 2; ++k) {
    Complex uy = 0.0;
    double uu = 0.0, yy = 0.0;
    for (int seg = 0; seg < 7; ++seg) {
      double mu = 0.0, my = 0.0;
      for (int j = 0; j < n; ++j) {
        mu += u[seg * 8 + j] / n;
        my += y[seg * 8 + j] / n;
      }
      Complex a = 0.0, b = 0.0;
      for (int j = 0; j < n; ++j) {
        const Complex e = std::exp(Complex(0.0, -2 * kPi * k * j / n));
        a += (u[seg * 8 + j] - mu) * w[j] * e;
        b += (y[seg * 8 + j] - my) * w[j] * e;
      }
      uu += std::norm(a);
      yy += std::norm(b);
      uy += std::conj(a) * b;
    }
    const double scale = (k == 0 || k == n / 2 ? 1.0 : 2.0) / (7 * (1 / dt) * window_power);
    EXPECT_NEAR(s.frequency[k], k / (n * dt), 1e-12);
    EXPECT_NEAR(s.uu[k], uu * scale, 1e-12 * (1 + uu * scale)) << k;
    EXPECT_NEAR(s.yy[k], yy * scale, 1e-12 * (1 + yy * scale)) << k;
    EXPECT_NEAR(std::abs(s.uy[k] - uy * scale), 0.0, 1e-12 * (1 + std::abs(uy) * scale)) << k;
  }
}

TEST(SpectralTest, SegmentLengthAndBadInput) {
  EXPECT_EQ(WelchSegmentLength(4608, 8), 1024);  // 8 averages of 1024 at hop 512
  EXPECT_EQ(WelchSegmentLength(4607, 8), 512);
  EXPECT_EQ(WelchSegmentLength(71, 8), 0);
  EXPECT_THROW(ComputeWelchSpectra({1, 2}, {1}, 0.1), std::invalid_argument);
  EXPECT_NO_THROW(ComputeWelchSpectra(std::vector<double>(72, 0.0),
                                      std::vector<double>(72, 0.0), 0.1));
  EXPECT_THROW(ComputeWelchSpectra(std::vector<double>(71, 0.0), std::vector<double>(71, 0.0),
                                   0.1),
               std::invalid_argument);  // fewer than 8 averages of 16
  WelchOptions odd;
  odd.segment_length = 24;
  EXPECT_THROW(ComputeWelchSpectra(std::vector<double>(100, 0.0),
                                   std::vector<double>(100, 0.0), 0.1, odd),
               std::invalid_argument);
}

// White noise through the resonator, noise on the output: the H1
// magnitude's error at every bin within 4 of its normalised random error
// sqrt(1 − γ²)/(|γ|·sqrt(2·n_d)) (Bendat & Piersol, Table 9.6) at the true
// coherence γ² = |H|²·σ_u²/(|H|²·σ_u² + σ_n²), and 90 % of the bins
// within 2.
TEST(SpectralTest, H1OfWhiteNoiseThroughAResonatorMatchesItsTransferFunction) {
  const size_t n = 1 << 17;
  const double dt = 1e-3;
  const Biquad filter = Resonator();
  const std::vector<double> u = WhiteNoise(n, 3);
  std::vector<double> y = filter.Filter(u);
  const std::vector<double> noise = WhiteNoise(n, 4, 0.3);
  for (size_t k = 0; k < n; ++k) y[k] += noise[k];
  WelchOptions options;
  options.segment_length = 512;
  const FrequencyResponseEstimate e = EstimateH1(ComputeWelchSpectra(u, y, dt, options));
  ASSERT_EQ(e.averages, 511);
  int within2 = 0, bins = 0;
  double worst = 0.0;
  for (size_t k = 1; k + 1 < e.frequency.size(); ++k) {
    const Complex h = filter.At(e.frequency[k], dt);
    const double signal = std::norm(h);  // σ_u = 1
    const double bound = H1RandomError(signal / (signal + 0.3 * 0.3), e.averages);
    const double error = std::abs(std::abs(e.h1[k]) - std::abs(h)) / std::abs(h);
    EXPECT_LE(error, 4.0 * bound) << e.frequency[k] << " Hz, coherence " << e.coherence[k];
    within2 += error <= 2.0 * bound ? 1 : 0;
    worst = std::max(worst, error / bound);
    ++bins;
  }
  EXPECT_GE(within2, 0.9 * bins);
  RecordProperty("worst_error_in_random_errors", std::to_string(worst));
}

// A periodic input (period half a segment) through the resonator in its
// periodic steady state: every segment sees the same samples, so the
// coherence is 1 at every bin the input reaches.
TEST(SpectralTest, CoherenceIsOneOnANoiseFreeLinearRecord) {
  const int period = 128;
  const std::vector<double> one = WhiteNoise(period, 5);
  std::vector<double> u;
  for (int p = 0; p < 200; ++p) u.insert(u.end(), one.begin(), one.end());
  const std::vector<double> y_all = Resonator().Filter(u);
  const size_t settle = 100 * period;  // 0.9^12800: the transient is gone
  const std::vector<double> us(u.begin() + settle, u.end()), ys(y_all.begin() + settle, y_all.end());
  WelchOptions options;
  options.segment_length = 2 * period;
  const FrequencyResponseEstimate e = EstimateH1(ComputeWelchSpectra(us, ys, 1e-3, options));
  int checked = 0;
  for (size_t k = 1; k < e.frequency.size(); ++k) {
    if (e.coherence[k] == 0.0) continue;
    EXPECT_NEAR(e.coherence[k], 1.0, 1e-9) << k;
    ++checked;
  }
  EXPECT_GE(checked, 100);
}

// The band criterion on 16.4 s at 1 kHz (16384 samples, 2048-sample
// segments, 15 averages, bins of 0.49 Hz).
TEST(SpectralTest, BandCriterionTellsBandsFromLinesAndTransients) {
  const double dt = 1e-3;
  const size_t n = 16384;
  const auto band = [&](const std::vector<double>& u) {
    return FindExcitedBand(ComputeWelchSpectra(u, u, dt));
  };
  std::vector<double> chirp(n), square(n), sine(n), step(n), ramp(n);
  for (size_t k = 0; k < n; ++k) {
    const double t = k * dt;
    chirp[k] = std::sin(2 * kPi * (1.0 * t + 0.5 * (100.0 - 1.0) / (n * dt) * t * t));
    square[k] = std::sin(2 * kPi * 5.0 * t) >= 0 ? 1.0 : -1.0;
    sine[k] = std::sin(2 * kPi * 17.3 * t);
    step[k] = t >= 3.0 ? 1.0 : 0.0;
    ramp[k] = 0.1 * t;
  }
  const InputSignal prbs = MakePrbs(1.0, 0.0, 0.005, 12, 1, n * dt);
  std::vector<double> prbs_u(n);
  for (size_t k = 0; k < n; ++k) prbs_u[k] = prbs.Evaluate(k * dt);
  const BandExcitation c = band(chirp);
  EXPECT_TRUE(c.band) << c.reason;
  EXPECT_LT(c.f_low, 3.0);
  EXPECT_GT(c.f_high, 95.0);
  EXPECT_TRUE(band(prbs_u).band) << band(prbs_u).reason;
  EXPECT_TRUE(band(WhiteNoise(n, 7)).band);
  for (const auto& [name, u] : {std::pair<std::string, std::vector<double>>{"square", square},
                                {"sine", sine}, {"step", step}, {"ramp", ramp}}) {
    const BandExcitation b = band(u);
    EXPECT_FALSE(b.band) << name;
    EXPECT_NE(b.reason.find("no band"), std::string::npos) << name << ": " << b.reason;
  }
}

// A two-mass axis (gear coupling without backlash or damping, a current
// source without tach feedback): the resonance sqrt(k_g·(r_g²/J_m + 1/M))
// and, on the motor velocity, the anti-resonance sqrt(k_g/M); none on the
// load velocity.
AxisConfig TwoMassAxis() {
  AxisConfig m = LoadAxisConfig(kRoot + "/configs/axes/x_axis.yaml");
  m.structure.amplifier = Amplifier::kCurrentSource;
  m.structure.coupling = Coupling::kGear;
  m.params.K2 = 0.0;
  m.params.H = 0.0;
  m.params.B_m = m.params.B_a = m.params.b_g = 0.0;
  return m;
}

TEST(LinearisationTest, TwoMassResonanceAndAntiResonance) {
  const AxisConfig m = TwoMassAxis();
  const AxisParams<double>& p = m.params;
  const OperatingPoint point =
      FindOperatingPoint(m.structure, p, AxisState<double>::Zero(), 0.0);
  ASSERT_TRUE(point.converged);
  EXPECT_EQ(LinearModelBlocker(m.structure, p, point), "");
  const LinearisedAxis sys =
      Linearise(m.structure, p, point.state, 0.0, {Channel::kV, Channel::kOmega});
  const std::vector<LinearMode> res = Resonances(sys);
  ASSERT_EQ(res.size(), 1u);
  const double f_res = std::sqrt(p.k_g * (p.r_g * p.r_g / p.J_m + 1.0 / p.M)) / (2 * kPi);
  EXPECT_NEAR(res[0].frequency, f_res, 1e-9 * f_res);
  EXPECT_NEAR(res[0].damping, 0.0, 1e-9);
  EXPECT_TRUE(AntiResonances(sys, 0).empty());
  const std::vector<LinearMode> anti = AntiResonances(sys, 1);
  ASSERT_EQ(anti.size(), 1u);
  const double f_anti = std::sqrt(p.k_g / p.M) / (2 * kPi);
  EXPECT_NEAR(anti[0].frequency, f_anti, 1e-7 * f_anti);
}

// The rigid current-source axis of sim/linear_model.h: no resonance, and
// the response of ω equals that of its 4×4 system at every frequency.
TEST(LinearisationTest, RigidAxisMatchesTheFourthOrderLinearAxis) {
  AxisConfig m = LoadAxisConfig(kRoot + "/configs/axes/x_axis.yaml");
  m.structure.amplifier = Amplifier::kCurrentSource;
  m.structure.coupling = Coupling::kRigid;
  m.params.V_L = HUGE_VAL;
  const LinearAxis reference = MakeLinearAxis(m.params);
  const LinearisedAxis sys = Linearise(m.structure, m.params, AxisState<double>::Zero(), 0.0,
                                       {Channel::kOmega, Channel::kV});
  for (double f : {0.1, 1.0, 10.0, 100.0, 1000.0}) {
    Eigen::Matrix4cd a = -reference.A.cast<Complex>();
    a.diagonal().array() += Complex(0.0, 2 * kPi * f);
    const Complex h = (a.partialPivLu().solve(reference.B.cast<Complex>()))(1);
    EXPECT_NEAR(std::abs(LinearResponse(sys, 0, f) - h), 0.0, 1e-9 * std::abs(h)) << f;
    EXPECT_NEAR(std::abs(LinearResponse(sys, 1, f) - m.params.r_g * h), 0.0,
                1e-9 * std::abs(m.params.r_g * h));
  }
  // The rigid axis's only complex poles are the analog loop's, not a
  // mechanical resonance: with K2 = 0 (no loop) none.
  m.params.K2 = 0.0;
  EXPECT_TRUE(Resonances(Linearise(m.structure, m.params, AxisState<double>::Zero(), 0.0,
                                   {Channel::kV}))
                  .empty());
}

TEST(LinearisationTest, NoLinearModelInsideTheCoulombBandOrTheBacklash) {
  AxisConfig m = TwoMassAxis();
  m.structure.effects.coulomb = true;
  m.params.F_c = 5.0;
  m.params.v_eps = 1e-3;
  const OperatingPoint rest =
      FindOperatingPoint(m.structure, m.params, AxisState<double>::Zero(), 0.0);
  EXPECT_NE(LinearModelBlocker(m.structure, m.params, rest).find("within 3*v_eps"),
            std::string::npos);
  // 1 mV: V_c = K1·U = 1.0 V, 150 N against F_c = 5 N. Without damping the
  // axis accelerates for ever; with B_a = 200 N·s/m it moves at 0.74 m/s,
  // well outside the band: a linear model.
  const OperatingPoint moving =
      FindOperatingPoint(m.structure, m.params, AxisState<double>::Zero(), 0.001);
  m.params.B_a = 200.0;
  const OperatingPoint damped =
      FindOperatingPoint(m.structure, m.params, AxisState<double>::Zero(), 0.001);
  ASSERT_TRUE(damped.converged);
  EXPECT_GT(std::abs(damped.state[1]), 3e-3);
  EXPECT_EQ(LinearModelBlocker(m.structure, m.params, damped), "");
  EXPECT_FALSE(moving.converged);
  AxisConfig g = TwoMassAxis();
  g.params.H = 1e-5;
  const OperatingPoint in_backlash =
      FindOperatingPoint(g.structure, g.params, AxisState<double>::Zero(), 0.0);
  EXPECT_NE(LinearModelBlocker(g.structure, g.params, in_backlash).find("backlash"),
            std::string::npos);
}

// The X axis as configured (analog velocity loop, gear with backlash) under
// 10 mV: steady motion at the loop's steady-state gain (to 10⁻⁵: the full
// current loop's finite K_a gives i = (K_a·V_c − K_e·ω)/(K_a/K_i + R),
// 5·10⁻⁶ below K_i·V_c), the gear in contact, a linear model. The loop
// holds the motor: the load resonates on the gear near √(k_g/M)/2π, and
// the motor velocity's anti-resonance is that frequency (the load on the
// gear with the motor held), damped by b_g and B_a.
TEST(LinearisationTest, AnalogLoopSteadyMotionThroughTheBacklash) {
  const AxisConfig m = LoadAxisConfig(kRoot + "/configs/axes/x_axis.yaml");
  const double u = 0.01;
  const OperatingPoint point =
      FindOperatingPoint(m.structure, m.params, AxisState<double>::Zero(), u);
  ASSERT_TRUE(point.converged);
  const double v = SteadyStateGain(m.params) * m.params.r_g * u;
  EXPECT_NEAR(point.state[1], v, 1e-5 * v);
  EXPECT_NEAR(point.state[3] * m.params.r_g, point.state[1], 1e-12 * v);
  EXPECT_GT(m.params.r_g * point.state[2] - point.state[0], m.params.H);
  EXPECT_EQ(LinearModelBlocker(m.structure, m.params, point), "");
  const LinearisedAxis sys =
      Linearise(m.structure, m.params, point.state, u, {Channel::kV, Channel::kOmega});
  const AxisParams<double>& p = m.params;
  const double f_held = std::sqrt(p.k_g / p.M) / (2 * kPi);
  const std::vector<LinearMode> res = Resonances(sys);
  ASSERT_FALSE(res.empty());
  EXPECT_NEAR(res[0].frequency, f_held, 0.05 * f_held);
  EXPECT_LT(res[0].damping, 0.1);
  EXPECT_TRUE(AntiResonances(sys, 0).empty());  // the load's velocity: none
  const std::vector<LinearMode> anti = AntiResonances(sys, 1);
  ASSERT_EQ(anti.size(), 1u);
  // M·s² + (b_g + B_a)·s + k_g = 0: |s| = √(k_g/M), ζ = (b_g + B_a)/(2·√(k_g·M)).
  EXPECT_NEAR(anti[0].frequency, f_held, 1e-9 * f_held);
  EXPECT_NEAR(anti[0].damping, (p.b_g + p.B_a) / (2 * std::sqrt(p.k_g * p.M)), 1e-9);
}

// A force source on a rigid load with viscous friction: v/U = g_F/(M·s +
// B_a) and a/U = g_F·s/(M·s + B_a), the acceleration with a direct
// feed-through (D = g_F/M); neither has a resonance or an anti-resonance.
TEST(LinearisationTest, ForceSourceResponseHasItsFeedThrough) {
  AxisConfig m = LoadAxisConfig(kRoot + "/configs/axes/x_axis.yaml");
  m.structure.amplifier = Amplifier::kForceSource;
  m.structure.coupling = Coupling::kRigid;
  m.params.g_F = 50.0;
  const AxisParams<double>& p = m.params;
  const LinearisedAxis sys =
      Linearise(m.structure, p, AxisState<double>::Zero(), 0.0, {Channel::kV, Channel::kA});
  EXPECT_NEAR(sys.D(1), p.g_F / p.M, 1e-12 * p.g_F / p.M);
  for (double f : {0.01, 0.2, 5.0, 100.0}) {
    const Complex s(0.0, 2 * kPi * f);
    const Complex v = p.g_F / (p.M * s + p.B_a);
    EXPECT_NEAR(std::abs(LinearResponse(sys, 0, f) - v), 0.0, 1e-12 * std::abs(v)) << f;
    EXPECT_NEAR(std::abs(LinearResponse(sys, 1, f) - s * v), 0.0, 1e-12 * std::abs(s * v)) << f;
  }
  EXPECT_TRUE(Resonances(sys).empty());
  EXPECT_TRUE(AntiResonances(sys, 0).empty());
  EXPECT_TRUE(AntiResonances(sys, 1).empty());
}

// A direct-drive pendulum on a voltage drive (rotary axis, no friction but
// the back-EMF's K_τ·K_e/R): under u the equilibrium at rest where the
// motor's torque K_τ·u/R holds the pendulum, sin x* = K_τ·u/(R·r_g·m_p·g·l_p);
// the resonance at √(r_g²·m_p·g·l_p·cos x*/J)/2π, J = J_m + r_g²·(M +
// m_p·l_p²), damped by the back-EMF.
TEST(LinearisationTest, PendulumOnAVoltageDriveRestsAndSwings) {
  AxisConfig m = LoadAxisConfig(kRoot + "/configs/axes/x_axis.yaml");
  m.structure.amplifier = Amplifier::kVoltageDrive;
  m.structure.coupling = Coupling::kRigid;
  m.structure.motion = Motion::kRotary;
  m.structure.load = LoadTerm::kPendulum;
  AxisParams<double>& p = m.params;
  p.r_g = 1.0;
  p.M = 0.01;
  p.m_p = 1.0;
  p.l_p = 0.5;
  p.B_m = p.B_a = 0.0;
  const double u = 0.5;
  const OperatingPoint point =
      FindOperatingPoint(m.structure, p, AxisState<double>::Zero(), u);
  ASSERT_TRUE(point.converged);
  const double mgl = p.m_p * kStandardGravity * p.l_p;
  const double x = std::asin(p.K_tau * u / (p.R * p.r_g * mgl));
  EXPECT_NEAR(point.state[0], x, 1e-12);
  EXPECT_EQ(point.state[1], 0.0);
  EXPECT_EQ(LinearModelBlocker(m.structure, p, point), "");
  const std::vector<LinearMode> res =
      Resonances(Linearise(m.structure, p, point.state, u, {Channel::kX}));
  ASSERT_EQ(res.size(), 1u);
  const double inertia = p.J_m + p.r_g * p.r_g * (p.M + p.m_p * p.l_p * p.l_p);
  const double w = std::sqrt(p.r_g * p.r_g * mgl * std::cos(x) / inertia);
  EXPECT_NEAR(res[0].frequency, w / (2 * kPi), 1e-9 * w);
  EXPECT_NEAR(res[0].damping, p.K_tau * p.K_e / p.R / (2 * w * inertia), 1e-9);
}

// The delta method: SE of the resonance in k_g alone is f/(2·k_g)·SE(k_g);
// four times the covariance, twice the interval.
TEST(FrequencyResponseTest, DeltaMethodIntervalMatchesItsClosedFormAndScales) {
  const AxisConfig m = TwoMassAxis();
  const double se = 0.05 * m.params.k_g;
  Eigen::MatrixXd cov(2, 2);
  cov << se * se, 0.0, 0.0, std::pow(0.01 * m.params.M, 2);
  const std::vector<std::string> free = {"k_g", "M"};
  const LinearModelModes one =
      LinearModelWithIntervals(m, AxisState<double>::Zero(), 0.0, {Channel::kV}, free, cov);
  const LinearModelModes four = LinearModelWithIntervals(m, AxisState<double>::Zero(), 0.0,
                                                         {Channel::kV}, free, 4.0 * cov);
  ASSERT_EQ(one.resonances.size(), 1u);
  ASSERT_EQ(four.resonances.size(), 1u);
  const double f = one.resonances[0].frequency;
  // ∂f/∂k_g = f/(2k_g); ∂f/∂M = −f/2·(1/M²)/(r_g²/J_m + 1/M).
  const AxisParams<double>& p = m.params;
  const double dk = f / (2 * p.k_g);
  const double dm = -f / 2 * (1 / (p.M * p.M)) / (p.r_g * p.r_g / p.J_m + 1 / p.M);
  const double expected = std::sqrt(dk * dk * cov(0, 0) + dm * dm * cov(1, 1));
  EXPECT_NEAR(one.resonances[0].std_error, expected, 1e-5 * expected);
  const double half_one = one.resonances[0].ci95_high - f;
  const double half_four = four.resonances[0].ci95_high - f;
  EXPECT_NEAR(half_four / half_one, 2.0, 1e-9);
  EXPECT_NEAR(half_one, 1.959963984540054 * expected, 1e-5 * half_one);
  EXPECT_THROW(LinearModelWithIntervals(m, AxisState<double>::Zero(), 0.0, {Channel::kV},
                                        {"no_such"}, Eigen::MatrixXd::Identity(1, 1)),
               std::invalid_argument);
}

// An experiment of the X axis without backlash, simulated noise-free; its
// record is the data.
FitExperiment Simulated(const AxisConfig& model, const InputSignal& input, double duration) {
  FitExperiment e;
  e.name = "record";
  e.drive.input = input;
  e.options.duration = duration;
  e.options.step = 1e-5;
  e.options.output_period = 1e-3;
  e.options.channels = {Channel::kU, Channel::kV, Channel::kI};
  const Trace<double> trace = Simulate(model.structure, model.params, e.initial_state, e.drive,
                                       e.options, MakeGrid(e.options, e.drive));
  e.t = trace.t;
  e.measured_channels = {Channel::kV, Channel::kI};
  e.measured = {trace[Channel::kV], trace[Channel::kI]};
  e.fitted = {{Channel::kV, 1e-3}, {Channel::kI, 1e-2}};
  return e;
}

// A PRBS of 2 mV (the preamp stays below V_L) with 2 ms bits, and a
// square wave of 5 Hz, on the X axis without backlash.
TEST(FrequencyResponseTest, ARecordOfTheModelGivesItsResponse) {
  AxisConfig m = LoadAxisConfig(kRoot + "/configs/axes/x_axis.yaml");
  m.params.H = 0.0;
  EstimationProblem job;
  job.model = m;
  job.experiments.push_back(Simulated(m, MakePrbs(0.002, 0.0, 0.002, 12, 3, 4.0), 4.0));
  InputSignal square;
  square.kind = InputSignal::Kind::kTable;
  square.hold = true;
  for (int k = 0; k <= 40; ++k) {
    square.times.push_back(0.1 * k);
    square.values.push_back(k % 2 == 0 ? 0.002 : -0.002);
  }
  job.experiments.push_back(Simulated(m, square, 4.0));
  job.experiments.back().name = "square";
  const std::vector<ExperimentFrequencyResponse> r = AnalyseFrequencyResponse(job, FitResult{});
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].note, "");
  EXPECT_EQ(r[0].input, "U");
  EXPECT_EQ(r[0].linear.blocker, "");
  ASSERT_EQ(r[0].channels.size(), 2u);
  const ChannelFrequencyResponse& v = r[0].channels[0];
  ASSERT_FALSE(v.frequency.empty());
  ASSERT_EQ(v.linear.size(), v.frequency.size());
  int compared = 0;
  for (size_t k = 0; k < v.frequency.size(); ++k) {
    // The model is the data's: the same H1 bin by bin.
    EXPECT_NEAR(std::abs(v.model[k] - v.data[k]), 0.0, 1e-9 * std::abs(v.data[k]));
    if (v.data_coherence[k] < 0.99 || v.frequency[k] > 50.0) continue;
    // The linear model (small signal, no limit reached) within 5 %.
    EXPECT_NEAR(std::abs(v.data[k] / v.linear[k]), 1.0, 0.05) << v.frequency[k];
    ++compared;
  }
  EXPECT_GE(compared, 10);
  EXPECT_FALSE(r[1].band.band);
  EXPECT_NE(r[1].note.find("no band"), std::string::npos) << r[1].note;
  EXPECT_TRUE(r[1].channels.empty());
  const std::string text = FormatFrequencyResponse(r);
  EXPECT_NE(text.find("square: U: no band"), std::string::npos) << text;
  const nlohmann::json json = FrequencyResponseToJson(r);
  EXPECT_EQ(json[0]["channels"][0]["channel"], "v");
  EXPECT_EQ(json[1]["band"], false);
}

// The pipeline (RunJob): the EMPS axis driven open loop by a PRBS, its
// velocity recorded with noise, M and B_a fitted: the frequency response of
// the record in JobRun and report.json, the data's H1 on the model's and on
// the linear model's (a first-order lag g_F/(M·s + B_a), no resonance)
// where the coherence is high.
TEST(FrequencyResponseTest, TheJobPipelineReportsIt) {
  const AxisConfig m = LoadAxisConfig(kRoot + "/configs/axes/emps.yaml");
  FitExperiment e;
  e.drive.input = MakePrbs(1.0, 0.5, 0.002, 12, 5, 8.0);
  e.options.duration = 8.0;
  e.options.step = 1e-3;
  e.options.output_period = 1e-3;
  e.options.channels = {Channel::kU, Channel::kV};
  const Trace<double> trace = Simulate(m.structure, m.params, e.initial_state, e.drive,
                                       e.options, MakeGrid(e.options, e.drive));
  std::vector<double> v = trace[Channel::kV];
  const std::vector<double> noise = WhiteNoise(v.size(), 9, 1e-4);
  for (size_t k = 0; k < v.size(); ++k) v[k] += noise[k];
  const std::string dir = testing_files::TestTempDir();
  WriteCsvAtomic(dir + "prbs.csv", {"t", "u", "v"}, {trace.t, trace[Channel::kU], v}, 17);
  const std::string job = testing_files::WriteTemp(
      "job.yaml", "model: " + kRoot + "/configs/axes/emps.yaml\n"
                  "free:\n  M: {initial: 80, lower: 10, upper: 500}\n"
                  "  B_a: {initial: 150, lower: 10, upper: 2000}\n"
                  "uncertainty: {method: gauss_newton}\n"
                  "experiments:\n  - name: prbs\n    data: prbs.csv\n"
                  "    channels: {u: u, v: v}\n"
                  "    input: {column: u, interpolation: hold}\n"
                  "    fit: {v: 0.0001}\n");
  std::ostringstream log;
  const JobRun run = RunJob(LoadFitJob(job), false, log);
  EXPECT_NE(log.str().find("frequency response (H1"), std::string::npos) << log.str();
  ASSERT_EQ(run.frequency_response.size(), 1u);
  const ExperimentFrequencyResponse& r = run.frequency_response[0];
  EXPECT_EQ(r.note, "");
  EXPECT_EQ(r.linear.blocker, "");
  EXPECT_TRUE(r.linear.resonances.empty());
  EXPECT_NEAR(r.mean_input, 0.5, 0.05);
  ASSERT_EQ(r.channels.size(), 1u);
  const ChannelFrequencyResponse& c = r.channels[0];
  int compared = 0;
  for (size_t k = 0; k < c.frequency.size(); ++k) {
    if (c.data_coherence[k] < 0.99) continue;
    EXPECT_NEAR(std::abs(c.data[k] / c.model[k]), 1.0, 0.05) << c.frequency[k];
    EXPECT_NEAR(std::abs(c.data[k] / c.linear[k]), 1.0, 0.05) << c.frequency[k];
    ++compared;
  }
  EXPECT_GE(compared, 20);
  const nlohmann::json& json = run.sections.json.at("frequency_response");
  ASSERT_EQ(json.size(), 1u);
  EXPECT_EQ(json[0]["linear_model"]["available"], true);
  EXPECT_EQ(json[0]["channels"][0]["frequency_hz"].size(), c.frequency.size());
  EXPECT_NE(run.sections.markdown.find("## Frequency response"), std::string::npos);
  bool phase = false;
  for (const RunPhase& p : run.phases) phase |= p.name == "frequency response";
  EXPECT_TRUE(phase);

  // `frequency_response:` settings: more averages (a shorter segment, a
  // coarser grid), or none at all; a bad key is refused naming it.
  const auto with = [&](const std::string& settings) {
    std::ifstream in(job);
    std::stringstream text;
    text << in.rdbuf() << "frequency_response: " << settings << "\n";
    return testing_files::WriteTemp("job_" + std::to_string(settings.size()) + ".yaml",
                                    text.str());
  };
  const JobRun more = RunJob(LoadFitJob(with("{min_averages: 32}")), false, log);
  ASSERT_EQ(more.frequency_response.size(), 1u);
  EXPECT_GE(more.frequency_response[0].averages, 32);
  EXPECT_LT(more.frequency_response[0].segment_length, r.segment_length);
  const JobRun off = RunJob(LoadFitJob(with("{enabled: false}")), false, log);
  EXPECT_TRUE(off.frequency_response.empty());
  EXPECT_EQ(off.sections.json.count("frequency_response"), 0u);
  for (const RunPhase& p : off.phases) EXPECT_NE(p.name, "frequency response");
  try {
    LoadFitJob(with("{min_averages: 1}"));
    ADD_FAILURE() << "min_averages: 1 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("key 'frequency_response.min_averages'"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace axis
