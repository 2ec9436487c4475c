// Tests of sim/controller.h against the law of MODEL.md §5 written out by hand:
// proportional + feed-forward, saturation, integral, filtered velocity, output
// delay, motor- and load-side encoder quantisation; SampleReference and
// Reference::Profile for trapezoidal and triangular moves; and a closed-loop
// Simulate run (u held over each control period, within ±U_max, replayable
// from the recorded states, injection added on top).
#include <algorithm>
#include <cmath>
#include <deque>
#include <iostream>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "sim/axis_model.h"
#include "sim/controller.h"
#include "sim/simulate.h"

namespace axis {
namespace {

using State7 = Eigen::Matrix<double, 7, 1>;
constexpr double kTwoPi = 6.283185307179586476925;

// y with arm position x (y0) and motor angle θ (y2); everything else zero.
State7 MakeState(double x, double theta = 0.0) {
  State7 y = State7::Zero();
  y[0] = x;
  y[2] = theta;
  return y;
}

// An ideal load-side measurement, no integral/velocity terms, no saturation
// in practice: the tests switch on what they check.
ControllerConfig IdealConfig() {
  ControllerConfig c;
  c.counts_per_rev = 0.0;
  c.load_quantum = 0.0;
  c.G_ff = 0.0;
  c.G_p = 0.0;
  c.G_i = 0.0;
  c.G_v = 0.0;
  c.alpha = 1.0;
  c.U_max = 1e9;
  c.delay_samples = 0;
  return c;
}

// MODEL.md §5 written out independently of sim/controller.h: takes the
// measured position directly, keeps its own sums and delay line.
struct HandLaw {
  explicit HandLaw(const ControllerConfig& config) : c(config) {}
  ControllerConfig c;
  long k = 0;
  double sum_e = 0.0, x_meas_prev = 0.0, x_f_prev = 0.0;
  std::deque<double> line;

