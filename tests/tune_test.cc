// The tuning of the analog loop (issue 45; tune/step_response.h,
// tune/analog_loop_tuning.h): the step figures against the closed form of
// a second-order response, the paper's own case (section III: T_p reduced
// from 4.74 s; below about 0.04 s the ringing decays too slowly), the
// proposal checked on the axis that made the data, and the `tune:` keys.
#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "estimation/fit.h"
#include "run/load_fit_job.h"
#include "tune/tune_settings.h"
#include "sim/config.h"
#include "tune/analog_loop_tuning.h"
#include "tune/step_response.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;

// v(t) = 1 − e^{−ζω t}(cos ω_d t + ζ/√(1−ζ²)·sin ω_d t), ω_d = ω√(1−ζ²):
// overshoot e^{−πζ/√(1−ζ²)}, peaks of |v − 1| decaying as e^{−ζω t}.
StepResponse SecondOrder(double zeta, double omega, double duration, double dt) {
  StepResponse r;
  const double wd = omega * std::sqrt(1.0 - zeta * zeta);
  for (double t = 0.0; t <= duration + 1e-12; t += dt) {
    const double e = std::exp(-zeta * omega * t);
    r.t.push_back(t);
    r.v.push_back(1.0 - e * (std::cos(wd * t) + zeta / std::sqrt(1.0 - zeta * zeta) *
                                                    std::sin(wd * t)));
    r.i.push_back(0.0);
    r.vm.push_back(0.0);
    r.fg.push_back(0.0);
  }
  return r;
}

TEST(TuneTest, StepFiguresMatchTheSecondOrderClosedForm) {
  const double zeta = 0.2, omega = 2.0 * M_PI * 5.0, dt = 1e-4;
  TuneSpec spec;
  spec.settling_band = 0.02;
  spec.ringing_after = 0.05;
  spec.duration = 3.0;
  const StepMetrics m = MeasureStep(SecondOrder(zeta, omega, 3.0, dt), spec, 95.0);
  // The tail mean is the final value to the size of the ringing left at
  // 2.85 s, e^{−ζω·2.85} ≈ 1.7e-8.
  EXPECT_NEAR(m.final_velocity, 1.0, 1e-7);
  // Sampled every 0.1 ms: the peak within (ω_d·dt)²/2 ≈ 5e-5 of its value.
  EXPECT_NEAR(m.overshoot, std::exp(-M_PI * zeta / std::sqrt(1 - zeta * zeta)), 1e-4);
  // The envelope e^{−ζω t}/√(1−ζ²) crosses the band at t_env; the last
  // exit is within half a period before it.
  const double t_env = -std::log(0.02 * std::sqrt(1 - zeta * zeta)) / (zeta * omega);
  const double period = 2 * M_PI / (omega * std::sqrt(1 - zeta * zeta));
  EXPECT_LE(m.settling_time, t_env + dt);
  EXPECT_GE(m.settling_time, t_env - 0.5 * period);
  EXPECT_TRUE(m.settled);
  // The peaks of |v − 1| lie on the envelope: the e-folding time 1/(ζω)
  // to the sampling of the peaks (relative (ω_d·dt)² ≈ 1e-5).
  EXPECT_NEAR(m.ringing_decay, 1.0 / (zeta * omega), 1e-3 / (zeta * omega));
  EXPECT_DOUBLE_EQ(m.voltage_headroom, 95.0);
  // A bound on each figure: the phrases name them.
  spec.max_overshoot = 0.1;
  spec.max_ringing_decay = 0.1;
  const std::vector<std::string> v = SpecViolations(m, spec);
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[0].rfind("overshoot 0.527 > 0.1", 0), 0u) << v[0];
  EXPECT_EQ(v[1].rfind("ringing decay time 0.159 s > 0.1 s", 0), 0u) << v[1];
  EXPECT_EQ(ViolatedFigures(m, spec), (std::vector<std::string>{"overshoot", "ringing_decay"}));
}

// The paper's case, section III, on its own values (configs/axes/
// x_axis.yaml): lowering T_p from 0.2 s makes the 10 V step's overshoot
// smaller (the transient approaches the manual's), while below about
// 0.04 s the ringing decays more slowly.
TEST(TuneTest, ThePapersSeriesOfStepsInTp) {
  const AxisConfig model = LoadAxisConfig(kRoot + "/configs/axes/x_axis.yaml");
  TuneSpec spec;  // the paper's Fig. 4 step: 10 V, 1.5 s
  const auto at = [&](double T_p) {
    AxisConfig m = model;
    m.params.T_p = T_p;
    return MeasureStep(SimulateStep(m, 1e-5, spec), spec, m.params.V_M);
  };
  double previous = std::numeric_limits<double>::infinity();
  for (double T_p : {0.2, 0.1, 0.06, 0.04, 0.02, 0.01}) {
    const StepMetrics m = at(T_p);
    EXPECT_LT(m.overshoot, previous) << "T_p " << T_p;
    previous = m.overshoot;
  }
  const double decay_04 = at(0.04).ringing_decay;
  EXPECT_GT(at(0.01).ringing_decay, decay_04);
  EXPECT_GT(at(0.005).ringing_decay, decay_04);
}

