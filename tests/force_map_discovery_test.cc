// The force-map step of the discovery loop (issue 15, discovery/force_map.h) on
// data with a force the library of MODEL.md §7 does not have — a friction
// patch over part of the travel, a friction bump at one speed
// (testdata/generate/discover/, generator-only effects) — and on data whose
// missing force is a library effect (Coulomb friction, a spring), which the
// library must keep: no map then.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "discovery/discovery.h"
#include "discovery/force_map.h"
#include "discovery/internal/screen.h"
#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "run/job_run.h"
#include "run/write_job_run.h"
#include "sim/axis_model.h"
#include "sim/config.h"
#include "sim/experiment.h"
#include "sim/simulate.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;

// The committed job with the library cut to the load-side effects that can
// stand in for these forces (the whole library, as committed, takes about
// 110 s a case here: README "Force maps"; its campaigns measure it), one of
// them at most: the step after the loop is what is tested.
JobRun RunCase(const std::string& name) {
  FitJob job = LoadFitJob(kRoot + "/configs/jobs/discover/" + name + ".yaml");
  job.problem.solver.progress = false;
  job.discover.candidates = {"coulomb", "load_offset", "spring"};
  job.discover.max_effects = 1;
  std::ostringstream out;
  return RunJob(job, true, out);
}

// The force a model resists steady motion at (x, v) with, as a load-side
// force: B_a·v and every load force of MODEL.md §7 (and the generator's),
// plus the motor side's B_m·ω and torque effects through the gear (/r_g),
// from AxisDerivative with the gear centred (no contact force), the motor
// at ω = v/r_g and no current: −M·y1' − J_m·y3'/r_g.
double LoadForce(const AxisConfig& model, const AxisParams<double>& p, double x, double v) {
  AxisState<double> y = AxisState<double>::Zero();
  y[0] = x;
  y[1] = v;
  y[2] = x / p.r_g;
  y[3] = v / p.r_g;
  AxisState<double> dy;
  AxisDerivative(model.structure, p, y, 0.0, &dy);
  const double mass = p.M + (model.structure.effects.payload ? p.Delta_M : 0.0);
  return -mass * dy[1] - p.J_m * dy[3] / p.r_g;
}

// RMS over the states (x, v) each fitted experiment's generating model
// visits (its clean simulation) of the true load force beyond the viscous
// B_a·v + B_m·ω/r_g (`truth`), and of the error of the learned model's.
struct ForceError {
  double truth_rms = 0.0;
  double error_rms = 0.0;
};

ForceError CompareLoadForce(const std::string& name, const JobRun& run) {
  double truth2 = 0.0, error2 = 0.0;
  int n = 0;
  for (const FitExperiment& e : run.job.problem.experiments) {
    const ExperimentConfig generating =
        LoadExperiment(kRoot + "/testdata/generate/discover/" + name + "_" + e.name + ".yaml");
    SimulationOptions options = generating.options;
    options.channels = {Channel::kX, Channel::kV};
    const Trace<double> trace =
        Simulate(generating.model.structure, generating.model.params, generating.initial_state,
                 generating.drive, options, MakeGrid(options, generating.drive));
    const std::vector<double>& x = trace[Channel::kX];
    const std::vector<double>& v = trace[Channel::kV];
    for (size_t k = 0; k < x.size(); ++k) {
      const double truth = LoadForce(generating.model, generating.model.params, x[k], v[k]);
      const double learned = LoadForce(run.job.problem.model, run.job.problem.model.params, x[k], v[k]);
      const AxisParams<double>& p = generating.model.params;
      const double viscous = p.B_a * v[k] + p.B_m * v[k] / (p.r_g * p.r_g);
      truth2 += (truth - viscous) * (truth - viscous);
      error2 += (learned - truth) * (learned - truth);
      ++n;
    }
  }
  return {std::sqrt(truth2 / n), std::sqrt(error2 / n)};
}

// Σ RMS² over the report's channels, before (library) or after (map).
double SumOfSquares(const ForceMapReport& r, double ChannelChange::*rms) {
  double s = 0.0;
  for (const ChannelChange& c : r.channels) s += (c.*rms) * (c.*rms);
  return s;
}

