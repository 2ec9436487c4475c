// Whether an effect matters (discovery/materiality.h), against a closed
// form: a mass M pushed by a force step F = g_F·U (no friction), its
// period-mean acceleration F/M after the step; a payload ΔM makes it
// F/(M + ΔM), so its contribution is |F/(M + ΔM) − F/M| on every sample
// after the step and 0 before.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "discovery/materiality.h"
#include "estimation/estimation_problem.h"
#include "estimation/fit_result.h"
#include "sim/simulate.h"

namespace axis {
namespace {

constexpr double kSigma = 0.02;   // m/s², the channel's noise σ
constexpr double kForce = 200.0;  // N: g_F 100 N/V · U 2 V
constexpr double kMass = 25.0;    // kg
constexpr int kSamples = 301;     // 0 … 0.3 s at 1 kHz
constexpr int kAfter = 200;       // samples after the step at 0.1 s (its own is 0)

// The problem: the force source on a rigid mass, `a` fitted with σ, the
// payload switched on at `delta_m` (a free parameter).
EstimationProblem PayloadProblem(double delta_m) {
  EstimationProblem problem;
  AxisStructure& s = problem.model.structure;
  s.amplifier = Amplifier::kForceSource;
  s.coupling = Coupling::kRigid;
  s.effects.payload = true;
  AxisParams<double>& p = problem.model.params;
  p.g_F = 100.0;
  p.M = kMass;
  p.B_a = 0.0;
  p.Delta_M = delta_m;
  FitExperiment e;
  e.name = "step";
  e.drive.input.kind = InputSignal::Kind::kStep;
  e.drive.input.amplitude = 2.0;
  e.drive.input.start = 0.1;
  e.options.duration = 0.3;
  e.options.step = 1e-4;
  e.options.output_period = 1e-3;
  e.options.channels = {Channel::kA};
  for (int k = 0; k < kSamples; ++k) e.t.push_back(k * 1e-3);
  e.measured_channels = {Channel::kA};
  e.measured = {std::vector<double>(kSamples, 0.0)};
  e.fitted = {{Channel::kA, kSigma}};
  problem.experiments = {e};
  FreeParameter f;
  f.name = "Delta_M";
  f.initial = delta_m;
  f.lower = -1.0;
  f.upper = 10.0;
  problem.free = {f};
  return problem;
}

FitResult FitAt(double delta_m) {
  FitResult fit;
  ParameterEstimate e;
  e.name = "Delta_M";
  e.value = delta_m;
  e.free = true;
  fit.parameters = {e};
  fit.free_names = {"Delta_M"};
  return fit;
}

// The closed form's share of σ.
double Share(double delta_m) {
  const double d = kForce / (kMass + delta_m) - kForce / kMass;
  return std::sqrt(static_cast<double>(kAfter) / kSamples) * std::abs(d) / kSigma;
}

TEST(MaterialityTest, ContributionIsTheClosedForm) {
  for (double delta_m : {0.0025, 0.05, 1.0}) {
    const Contribution c = EffectContribution("payload", PayloadProblem(delta_m), FitAt(delta_m));
    // The period mean of a constant acceleration is exact; the RK4 grid
    // puts the step on a sample (1e-12 relative: rounding).
    EXPECT_NEAR(c.share, Share(delta_m), 1e-9 * Share(delta_m) + 1e-12) << delta_m;
    EXPECT_EQ(c.channel, "step/a");
    EXPECT_DOUBLE_EQ(c.value, delta_m);
    EXPECT_DOUBLE_EQ(c.floor, 0.01 * kMass);
  }
}

// 2.5 g on 25 kg: 0.03·σ and below the 0.25 kg floor — negligible. 50 g:
// 0.65·σ, material though below the floor. 1 kg: above the floor.
TEST(MaterialityTest, NegligibleBelowTheShareAndTheFloor) {
  const Contribution grams = EffectContribution("payload", PayloadProblem(0.0025), FitAt(0.0025));
  EXPECT_LT(grams.share, kMaterialShare);
  EXPECT_FALSE(grams.material);
  const std::string note = NegligibleNote("payload", grams);
  EXPECT_NE(note.find("significant but negligible"), std::string::npos) << note;
  EXPECT_NE(note.find("below its physical floor 0.25 kg"), std::string::npos) << note;
  const Contribution some = EffectContribution("payload", PayloadProblem(0.05), FitAt(0.05));
  EXPECT_GT(some.share, kMaterialShare);
  EXPECT_TRUE(some.material);
  EXPECT_TRUE(EffectContribution("payload", PayloadProblem(1.0), FitAt(1.0)).material);
}

}  // namespace
}  // namespace axis
