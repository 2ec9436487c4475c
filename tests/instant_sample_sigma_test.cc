// The instant accelerometer's per-sample σ_k at the jumps of y1'
// (estimation/internal/instant_sample_sigma.h, MODEL.md §6), against closed forms:
// a mass driven by a force step, F = g_F·U on M with viscous friction B_a,
// whose acceleration jumps by J = g_F·U/M at the step and then decays as
// J·exp(−B_a·(t − t_s)/M).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "estimation/experiment_cost.h"
#include "estimation/internal/instant_sample_sigma.h"
#include "run/fit_job.h"
#include "sim/simulate.h"

namespace axis {
namespace {

constexpr double kStepTime = 0.1;   // s, on a sample and on the RK4 grid
constexpr double kSigma = 0.02;     // m/s², the channel's noise σ
constexpr double kWindow = 1e-4;    // s, the instant window, one RK4 step

AxisStructure ForceStructure(AccelerometerSampling sampling) {
  AxisStructure s;
  s.amplifier = Amplifier::kForceSource;
  s.coupling = Coupling::kRigid;
  s.accelerometer = sampling;
  s.instant_window = kWindow;
  return s;
}

AxisParams<double> ForceParams() {
  AxisParams<double> p;
  p.g_F = 100.0;  // N/V
  p.M = 10.0;     // kg
  p.B_a = 20.0;   // N·s/m: a decay time M/B_a = 0.5 s
  return p;
}

FitExperiment ForceStep(const AxisStructure& s, const AxisParams<double>& p) {
  FitExperiment e;
  e.name = "force_step";
  e.drive.input.kind = InputSignal::Kind::kStep;
  e.drive.input.amplitude = 2.0;  // V: J = 20 m/s²
  e.drive.input.start = kStepTime;
  e.options.duration = 0.3;
  e.options.step = 1e-4;
  e.options.output_period = 1e-3;
  e.options.channels = {Channel::kA};
  const Trace<double> trace = Simulate(s, p, AxisState<double>::Zero().eval(), e.drive,
                                       e.options, MakeGrid(e.options, e.drive));
  e.t = trace.t;
  e.measured_channels = {Channel::kA};
  e.measured = {trace[Channel::kA]};
  e.fitted = {{Channel::kA, kSigma}};
  return e;
}

// y1' at the instant beside the window mean: the closed form, zero before
// the step (the step applies from the grid point it falls on).
TEST(InstantSampleSigmaTest, PointAccelerationIsTheClosedForm) {
  const AxisStructure s = ForceStructure(AccelerometerSampling::kInstant);
  const AxisParams<double> p = ForceParams();
  FitExperiment e = ForceStep(s, p);
  SimulationOptions options = e.options;
  options.point_acceleration = true;
  const Trace<double> trace = Simulate(s, p, AxisState<double>::Zero().eval(), e.drive,
                                       options, MakeGrid(options, e.drive));
  ASSERT_EQ(trace.a_point.size(), trace.t.size());
  const double jump = p.g_F * 2.0 / p.M;
  for (size_t k = 0; k < trace.t.size(); ++k) {
    const double t = trace.t[k];
    const double exact =
        t < kStepTime - 1e-12 ? 0.0 : jump * std::exp(-p.B_a * (t - kStepTime) / p.M);
    // RK4 at 100 µs on a decay of 0.5 s: relative error ~ (h/τ)^4/120.
    EXPECT_NEAR(trace.a_point[k], exact, 1e-9 * jump) << t;
  }
}

// At the step's sample the window ±w holds the jump at its centre: the mean
// is J/2 + O(B_a·w/M), y1' there is J, so σ_k = √(σ² + (J/2)²). Elsewhere
// the mean of a decaying exponential differs from its value by
// J·(w/τ)²/6 ≈ 3e-7·J, far below σ.
TEST(InstantSampleSigmaTest, TheSampleAtTheJumpGetsHalfTheJump) {
  const AxisStructure s = ForceStructure(AccelerometerSampling::kInstant);
  const AxisParams<double> p = ForceParams();
  const FitExperiment e = ForceStep(s, p);
  const std::vector<double> sigma =
      InstantSampleSigmas(s, p, AxisState<double>::Zero().eval(), e);
  ASSERT_EQ(sigma.size(), e.t.size());
  const double jump = p.g_F * 2.0 / p.M;
  const double tau = p.M / p.B_a;
  for (size_t k = 0; k < e.t.size(); ++k) {
    if (std::abs(e.t[k] - kStepTime) < 1e-9) {
      // The window's decay inside it: the mean is J·(1 − w/(2τ))/2 to first order.
      EXPECT_NEAR(sigma[k], std::hypot(kSigma, jump / 2.0), jump * kWindow / tau) << e.t[k];
    } else if (k + 1 == e.t.size()) {
      // The last sample's window is one-sided, [t − h, t] (MODEL.md §6): its
      // mean is y1'(t − h/2), Δ = y1'(t)·h/(2τ) to first order in h/τ.
      const double a_end = jump * std::exp(-(e.t[k] - kStepTime) / tau);
      const double spread = a_end * e.options.step / (2.0 * tau);
      EXPECT_NEAR(sigma[k], std::hypot(kSigma, spread), 1e-3 * spread) << e.t[k];
    } else {
      EXPECT_NEAR(sigma[k], kSigma, 1e-9) << e.t[k];
    }
  }
  // −2·log L gains log(σ_k²/σ²) for every weighted sample.
  const std::vector<SampleSigmas> weighted = {{sigma}};
  double expected = 0.0;
  for (double s_k : sigma) expected += 2.0 * std::log(s_k / kSigma);
  EXPECT_NEAR(SampleSigmaLogTerm({e}, weighted), expected, 1e-12);
  // The step's sample carries it; the last adds log(1 + (Δ/σ)²) ≈ 0.004.
  EXPECT_NEAR(SampleSigmaLogTerm({e}, weighted),
              2.0 * std::log(std::hypot(kSigma, jump / 2.0) / kSigma), 0.01);
  EXPECT_EQ(SampleSigmaLogTerm({e}, {SampleSigmas{{}}}), 0.0);
}

// Nothing to weigh: the period-mean accelerometer, `a` not fitted, no jump.
TEST(InstantSampleSigmaTest, EmptyWhereThereIsNothingToWeigh) {
  const AxisParams<double> p = ForceParams();
  const AxisStructure mean = ForceStructure(AccelerometerSampling::kPeriodMean);
  EXPECT_TRUE(
      InstantSampleSigmas(mean, p, AxisState<double>::Zero().eval(), ForceStep(mean, p)).empty());
  const AxisStructure instant = ForceStructure(AccelerometerSampling::kInstant);
  FitExperiment not_fitted = ForceStep(instant, p);
  not_fitted.fitted.clear();
  EXPECT_TRUE(
      InstantSampleSigmas(instant, p, AxisState<double>::Zero().eval(), not_fitted).empty());
  FitExperiment smooth = ForceStep(instant, p);
  smooth.drive.input.start = 0.0;  // the jump at t = 0, continued back by y1'(0)
  smooth.drive.input.kind = InputSignal::Kind::kZero;
  EXPECT_TRUE(InstantSampleSigmas(instant, p, AxisState<double>::Zero().eval(), smooth).empty());
}

// The cost divides each residual by its own σ_k.
TEST(InstantSampleSigmaTest, TheCostUsesThePerSampleSigma) {
  const AxisStructure s = ForceStructure(AccelerometerSampling::kInstant);
  const AxisParams<double> p = ForceParams();
  FitExperiment e = ForceStep(s, p);
  for (size_t k = 0; k < e.measured[0].size(); ++k) e.measured[0][k] += 0.01;
  FreeParameter b_a;
  b_a.name = "B_a";
  b_a.initial = 20.0;
  b_a.lower = 1.0;
  b_a.upper = 100.0;
  b_a.scale = 20.0;
  const ParameterMap map(p, {b_a});
  EvaluationCounter counter;
  const std::vector<double> theta = {map.ToInternal(0, 20.0)};
  const std::vector<double> direction = {0.0};
  ExperimentCost plain(s, map, e, 1, -1, &counter);
  std::vector<double> r(e.t.size()), d(e.t.size());
  ASSERT_TRUE(plain.Directional(theta.data(), direction.data(), r.data(), d.data()));
  SampleSigmas sample_sigma = {std::vector<double>(e.t.size(), kSigma)};
  sample_sigma[0][5] = 4.0 * kSigma;
  ExperimentCost weighted(s, map, e, 1, -1, &counter, &sample_sigma);
  std::vector<double> rw(e.t.size());
  ASSERT_TRUE(weighted.Directional(theta.data(), direction.data(), rw.data(), d.data()));
  for (size_t k = 0; k < r.size(); ++k) {
    EXPECT_NEAR(rw[k], k == 5 ? r[k] / 4.0 : r[k], 1e-12) << k;
  }
}

}  // namespace
}  // namespace axis