// Section III as a tuning: T_p lowered until the transient is the
// manual's, and no further because below about 0.04 s the ringing decays
// too slowly. The paper gives neither the manual's response nor a number
// for "too slowly"; as a spec, the ringing's e-folding time bounded at
// 75 ms (on the paper's values it is about 70 ms at T_p = 0.049 s and
// 80 ms at 0.037 s, and grows as T_p falls below 0.09 s) and nothing else
// but the velocity gain. The tuning (the settling time minimised among the
// settings that meet the spec: the trade-off curve, then Brent) on the
// paper job's fit must stop at that edge, near the paper's 0.04 s — between
// the curve's points around it — meet the spec there, and the next lower
// point of the curve must break it.
TEST(TuneTest, ThePapersProcedureStopsNearItsChoiceOfTp) {
  FitJob job = LoadFitJob(kRoot + "/configs/jobs/tune/x_axis_paper.yaml");
  job.problem.solver.progress = false;
  const FitResult result = FitParameters(job.problem, nullptr);
  job.tune.spec = TuneSpec{};
  job.tune.spec.velocity_gain = 0.1;
  job.tune.spec.max_ringing_decay = 0.075;
  job.tune.samples = 0;
  const AnalogLoopTuning t = TuneAnalogLoop(job.problem, result, job.tune);
  ASSERT_TRUE(t.ran) << t.note;
  EXPECT_TRUE(t.proposed.violations.empty());
  EXPECT_GT(t.proposed.T_p, 0.03);
  EXPECT_LT(t.proposed.T_p, 0.055);
  // The curve's first point below the proposal decays too slowly.
  for (const TuningPoint& p : t.curve) {
    if (p.T_p >= t.proposed.T_p) continue;
    EXPECT_GT(p.metrics.ringing_decay, 0.075) << "T_p " << p.T_p;
    break;
  }
}

// The paper's job with `tune:` (configs/jobs/tune/x_axis_paper.yaml):
// the proposal meets the spec at the estimate and over the intervals, and
// on the axis that made the records (the paper's values) too.
TEST(TuneTest, TheProposalMeetsTheSpecOnTheAxisThatMadeTheData) {
  FitJob job = LoadFitJob(kRoot + "/configs/jobs/tune/x_axis_paper.yaml");
  job.problem.solver.progress = false;
  const FitResult result = FitParameters(job.problem, nullptr);
  const AnalogLoopTuning t = TuneAnalogLoop(job.problem, result, job.tune);
  ASSERT_TRUE(t.ran) << t.note;
  EXPECT_TRUE(t.proposed.violations.empty());
  EXPECT_TRUE(t.proposed.robust);
  EXPECT_EQ(t.curve.size(), 25u);
  AxisConfig truth = LoadAxisConfig(kRoot + "/configs/axes/x_axis.yaml");
  truth.params.K1 = t.proposed.K1;
  truth.params.T_p = t.proposed.T_p;
  const TuneSpec& spec = job.tune.spec;
  const StepMetrics m = MeasureStep(SimulateStep(truth, 1e-5, spec), spec, truth.params.V_M);
  EXPECT_TRUE(SpecViolations(m, spec).empty()) << SpecViolations(m, spec)[0];
}

TEST(TuneTest, BadKeysAreRefusedNamingThem) {
  const auto parse = [](const std::string& text) {
    TuneSettings s;
    ParseTuneSettings(YAML::Load(text), "job.yaml", &s);
    return s;
  };
  const TuneSettings ok = parse("{spec: {overshoot: 0.05}, T_p: {low: 0.01, high: 1}}");
  EXPECT_TRUE(ok.enabled);
  EXPECT_DOUBLE_EQ(ok.spec.max_overshoot, 0.05);
  EXPECT_TRUE(std::isnan(ok.spec.max_settling_time));
  const auto message = [&](const std::string& text) {
    try {
      parse(text);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("{spec: {overshoot: -1}}").find("tune.spec.overshoot"), std::string::npos);
  EXPECT_NE(message("{step: {voltage: 12}}").find("tune.step.voltage"), std::string::npos);
  EXPECT_NE(message("{T_p: {low: 1, high: 0.1}}").find("low < high"), std::string::npos);
  EXPECT_NE(message("{spec: {overshot: 0.1}}").find("overshot"), std::string::npos);
  EXPECT_EQ(ok.samples, 32);
  EXPECT_EQ(parse("{samples: 0}").samples, 0);
  EXPECT_NE(message("{samples: -1}").find("tune.samples"), std::string::npos);
  EXPECT_NE(message("{samples: 2.5}").find("tune.samples"), std::string::npos);
}

}  // namespace
}  // namespace axis