  // The law's output at this sample (before the delay).
  double Law(double x_meas, double x_ref, double v_ref) {
    const double x_before = k == 0 ? x_meas : x_meas_prev;
    const double x_f = c.alpha * x_meas + (1.0 - c.alpha) * x_before;
    const double v_meas = k == 0 ? 0.0 : (x_f - x_f_prev) / c.T_s;
    const double e = x_ref - x_meas;
    sum_e += e;
    const double u = c.G_ff * v_ref + c.G_p * e + c.G_i * c.T_s * sum_e -
                     c.G_v * v_meas;
    x_meas_prev = x_meas;
    x_f_prev = x_f;
    ++k;
    return std::clamp(u, -c.U_max, c.U_max);
  }
  // What reaches the plant: the law's output delay_samples samples ago.
  double Output(double x_meas, double x_ref, double v_ref) {
    line.push_back(Law(x_meas, x_ref, v_ref));
    if (static_cast<int>(line.size()) <= c.delay_samples) return 0.0;
    const double u = line.front();
    line.pop_front();
    return u;
  }
};

ReferenceSample Ref(double x_ref, double v_ref) {
  ReferenceSample r;
  r.x_ref = x_ref;
  r.v_ref = v_ref;
  return r;
}

TEST(ControllerUpdateTest, ProportionalPlusFeedForward) {
  ControllerConfig c = IdealConfig();
  c.G_ff = 10.0;
  c.G_p = 300.0;
  const AxisParams<double> p;
  ControllerState<double> s;
  struct Case { double x, x_ref, v_ref; };
  for (const Case& k : {Case{0.0, 0.0, 0.0}, Case{0.0, 0.01, 0.2},
                        Case{0.1, 0.1013, 0.5}, Case{0.25, 0.2496, -0.3},
                        Case{-0.03, -0.0301, 0.0}}) {
    const double u = ControllerUpdate(c, p, MakeState(k.x, 123.0), Ref(k.x_ref, k.v_ref), &s);
    // U = G_ff·v_ref + G_p·e; |terms| ≤ 5 V, a few roundings: 1e-12 V.
    EXPECT_NEAR(u, 10.0 * k.v_ref + 300.0 * (k.x_ref - k.x), 1e-12)
        << k.x << " " << k.x_ref << " " << k.v_ref;
  }
  EXPECT_EQ(s.k, 5);
}

TEST(ControllerUpdateTest, SaturatesAtUMax) {
  ControllerConfig c = IdealConfig();
  c.G_ff = 10.0;
  c.G_p = 300.0;
  c.U_max = 10.0;
  const AxisParams<double> p;
  ControllerState<double> s;
  // Clamped values are the bound itself: exact.
  EXPECT_EQ(ControllerUpdate(c, p, MakeState(0.0), Ref(0.1, 0.0), &s), 10.0);
  EXPECT_EQ(ControllerUpdate(c, p, MakeState(0.0), Ref(-0.1, 0.0), &s), -10.0);
  EXPECT_EQ(ControllerUpdate(c, p, MakeState(0.0), Ref(0.0, 1.5), &s), 10.0);
  EXPECT_EQ(ControllerUpdate(c, p, MakeState(0.05), Ref(0.0, 0.2), &s), -10.0);
  // Just inside: unclamped (9 V; rounding of 300·0.03 is below 1e-12 V).
  EXPECT_NEAR(ControllerUpdate(c, p, MakeState(0.0), Ref(0.03, 0.0), &s), 9.0,
              1e-12);
  EXPECT_NEAR(ControllerUpdate(c, p, MakeState(0.0), Ref(0.0, -0.95), &s),
              -9.5, 1e-12);
}

TEST(ControllerUpdateTest, IntegralAccumulatesError) {
  ControllerConfig c = IdealConfig();
  c.G_i = 50.0;
  const AxisParams<double> p;
  ControllerState<double> s;
  const std::vector<double> x = {0.0, 0.001, 0.004, 0.02, 0.019, 0.03};
  const std::vector<double> r = {0.01, 0.021, 0.0, 0.05, 0.02, 0.03};
  double sum = 0.0;
  for (size_t k = 0; k < x.size(); ++k) {
    sum += r[k] - x[k];
    const double u = ControllerUpdate(c, p, MakeState(x[k]), Ref(r[k], 0.0), &s);
    // G_i·T_s·Σe with Σe ≤ 0.1 m: values ≤ 0.025 V, rounding ≪ 1e-15 V.
    EXPECT_NEAR(u, 50.0 * 0.005 * sum, 1e-15) << "k = " << k;
  }
  EXPECT_NEAR(s.integral, sum, 1e-15);  // Σe itself, in metres
}

TEST(ControllerUpdateTest, IntegralKeepsAccumulatingWhileSaturated) {
  // MODEL.md §5 clamps the sum of the terms; the integral has no anti-windup.
  ControllerConfig c = IdealConfig();
  c.G_i = 1000.0;  // G_i·T_s = 5 V/m per sample
  c.U_max = 1.0;
  const AxisParams<double> p;
  ControllerState<double> s;
  // e = 0.1 m: 0.5 V after one sample, then 1.0, 1.5, ... clamped to 1 V.
  EXPECT_NEAR(ControllerUpdate(c, p, MakeState(0.0), Ref(0.1, 0.0), &s), 0.5,
              1e-15);  // one product of exact-ish decimals
  for (int k = 1; k < 10; ++k) {
    EXPECT_EQ(ControllerUpdate(c, p, MakeState(0.0), Ref(0.1, 0.0), &s), 1.0);
  }
  // Σe = 1 m (5 V). Reversing the error unwinds it one 0.5 V step a sample:
  // Σe = 0.9 ... 0.3 m is still ≥ 1.5 V and stays clamped at +1 V although
  // e < 0 (an anti-windup law would go negative at once).
  for (int k = 0; k < 7; ++k) {
    EXPECT_EQ(ControllerUpdate(c, p, MakeState(0.0), Ref(-0.1, 0.0), &s), 1.0)
        << "k = " << k;
  }
  // Σe = 0.2 m (borderline 1 V: skip its verdict), then 0.1 m: 0.5 V.
  ControllerUpdate(c, p, MakeState(0.0), Ref(-0.1, 0.0), &s);
  // 19 additions of ±0.1 leave ≈ 1e-16 m in Σe, 5e-16 V in U.
  EXPECT_NEAR(ControllerUpdate(c, p, MakeState(0.0), Ref(-0.1, 0.0), &s), 0.5,
              1e-14);
  EXPECT_NEAR(s.integral, 0.1, 1e-14);
}

TEST(ControllerUpdateTest, FilteredVelocityWithHalfAlpha) {
  ControllerConfig c = IdealConfig();
  c.G_v = 200.0;
  c.alpha = 0.5;
  const AxisParams<double> p;
  ControllerState<double> s;
  const double Ts = c.T_s;
  const std::vector<double> x = {0.001, 0.0013, 0.0018, 0.0020, 0.0020};
  // x_f,0 = x_0 (no earlier sample), then x_f,k = (x_k + x_{k−1})/2.
  const std::vector<double> x_f = {0.001, 0.00115, 0.00155, 0.0019, 0.0020};
  // v_meas,0 = 0, v_meas,k = (x_f,k − x_f,k−1)/T_s.
  std::vector<double> expected = {0.0};
  for (size_t k = 1; k < x.size(); ++k) {
    expected.push_back(-200.0 * (x_f[k] - x_f[k - 1]) / Ts);
  }
  for (size_t k = 0; k < x.size(); ++k) {
    const double u = ControllerUpdate(c, p, MakeState(x[k]), Ref(0.0, 0.0), &s);
    // Differences of positions ~1e-3 m divided by 5 ms: cancellation leaves
    // ≈ 1e-19 m / 5e-3 s · 200 ≈ 4e-15 V of rounding; 1e-12 V bound.
    EXPECT_NEAR(u, expected[k], 1e-12) << "k = " << k;
  }
  // Sample 1 by hand: −200·((0.0013 + 0.001)/2 − 0.001)/0.005 = −6 V.
  ControllerState<double> s2;
  EXPECT_EQ(ControllerUpdate(c, p, MakeState(0.001), Ref(0.0, 0.0), &s2), 0.0);
  EXPECT_NEAR(ControllerUpdate(c, p, MakeState(0.0013), Ref(0.0, 0.0), &s2),
              -6.0, 1e-12);
}

TEST(ControllerUpdateTest, FirstSampleHasNoVelocityEvenAwayFromZero) {
  ControllerConfig c = IdealConfig();
  c.G_v = 200.0;
  c.alpha = 0.5;
  const AxisParams<double> p;
  ControllerState<double> s;
  EXPECT_EQ(ControllerUpdate(c, p, MakeState(0.7), Ref(0.0, 0.0), &s), 0.0);
}

TEST(ControllerUpdateTest, DelayOfTwoSamples) {
  ControllerConfig c = IdealConfig();
  c.G_ff = 10.0;
  c.G_p = 300.0;
  c.G_i = 20.0;
  c.G_v = 5.0;
  c.alpha = 0.5;
  c.U_max = 10.0;
  c.delay_samples = 2;
  const AxisParams<double> p;
  ControllerState<double> s;
  HandLaw law(c);
  HandLaw law_undelayed(c);
  law_undelayed.c.delay_samples = 0;
  std::vector<double> undelayed;
  for (int k = 0; k < 40; ++k) {
    const double t = k * c.T_s;
    const double x = 0.05 * std::sin(3.0 * t) + 0.001 * k;
    const double x_ref = 0.06 * std::sin(3.0 * t + 0.2) + (k == 7 ? 0.1 : 0.0);
    const double v_ref = 0.18 * std::cos(3.0 * t + 0.2);
    const double u =
        ControllerUpdate(c, p, MakeState(x), Ref(x_ref, v_ref), &s);
    undelayed.push_back(law_undelayed.Output(x, x_ref, v_ref));
    if (k < 2) {
      EXPECT_EQ(u, 0.0) << "k = " << k;  // nothing computed 2 samples ago
    } else {
      // The law's output at k − 2; terms ≤ ~40 V (the k = 7 jump saturates),
      // a few roundings each: 1e-12 V.
      EXPECT_NEAR(u, undelayed[k - 2], 1e-12) << "k = " << k;
    }
    EXPECT_NEAR(u, law.Output(x, x_ref, v_ref), 1e-12) << "k = " << k;
  }
  // The saturating sample went through the delay line clamped.
  EXPECT_EQ(undelayed[7], 10.0);
  EXPECT_EQ(s.pending.size(), 2u);
}

TEST(ControllerUpdateTest, FullLawMatchesHandWrittenLaw) {
  ControllerConfig c = IdealConfig();
  c.G_ff = 10.0;
  c.G_p = 300.0;
  c.G_i = 40.0;
  c.G_v = 3.0;
  c.alpha = 0.7;
  c.U_max = 4.0;
  c.delay_samples = 1;
  const AxisParams<double> p;
  ControllerState<double> s;
  HandLaw law(c);
  int saturated = 0;
  for (int k = 0; k < 200; ++k) {
    const double t = k * c.T_s;
    const double x = 0.1 * std::sin(2.0 * t);
    const double x_ref = 0.1 * std::sin(2.0 * t + 0.1);
    const double v_ref = 0.2 * std::cos(2.0 * t + 0.1);
    const double u =
        ControllerUpdate(c, p, MakeState(x), Ref(x_ref, v_ref), &s);
    // Terms ≤ ~10 V and Σe over 200 samples: rounding ≪ 1e-11 V.
    EXPECT_NEAR(u, law.Output(x, x_ref, v_ref), 1e-11) << "k = " << k;
    saturated += std::abs(u) == 4.0;
  }
  EXPECT_GT(saturated, 0);  // the run exercises the clamp too
}

TEST(ControllerUpdateTest, MotorEncoderQuantisation) {
  ControllerConfig c = IdealConfig();
  c.G_p = 300.0;
  c.counts_per_rev = 8000.0;
  const AxisParams<double> p;  // r_g = 0.00573 m
  ASSERT_EQ(p.r_g, 0.00573);
  const double q = kTwoPi / 8000.0;  // rad per count
  // Angles inside counts (fractions away from the edges, so floor cannot
  // tip over by rounding), positive and negative, large and small.
  std::vector<double> thetas = {0.0, 0.1234, 1.0, -0.5, 12.3456, -7.89, 250.0};
  for (long m : {0L, 1L, 7L, -1L, -8L, 8000L, 123456L, -99999L}) {
    for (double f : {0.001, 0.5, 0.999}) thetas.push_back((m + f) * q);
  }
  for (double theta : thetas) {
    ControllerState<double> s;
    // y0 differs from r_g·θ: the motor encoder must not look at it.
    const double u =
        ControllerUpdate(c, p, MakeState(0.3, theta), Ref(0.0, 0.0), &s);
    const double x_meas =
        0.00573 * kTwoPi * std::floor(theta * 8000.0 / kTwoPi) / 8000.0;
    // Quantize returns θ + (q·n − θ): within an ulp of θ of q·n, times r_g·G_p
    // (≈ 1.7); 1e-14·(1 + |θ|) covers it.
    EXPECT_NEAR(u, -300.0 * x_meas, 1e-14 * (1.0 + std::abs(theta)))
        << "theta = " << theta;
  }
  // One count is r_g·2π/8000 = 4.5e-6 m of arm travel, 1.35 mV at G_p.
  ControllerState<double> s1, s2, s3;
  const double u_lo = ControllerUpdate(c, p, MakeState(0.0, 5.001 * q),
                                       Ref(0.0, 0.0), &s1);
  const double u_hi = ControllerUpdate(c, p, MakeState(0.0, 5.999 * q),
                                       Ref(0.0, 0.0), &s2);
  const double u_next = ControllerUpdate(c, p, MakeState(0.0, 6.001 * q),
                                         Ref(0.0, 0.0), &s3);
  EXPECT_EQ(u_lo, u_hi);  // same count
  EXPECT_NEAR(u_lo - u_next, 300.0 * 0.00573 * q, 1e-15);  // ≈ 1.35e-3 V
  // PositionQuantum names the same count in m of travel.
  EXPECT_NEAR(PositionQuantum(c, p.r_g), 0.00573 * q, 1e-20);
}

// The quantum in m: the load-side encoder's if set (the motor encoder is
// then ignored, as ControllerUpdate does), none for an ideal measurement.
TEST(ControllerUpdateTest, PositionQuantumOfEachFeedback) {
  ControllerConfig c;
  c.counts_per_rev = 8000.0;
  c.load_quantum = 5e-8;
  EXPECT_EQ(PositionQuantum(c, 0.00573), 5e-8);
  c.load_quantum = 0.0;
  EXPECT_NEAR(PositionQuantum(c, 0.00573), 0.00573 * 6.283185307179586 / 8000.0, 1e-20);
  c.counts_per_rev = 0.0;
  EXPECT_EQ(PositionQuantum(c, 0.00573), 0.0);
}

TEST(ControllerUpdateTest, LoadSideQuantum) {
  ControllerConfig c = IdealConfig();
  c.G_p = 300.0;
  c.counts_per_rev = 8000.0;  // ignored when load_quantum > 0
  c.load_quantum = 5e-8;
  const AxisParams<double> p;
  std::vector<double> xs = {0.0, 1.23456789e-3, -2.5e-7 - 1e-9, 0.2};
  for (long m : {0L, 3L, -1L, -7L, 4000000L, -123457L}) {
    for (double f : {0.001, 0.5, 0.999}) xs.push_back((m + f) * 5e-8);
  }
  for (double x : xs) {
    ControllerState<double> s;
    // θ is far from x/r_g: the motor encoder must not be used.
    const double u = ControllerUpdate(c, p, MakeState(x, 9.0), Ref(0.0, 0.0), &s);
    const double x_meas = 5e-8 * std::floor(x / 5e-8);
    // An ulp of x (≤ 0.2 m: 3e-17 m) times G_p: 1e-14 V is ample.
    EXPECT_NEAR(u, -300.0 * x_meas, 1e-14) << "x = " << x;
  }
  ControllerState<double> s;
  // 0.2 m + 0.7 quanta reads 0.2 m exactly up to rounding: U = −60 V.
  EXPECT_NEAR(ControllerUpdate(c, p, MakeState(0.2 + 3.5e-8, 0.0),
                               Ref(0.0, 0.0), &s),
              -60.0, 1e-12);
}

// ----------------------------------------------------------------------------
// Reference

Reference Trapezoid(double distance, double velocity, double acceleration,
                    double start = 0.0, double origin = 0.0) {
  Reference r;
  r.kind = Reference::Kind::kTrapezoid;
  r.distance = distance;
  r.velocity = velocity;
  r.acceleration = acceleration;
  r.start = start;
  r.origin = origin;
  return r;
}

// Largest forward-difference slope of the profile over [start, start + T]
// on a grid of h (sign of the move removed).
double PeakSlope(const Reference& r, double T, double h) {
  double peak = 0.0;
  const long n = std::lround(T / h);
  const double sign = r.distance > 0.0 ? 1.0 : -1.0;
  for (long i = 0; i < n; ++i) {
    const double t = r.start + i * h;
    peak = std::max(peak, sign * (r.Profile(t + h) - r.Profile(t)) / h);
  }
  return peak;
}

TEST(ReferenceTest, ProfileEndsAtDistanceWithPeakSlope) {
  struct Case { double D, v, a, start, origin, t_end; };
  // t_end = D/v + v/a (trapezoid) or 2·sqrt(D/a) (triangle, v ≥ sqrt(D·a)).
  const Case cases[] = {
      {0.2, 0.5, 2.0, 0.0, 0.0, 0.2 / 0.5 + 0.5 / 2.0},     // trapezoid
      {-0.2, 0.5, 2.0, 0.3, 0.1, 0.2 / 0.5 + 0.5 / 2.0},    // reversed
      {0.1, 1.0, 2.0, 0.05, 0.0, 2.0 * std::sqrt(0.1 / 2.0)},  // triangle
      {-0.05, 0.4, 1.0, 0.0, -0.02, 2.0 * std::sqrt(0.05 / 1.0)},  // tri.
  };
  for (const Case& k : cases) {
    const Reference r = Trapezoid(k.D, k.v, k.a, k.start, k.origin);
    const double v_peak = std::min(k.v, std::sqrt(std::abs(k.D) * k.a));
    // Starts at the origin, ends at origin + D (exactly: the final branch
    // returns origin + sign·|D|).
    EXPECT_EQ(r.Profile(k.start - 1.0), k.origin);
    EXPECT_EQ(r.Profile(k.start), k.origin);
    EXPECT_EQ(r.Profile(k.start + k.t_end + 1e-9), k.origin + k.D);
    EXPECT_EQ(r.Profile(k.start + k.t_end + 10.0), k.origin + k.D);
    // Just before the end the remaining distance is a/2·r² (r = 1e-4 s);
    // rounding of the 0.2 m sum: 1e-15 m.
    EXPECT_NEAR(r.Profile(k.start + k.t_end - 1e-4),
                k.origin + k.D - std::copysign(0.5 * k.a * 1e-8, k.D),
                1e-12);
    const double h = 1e-5;
    const double peak = PeakSlope(r, k.t_end + 0.1, h);
    std::cout << "D=" << k.D << " v=" << k.v << " a=" << k.a
              << ": peak slope " << peak << " vs min(v, sqrt(D a)) = "
              << v_peak << "\n";
    // A difference quotient over h around the peak of a triangle averages
    // the velocity, losing at most a·h; rounding of positions ≈ 0.3 m over
    // h adds ≈ 1e-11 m/s.
    EXPECT_NEAR(peak, v_peak, k.a * h + 1e-10);
    EXPECT_LE(peak, v_peak + 1e-10);
  }
}

TEST(ReferenceTest, ZeroDistanceStaysAtOrigin) {
  const Reference r = Trapezoid(0.0, 0.5, 2.0, 0.0, 0.125);
  EXPECT_EQ(r.Profile(0.5), 0.125);
  EXPECT_EQ(r.Profile(5.0), 0.125);
}

TEST(SampleReferenceTest, TrapezoidInterpolatesTrackPoints) {
  ControllerConfig c;  // T_s = 5 ms, T_track = 80 ms: 16 samples per track
  for (const Reference& r :
       {Trapezoid(0.2, 0.5, 2.0), Trapezoid(-0.15, 0.3, 1.5, 0.033, 0.05),
        Trapezoid(0.1, 1.0, 2.0, 0.1)}) {
    for (long k = 0; k <= 300; ++k) {
      const long j = k / 16;  // the segment, by integer arithmetic
      const double t = k * c.T_s;
      const double t0 = j * c.T_track;
      const double p0 = r.Profile(t0);
      const double p1 = r.Profile((j + 1) * c.T_track);
      const double slope = (p1 - p0) / c.T_track;
      const ReferenceSample s = SampleReference(r, c, k);
      // Positions ≤ 0.25 m, slopes ≤ 1 m/s: a few roundings, 1e-12.
      EXPECT_NEAR(s.v_ref, slope, 1e-12) << "k = " << k;
      EXPECT_NEAR(s.x_ref, p0 + slope * (t - t0), 1e-12) << "k = " << k;
      if (k % 16 == 0) {  // on a track point the profile itself
        EXPECT_NEAR(s.x_ref, r.Profile(t), 1e-12) << "k = " << k;
      }
    }
    // Long after the move: at rest on the end point.
    const ReferenceSample end = SampleReference(r, c, 1000);
    EXPECT_EQ(end.v_ref, 0.0);
    EXPECT_EQ(end.x_ref, r.origin + r.distance);
  }
}

TEST(SampleReferenceTest, TableReferenceAndBackwardDifference) {
  ControllerConfig c;
  Reference r;
  r.kind = Reference::Kind::kTable;
  r.table.kind = InputSignal::Kind::kTable;
  r.table.times = {0.0, 0.1, 0.2};
  r.table.values = {0.0, 0.01, 0.01};
  EXPECT_EQ(SampleReference(r, c, 0).v_ref, 0.0);
  // 5 ms into the ramp of 0.1 m/s: 0.5 mm; v_ref = 0.1 m/s (1e-12: rounding).
  EXPECT_NEAR(SampleReference(r, c, 1).x_ref, 0.0005, 1e-15);
  EXPECT_NEAR(SampleReference(r, c, 1).v_ref, 0.1, 1e-12);
  EXPECT_NEAR(SampleReference(r, c, 30).v_ref, 0.0, 1e-12);
}

// ----------------------------------------------------------------------------
// Closed loop through Simulate

struct ClosedLoopRun {
  Drive drive;
  SimulationOptions options;
  SimulationGrid grid;
  Trace<double> trace;
};

ClosedLoopRun RunClosedLoop(bool with_injection, double U_max = 10.0) {
  ClosedLoopRun run;
  run.drive.closed_loop = true;  // default ControllerConfig (AID 600)
  run.drive.controller.U_max = U_max;
  run.drive.reference = Trapezoid(0.2, 0.5, 2.0);
  if (with_injection) {
    run.drive.has_injection = true;
    run.drive.injection.kind = InputSignal::Kind::kTable;
    run.drive.injection.times = {0.0, 1.5};
    run.drive.injection.values = {0.5, 0.5};
  }
  run.options.duration = 1.5;
  run.options.step = 1e-5;
  run.options.output_period = 1e-5;  // every RK4 step: see every change of u
  run.options.channels = {Channel::kU, Channel::kX, Channel::kTheta,
                          Channel::kXRef, Channel::kVRef};
  run.grid = MakeGrid(run.options, run.drive);
  run.trace = Simulate(AxisStructure(), AxisParams<double>(),
                       AxisState<double>::Zero().eval(), run.drive,
                       run.options, run.grid);
  return run;
}

// max |u| of the default run below (printed by it): lower U_max saturate.
constexpr double u_abs_max_unsaturated = 6.9;

// Checks u: held over each control period, within ±U_max, and equal to the
// controller replayed on the recorded states (plus `injection`).
void CheckClosedLoop(const ClosedLoopRun& run, double injection,
                     bool settles = true) {
  const Trace<double>& tr = run.trace;
  const ControllerConfig& c = run.drive.controller;
  ASSERT_TRUE(tr.finite);
  ASSERT_EQ(run.grid.steps_per_control, 500);
  ASSERT_EQ(run.grid.steps_per_output, 1);
  const std::vector<double>& u = tr[Channel::kU];
  ASSERT_EQ(u.size(), 150001u);
  long changes = 0, changes_off_grid = 0;
  double u_abs_max = 0.0;
  for (size_t j = 0; j < u.size(); ++j) {
    u_abs_max = std::max(u_abs_max, std::abs(u[j]));
    if (j == 0 || u[j] == u[j - 1]) continue;
    ++changes;
    if (j % 500 != 0) ++changes_off_grid;
  }
  std::cout << "closed loop (injection " << injection << " V): " << changes
            << " changes of u, all at multiples of T_s: "
            << (changes_off_grid == 0) << "; max |u| " << u_abs_max
            << " V; x(1.5 s) " << tr[Channel::kX].back() << " m\n";
  EXPECT_EQ(changes_off_grid, 0);
  EXPECT_GT(changes, 100);  // the controller does act
  EXPECT_LE(u_abs_max, c.U_max + injection);
  if (c.U_max < u_abs_max_unsaturated) {
    EXPECT_EQ(u_abs_max, c.U_max);
  }

  // Replay: the controller fed the recorded motor angle at each control
  // instant, with the reference of that sample, gives the recorded u exactly
  // (same operations on the same doubles).
  ControllerState<double> state;
  const AxisParams<double> p;
  long mismatches = 0;
  for (long k = 0; 500 * k < static_cast<long>(u.size()); ++k) {
    const size_t j = 500 * k;
    const ReferenceSample ref = SampleReference(run.drive.reference, c, k);
    EXPECT_EQ(tr[Channel::kXRef][j], ref.x_ref);
    EXPECT_EQ(tr[Channel::kVRef][j], ref.v_ref);
    double replay = ControllerUpdate(
        c, p, MakeState(tr[Channel::kX][j], tr[Channel::kTheta][j]), ref,
        &state);
    if (injection != 0.0) replay += injection;
    if (u[j] != replay) ++mismatches;
  }
  EXPECT_EQ(mismatches, 0);
  // The 0.2 m move ends at 0.65 s; 0.85 s later the P loop (30 1/s through
  // the 0.1 m/s/V drive) has settled where U = 0, i.e. G_p·e = −injection:
  // x = 0.2 m + injection/G_p (1.67 mm for 0.5 V), to within a few encoder
  // counts of 4.5 µm; 1e-4 m is a loose sanity bound, not a precision claim.
  if (settles) {
    EXPECT_NEAR(tr[Channel::kX].back(), 0.2 + injection / c.G_p, 1e-4);
  }
}

TEST(ClosedLoopSimulateTest, ControllerOutputHeldAndBounded) {
  const ClosedLoopRun run = RunClosedLoop(false);
  CheckClosedLoop(run, 0.0);
}

TEST(ClosedLoopSimulateTest, SaturatedControllerOutputHeldAndBounded) {
  // The default run peaks at 6.93 V; with U_max = 3 V the clamp is active
  // (and the axis, limited to 0.3 m/s, is still 2 mm short at 1.5 s).
  const ClosedLoopRun run = RunClosedLoop(false, 3.0);
  CheckClosedLoop(run, 0.0, /*settles=*/false);
  long at_limit = 0;
  for (double u : run.trace[Channel::kU]) at_limit += std::abs(u) == 3.0;
  std::cout << "U_max = 3 V: " << at_limit << " of "
            << run.trace[Channel::kU].size() << " samples at the limit\n";
  EXPECT_GT(at_limit, 0);
}

TEST(ClosedLoopSimulateTest, InjectionAddsToControllerOutput) {
  const ClosedLoopRun run = RunClosedLoop(true);
  CheckClosedLoop(run, 0.5);
  // First sample: x = θ = 0, x_ref = 0, v_ref = Profile(T_track)/T_track.
  const ControllerConfig& c = run.drive.controller;
  const ReferenceSample ref0 = SampleReference(run.drive.reference, c, 0);
  EXPECT_EQ(ref0.x_ref, 0.0);
  ControllerState<double> s;
  const double u0 = ControllerUpdate(c, AxisParams<double>(),
                                     MakeState(0.0, 0.0), ref0, &s);
  // Hand value: G_ff·v_ref = 10·(a/2·T_track²)/T_track = 10·0.08 = 0.8 V.
  EXPECT_NEAR(u0, 0.8, 1e-12);
  std::cout << "first sample: controller " << u0 << " V, recorded u "
            << run.trace[Channel::kU][0] << " V\n";
  EXPECT_EQ(run.trace[Channel::kU][0], u0 + 0.5);  // the same one addition
  // And with no injection the first recorded u is the controller's alone.
  const ClosedLoopRun plain = RunClosedLoop(false);
  EXPECT_EQ(plain.trace[Channel::kU][0], u0);
  EXPECT_NEAR(run.trace[Channel::kU][0] - plain.trace[Channel::kU][0], 0.5,
              1e-15);  // ulp of 1.3 V
}

}  // namespace
}  // namespace axis