// *stopped: how many forms stopped under the level (discovery/internal/screen.h).
void ExpectLearned(const std::string& name, const std::string& kind, int* stopped) {
  const JobRun run = RunCase(name);
  const ForceMapReport& map = run.force_map;
  EXPECT_EQ(run.discovery.verdict.verdict, "incomplete");  // the library alone
  ASSERT_TRUE(map.tried) << map.reason;
  ASSERT_TRUE(map.kept) << FormatForceMap(map);
  EXPECT_EQ(map.kind, kind) << FormatForceMap(map);
  EXPECT_LT(map.bic_after, map.bic_before);
  EXPECT_LT(SumOfSquares(map, &ChannelChange::rms_after),
            SumOfSquares(map, &ChannelChange::rms_before));
  EXPECT_TRUE(run.job.problem.model.structure.force_map.enabled);
  EXPECT_FALSE(map.significant.empty());
  // The learned load force along the visited states accounts for at least
  // 65 % of the missing force's RMS (the rest of the model, B_a included,
  // takes part: the comparison is of the whole load force). Not a noise
  // bound: the knots (about 2.5 cm apart over the patch) cannot follow the
  // patch's 5 mm edges. Measured: 72 % (friction patch) and 85 % (velocity
  // bump) here, 73 % and 86 % with the whole library.
  const ForceError f = CompareLoadForce(name, run);
  std::cout << name << ": missing force RMS " << f.truth_rms << " N, learned load force error RMS "
            << f.error_rms << " N\n" << FormatForceMap(map);
  EXPECT_LT(f.error_rms, 0.35 * f.truth_rms);
  // The forms (discovery/internal/screen.h): the winner ran to the end; a form stopped
  // under the level names the leader (the first form, by score) and ended
  // with a BIC bound above kStopFactor times the leader's BIC. The stop
  // compares with the leader's fit BIC (2·cost + n·ln(m), its roughness
  // penalty included: 4.33e4 on the velocity bump job); the table's edf
  // BIC (Σr² + edf·ln(m): 2.95e4 there) is at most that, so the bound is
  // above twice it too (0.99: both from the same residuals, up to
  // round-off).
  ASSERT_FALSE(map.forms.empty());
  const ForceMapForm& leader = map.forms.front();
  EXPECT_EQ(leader.stopped, "");
  *stopped = 0;
  for (const ForceMapForm& form : map.forms) {
    if (form.name == "force_map." + kind) {
      EXPECT_EQ(form.stopped, "") << form.name;
    }
    if (form.stopped.empty()) continue;
    ++*stopped;
    EXPECT_NE(form.stopped.find(leader.name + "'s fit BIC"), std::string::npos) << form.stopped;
    EXPECT_GT(form.bic, 0.99 * kStopFactor * leader.bic) << form.name;
  }
  ::testing::Test::RecordProperty("forms_stopped", *stopped);
  // The backward pass: a refit without an effect that ends within the
  // solver's accuracy of the BIC with it (the effect moved into the map
  // whole) removes it.
  for (const ForceMapRemoval& r : map.removals) {
    if (std::abs(r.bic_without - r.bic_with) <= 1e-9 * r.bic_with) {
      EXPECT_TRUE(r.removed) << r.effect;
    }
  }
  // The outputs: the force with its band, and model_discovered.yaml, which
  // carries the map and which simulate-axis replays.
  const std::string dir = testing_files::TestTempDir() + "out";
  WriteJobRun(run, dir);
  EXPECT_TRUE(std::filesystem::exists(dir + "/force_map.csv"));
  std::ifstream html_file(dir + "/report.html");
  const std::string html((std::istreambuf_iterator<char>(html_file)), {});
  EXPECT_NE(html.find("<section id=\"force-map\">"), std::string::npos);
  EXPECT_NE(html.find("The learned load force (N)"), std::string::npos);
  const AxisConfig back = LoadAxisConfig(dir + "/model_discovered.yaml");
  EXPECT_EQ(back.structure.force_map.knots, run.job.problem.model.structure.force_map.knots);
  EXPECT_EQ(back.params.f_map, run.job.problem.model.params.f_map);
  const std::string experiment = testing_files::WriteTemp(
      "replay.yaml", "model: " + dir +
                         "/model_discovered.yaml\nduration: 1.0\nstep: 1.0e-4\noutput_rate: "
                         "1000\nchannels: [u, a, tach, i]\ninput: {type: sine, amplitude: 3, "
                         "frequency: 1}\n");
  const auto r = testing_files::RunCommand(std::string(BINARY_DIR) + "/simulate-axis",
                                           experiment + " --out " + dir + "/replay.csv", true);
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(ForceMapDiscoveryTest, FrictionPatchIsLearnedAsFrictionAlongTheTravel) {
  int stopped = -1;
  ExpectLearned("friction_patch", "x_friction", &stopped);
}

// f(v) is first by score and leads; f(x) and f(x)·sgn(v) stop under its
// level at the 0.4 s horizon, their bounds (1.72e5, 1.81e5) 40 % above
// twice its BIC (6.02e4), where with the whole record they would have
// ended 6 times above it.
TEST(ForceMapDiscoveryTest, VelocityBumpIsLearnedAsAFunctionOfTheVelocity) {
  int stopped = -1;
  ExpectLearned("velocity_bump", "v", &stopped);
  EXPECT_EQ(stopped, 2);
}

// A library effect as the truth: the loop explains the data with it alone
// and no map is fitted.
void ExpectLibraryEffectWins(FitJob job, const std::string& effect) {
  job.problem.solver.progress = false;
  std::ostringstream out;
  const JobRun run = RunJob(job, true, out);
  EXPECT_EQ(run.discovery.selected, std::vector<std::string>{effect});
  EXPECT_EQ(run.discovery.verdict.verdict, "explained");
  EXPECT_FALSE(run.force_map.tried) << run.force_map.reason;
  EXPECT_FALSE(run.job.problem.model.structure.force_map.enabled);
}

TEST(ForceMapDiscoveryTest, CoulombFrictionStaysALibraryEffect) {
  FitJob job = LoadFitJob(kRoot + "/configs/jobs/discover/coulomb.yaml");
  job.problem.solver.progress = false;
  job.discover.force_map = true;
  ExpectLibraryEffectWins(job, "coulomb");
}

TEST(ForceMapDiscoveryTest, SpringStaysALibraryEffect) {
  // The power_spring campaign's data (seed 0: the generating configs' own
  // seeds), fitted by the "none" job with the force map on.
  const std::string dir = testing_files::TestTempDir();
  for (const char* e : {"step_p4V", "step_m2V", "sine", "slow_sine"}) {
    const std::string config = kRoot + "/configs/campaigns/generate/power/spring_" + e + ".yaml";
    const auto r = testing_files::RunCommand(std::string(BINARY_DIR) + "/simulate-axis",
                                             config + " --out " + dir + "spring_" + e + ".csv",
                                             true);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  std::ifstream in(kRoot + "/configs/jobs/discover/none.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const auto replace = [&](const std::string& from, const std::string& to) {
    for (size_t at; (at = text.find(from)) != std::string::npos;) text.replace(at, from.size(), to);
  };
  replace("../../../testdata/discover/none_", dir + "spring_");
  replace("../../axes", kRoot + "/configs/axes");
  replace("../../../build/fit/discover_none", dir + "out");
  text.replace(text.find("discover:\n"), 10, "discover:\n  force_map: true\n");
  FitJob job = ParseFitJob(ParseYamlText(text, "spring.yaml"), "spring.yaml", dir);
  job.problem.solver.progress = false;
  ExpectLibraryEffectWins(job, "spring");
}

// A map learned on a rotary axis speaks its units: the variable in rad
// (rad/s for f(v)), the values in N*m, in the text, report.json and the
// plot; a linear axis keeps m and N.
TEST(ForceMapReportTest, ARotaryAxisMapIsInRadiansAndNewtonMetres) {
  ForceMapReport report;
  report.tried = true;
  report.kept = true;
  report.reason = "binned structure along the travel";
  report.kind = "x";
  report.map.enabled = true;
  report.map.knots = {0.0, 1.0, 2.0, 3.0};
  report.values = {0.1, -0.2, 0.3, 0.0};
  report.std_errors = {0.01, 0.01, 0.01, 0.01};
  report.lambda = 2.0;
  report.rotary = true;
  const std::string text = FormatForceMap(report);
  EXPECT_NE(text.find("] rad\n"), std::string::npos) << text;
  EXPECT_NE(text.find("knot (rad)"), std::string::npos) << text;
  EXPECT_NE(text.find("torque (N*m)"), std::string::npos) << text;
  EXPECT_NE(text.find("lambda (1/(N*m)^2)"), std::string::npos) << text;
  EXPECT_EQ(text.find("(N)"), std::string::npos) << text;
  const nlohmann::json json = ForceMapToJson(report);
  EXPECT_EQ(json["variable_unit"], "rad");
  EXPECT_EQ(json["value_unit"], "N*m");
  EXPECT_NE(ForceMapPlotScript(report, "m.csv", "m.png", false).find("set ylabel 'torque (N*m)'"),
            std::string::npos);
  report.map.variable = ForceMapVariable::kV;
  EXPECT_NE(FormatForceMap(report).find("knot (rad/s)"), std::string::npos);
  report.rotary = false;
  report.map.variable = ForceMapVariable::kX;
  const std::string linear = FormatForceMap(report);
  EXPECT_NE(linear.find("knot (m)"), std::string::npos) << linear;
  EXPECT_NE(linear.find("force (N)"), std::string::npos) << linear;
  EXPECT_NE(linear.find("lambda (1/N^2)"), std::string::npos) << linear;
}

}  // namespace
}  // namespace axis
