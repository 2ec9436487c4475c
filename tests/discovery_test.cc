// The discovery loop (issue 4) on data with an effect the fitting job does
// not declare (testdata/discover/, generated from testdata/generate/discover/
// with the noise of the fit-params data). Only the paper's five unknowns are
// free in configs/jobs/discover/*.yaml.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "common/statistics.h"
#include "discovery/candidates.h"
#include "discovery/diagnostics.h"
#include "discovery/discovery.h"
#include "discovery/removal.h"
#include "estimation/fit.h"
#include "estimation/fit_result.h"
#include "discovery/discovery_settings.h"
#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "run/campaign.h"
#include "run/job_run.h"
#include "run/write_job_run.h"
#include "io/csv.h"
#include "sim/experiment.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;

struct Outcome {
  FitJob job;
  FitResult result;
  DiscoveryReport report;
};

Outcome RunCase(const std::string& name) {
  Outcome o;
  o.job = LoadFitJob(kRoot + "/configs/jobs/discover/" + name + ".yaml");
  o.job.problem.solver.progress = false;
  o.result = FitParameters(o.job.problem);
  o.report = Discover(o.job.discover, &o.job.problem, &o.result, nullptr);
  return o;
}

const ParameterEstimate* Estimate(const FitResult& r, const std::string& name) {
  for (const ParameterEstimate& p : r.parameters) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

// The estimate of `param` within 10 % of `truth` (the band) and
// within 4 of its standard errors (with the effect in the model the fit is
// the generating model: |estimate − truth| beyond 4 standard errors has
// probability 6e-5 if the standard errors are right).
void ExpectNearTruth(const FitResult& r, const std::string& param, double truth) {
  const ParameterEstimate* p = Estimate(r, param);
  ASSERT_NE(p, nullptr) << param << " is not in the fit";
  EXPECT_NEAR(p->value / truth, 1.0, 0.10) << param << " = " << p->value;
  EXPECT_LE(std::abs(p->value - truth), 4.0 * p->std_error)
      << param << " = " << p->value << " ± " << p->std_error << ", truth " << truth;
}

// After the loop the fitted channels are at the noise level: RMS within 20 %
// of σ (the bound; with ~2000 samples the RMS of pure noise is
// within ~5 % of σ).
void ExpectNoiseLevel(const Outcome& o) {
  for (const ExperimentFit& e : o.result.experiments) {
    for (const ChannelFit& c : e.channels) {
      if (!c.fitted) continue;
      EXPECT_NEAR(c.rms / c.sigma, 1.0, 0.2) << e.name << " " << c.channel;
    }
  }
}

// The final model is the generating one: its residual is the noise, and
// the verdict says so (the verdict's tests, family-wise at α = 1e-3, call a
// right model incomplete with probability ≤ 1e-3).
void ExpectExplained(const Outcome& o) {
  EXPECT_EQ(o.report.verdict.verdict, "explained") << FormatVerdict(o.report.verdict);
  EXPECT_NEAR(o.report.verdict.s2, 1.0, 0.1);
}

// Ends with `effect` and nothing else selected, with `param` near `truth`
// (ExpectNearTruth).
void ExpectFound(const Outcome& o, const std::string& effect, const std::string& param,
                 double truth) {
  // The final set; an effect added on the way as a stand-in and dropped by
  // the backward pass (report.removed) is allowed.
  EXPECT_EQ(o.report.selected, std::vector<std::string>{effect}) << o.report.stop_reason;
  ExpectNearTruth(o.result, param, truth);
  ExpectExplained(o);
  for (const DiscoveryStep& s : o.report.steps) {
    for (const ParameterEstimate& p : s.parameters) {
      ::testing::Test::RecordProperty(p.name, std::to_string(p.value) + " +- " + std::to_string(p.std_error));
    }
  }
  ExpectNoiseLevel(o);
}

void ExpectFound(const std::string& name, const std::string& effect,
                 const std::string& param, double truth) {
  ExpectFound(RunCase(name), effect, param, truth);
}

// The coulomb case as fit-params runs it (RunJob, then WriteJobRun): the
// effect is found, and the written report's after-discovery RMS equals a
// recomputation from fit_<experiment>.csv, and the discovered model loads
// as a model config.
TEST(DiscoveryTest, Coulomb) {
  FitJob job = LoadFitJob(kRoot + "/configs/jobs/discover/coulomb.yaml");
  job.problem.solver.progress = false;
  std::ostringstream sink;
  JobRun run = RunJob(job, /*discover=*/true, sink);
  ASSERT_TRUE(run.discovered);
  Outcome o{run.job, run.result, run.discovery};
  ExpectFound(o, "coulomb", "F_c", 30.0);

  const std::string out = axis::testing_files::TestTempDir() + "discover_coulomb";
  std::filesystem::remove_all(out);
  WriteJobRun(run, out);
  std::ifstream in(out + "/report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  const nlohmann::json& step = report["discovery"]["steps"][0];
  EXPECT_EQ(step["effect"], "coulomb");
  for (const nlohmann::json& c : step["channels"]) {
    const std::string experiment = c["experiment"];
    const std::string channel = c["channel"];
    const CsvTable t = ReadCsv(out + "/fit_" + experiment + ".csv");
    const std::vector<double>& residual = t.Column(channel + "_residual");
    double sum = 0.0;
    for (double r : residual) sum += r * r;
    const double rms = std::sqrt(sum / residual.size());
    // The CSV holds 12 significant digits.
    EXPECT_NEAR(rms, c["rms_after"].get<double>(), 1e-9 * (1 + rms))
        << experiment << " " << channel;
  }
  const AxisConfig discovered = LoadAxisConfig(out + "/model_discovered.yaml");
  EXPECT_TRUE(discovered.structure.effects.coulomb);
  EXPECT_NEAR(discovered.params.F_c, 30.0, 3.0);
  // Every significant candidate is refitted here (s² = 26.5): those whose
  // BIC's lower bound passes twice Coulomb friction's on a shorter horizon
  // stop there (issue 11), with no values or channels reported.
  int stopped = 0;
  for (const DiscoveryStep& s : run.discovery.steps) {
    if (s.stopped.empty()) continue;
    ++stopped;
    EXPECT_FALSE(s.kept) << s.effect;
    EXPECT_GT(s.bic_after, 2.0 * run.result.bic) << s.effect;
    EXPECT_TRUE(s.parameters.empty()) << s.effect;
    EXPECT_TRUE(s.channels.empty()) << s.effect;
  }
  EXPECT_GE(stopped, 1);
}
// A 60 N offset preloads the gear backlash: from the job's start the base
// fit ends in a local minimum (T_p at its bound) where the score test ranks
// Coulomb first; the job's 3 random starts find the better one, where the
// offset ranks first.
// The offset is seventh by score here (s² = 317: every significant
// candidate is refitted): the screen of the refits (their first four
// horizons) puts it first, its refit sets the level, and the others stop
// early (issue 11). Without the screen, in score order, only one of the
// eight others stopped.
TEST(DiscoveryTest, LoadOffset) {
  const Outcome o = RunCase("load_offset");
  ExpectFound(o, "load_offset", "F_0", 60.0);
  int stopped = 0;
  for (const DiscoveryStep& s : o.report.steps) {
    if (s.effect == "load_offset") {
      EXPECT_TRUE(s.stopped.empty());
    }
    stopped += !s.stopped.empty();
  }
  EXPECT_GE(stopped, 5);
}
// The base fit is far off (s² = 89.5) and the payload only ninth by score
// (χ² 229 against Coulomb friction's 1.76e4): refitting only the top three
// (`misspecified_tries: 3`) kept Coulomb friction first and needed the
// backward pass; refitting every significant candidate (the default) keeps
// the payload first (BIC 1.19e4 against 1.03e5 for the offset's refit).
TEST(DiscoveryTest, Payload) {
  const Outcome o = RunCase("payload");
  ExpectFound(o, "payload", "Delta_M", 25.0);
  std::string first;
  for (const DiscoveryStep& s : o.report.steps) {
    if (s.kept && !s.removal) {
      first = s.effect;
      break;
    }
  }
  EXPECT_EQ(first, "payload");
  EXPECT_TRUE(o.report.removed.empty());
}
TEST(DiscoveryTest, SensorDelay) {
  ExpectFound("sensor_delay", "sensor_delay.a", "tau_d.a", 0.002);
}
TEST(DiscoveryTest, Cogging) { ExpectFound("cogging", "cogging", "A_cog", 0.02); }
TEST(DiscoveryTest, ViscousAsymmetry) {
  ExpectFound("viscous_asymmetry", "viscous_asymmetry", "Delta_B", 60.0);
}

// Two effects: exactly these two are selected, each near the truth. The
// backward pass refitted without every added effect but the last (an
// effect added on the way, e.g. cogging standing in for the still missing
// Coulomb friction, may be dropped there): one removal step each, and an
// effect is listed as removed exactly when its removal step improved BIC.
TEST(DiscoveryTest, CoulombAndLoadOffset) {
  const Outcome o = RunCase("coulomb_load_offset");
  std::vector<std::string> sorted = o.report.selected;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, (std::vector<std::string>{"coulomb", "load_offset"}))
      << o.report.stop_reason;
  ExpectNearTruth(o.result, "F_0", 60.0);
  ExpectNearTruth(o.result, "F_c", 30.0);
  size_t added = 0, removals = 0;
  for (const DiscoveryStep& s : o.report.steps) {
    if (!s.removal) {
      added += s.kept;
      continue;
    }
    const bool removed = std::find(o.report.removed.begin(), o.report.removed.end(),
                                   s.effect) != o.report.removed.end();
    EXPECT_EQ(s.kept, removed) << s.effect;
    // A removal for lack of significance (after the backward pass) is
    // removed whatever BIC says; a backward-pass removal by BIC.
    if (!s.insignificant.empty()) continue;
    ++removals;
    EXPECT_EQ(s.kept, s.bic_after < s.bic_before) << s.effect;
  }
  EXPECT_EQ(added, o.report.selected.size() + o.report.removed.size());
  EXPECT_EQ(removals, added - 1);
  // Each effect left is significant at the loop's level.
  ASSERT_EQ(o.report.significance.size(), o.report.selected.size());
  for (const EffectSignificance& w : o.report.significance) {
    EXPECT_LT(w.p_value, o.report.level) << w.effect;
  }
  std::string selected;
  for (const std::string& e : o.report.selected) selected += e + " ";
  RecordProperty("selected", selected);
  ExpectNoiseLevel(o);
  ExpectExplained(o);
}

// Coulomb friction and viscous asymmetry together (issue 10, misspecified
// start): the base fit is far from the data (s² ≈ 48) and the score test
// ranks motor-side Coulomb friction first (χ² 1.85e5). With the score order
// alone the loop kept motor_coulomb, cogging and coulomb and ended
// `incomplete` at s² = 7.5 (measured before the refit rule); refitting the
// top candidates and keeping the lowest BIC finds exactly the two effects.
TEST(DiscoveryTest, CoulombAndViscousAsymmetryChosenByRefit) {
  const Outcome o = RunCase("coulomb_viscous_asymmetry");
  std::vector<std::string> sorted = o.report.selected;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, (std::vector<std::string>{"coulomb", "viscous_asymmetry"}))
      << o.report.stop_reason;
  ExpectNearTruth(o.result, "F_c", 30.0);
  ExpectNearTruth(o.result, "Delta_B", 60.0);
  ASSERT_FALSE(o.report.steps.empty());
  EXPECT_NE(o.report.steps.front().rule.find("lowest BIC"), std::string::npos)
      << o.report.steps.front().rule;
  ExpectNoiseLevel(o);
  ExpectExplained(o);
}

// No effect in the data: nothing is added (no false discovery). Then, from
// the same base fit, `discover.tries`: with every candidate counted
// significant (alpha above the number of candidates, so that the Bonferroni
// threshold exceeds 1) no refit improves BIC (a parameter costs ln n ≈ 10
// against a cost gain of about ½χ²₁ on noise), and the loop refits exactly
// `tries` candidates, in rank order, then stops.
TEST(DiscoveryTest, NoEffectAddsNothing) {
  Outcome o;
  o.job = LoadFitJob(kRoot + "/configs/jobs/discover/none.yaml");
  o.job.problem.solver.progress = false;
  o.result = FitParameters(o.job.problem);
  FitJob job = o.job;
  FitResult base = o.result;
  o.report = Discover(o.job.discover, &o.job.problem, &o.result, nullptr);
  EXPECT_TRUE(o.report.selected.empty()) << o.report.selected.front();
  EXPECT_TRUE(o.report.steps.empty());
  ExpectNoiseLevel(o);
  ExpectExplained(o);

  DiscoverySettings everything = job.discover;
  everything.alpha = 1e3;
  everything.tries = 2;
  const DiscoveryReport tried = Discover(everything, &job.problem, &base, nullptr);
  EXPECT_TRUE(tried.selected.empty());
  ASSERT_EQ(tried.steps.size(), 2u) << tried.stop_reason;
  ASSERT_GE(tried.ranking.scores.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(tried.steps[i].effect, tried.ranking.scores[i].name) << i;
    EXPECT_FALSE(tried.steps[i].kept) << tried.steps[i].effect;
    EXPECT_FALSE(tried.steps[i].removal);
  }
  EXPECT_NE(tried.stop_reason.find("no significant candidate improved BIC"), std::string::npos)
      << tried.stop_reason;
}

// The stand-in rule (issue 10): an effect whose parameter cannot be told
// from its off value leaves the final model whatever BIC says. The no-effect
// data fitted with a load offset F_0 declared free (from 5 N): F_0 ends
// within a few standard errors of 0 and DropInsignificant refits it away,
// leaving the declared model; on the load-offset data F_0 = 60 N stays.
// Without the rule the first model would keep F_0.
TEST(DiscoveryTest, EffectAtItsOffValueIsDropped) {
  for (const std::string name : {"none", "load_offset"}) {
    FitJob job = LoadFitJob(kRoot + "/configs/jobs/discover/" + name + ".yaml");
    job.problem.solver.progress = false;
    job.problem.validate.clear();
    job.problem.model.structure.effects.load_offset = true;
    FreeParameter f;
    f.name = "F_0";
    f.unit = "N";
    f.initial = 5.0;
    f.lower = -200.0;
    f.upper = 200.0;
    job.problem.free.push_back(f);
    job.problem.model.params.F_0 = f.initial;
    FitResult result = FitParameters(job.problem);
    DiscoveryReport report;
    report.selected = {"load_offset"};
    const double level = 1e-4;
    DropInsignificant(level, &job.problem, &result, &report, nullptr);
    if (name == "none") {
      EXPECT_TRUE(report.selected.empty());
      EXPECT_EQ(report.removed, std::vector<std::string>{"load_offset"});
      ASSERT_EQ(report.steps.size(), 1u);
      EXPECT_TRUE(report.steps[0].removal);
      EXPECT_NE(report.steps[0].insignificant.find("not distinguishable from off"),
                std::string::npos) << report.steps[0].insignificant;
      EXPECT_FALSE(job.problem.model.structure.effects.load_offset);
      for (const FreeParameter& g : job.problem.free) EXPECT_NE(g.name, "F_0");
      EXPECT_TRUE(report.significance.empty());
    } else {
      EXPECT_EQ(report.selected, std::vector<std::string>{"load_offset"});
      EXPECT_TRUE(report.steps.empty());
      ASSERT_EQ(report.significance.size(), 1u);
      EXPECT_LT(report.significance[0].p_value, level);
      ExpectNearTruth(result, "F_0", 60.0);
    }
  }
}

// When the library runs out the verdict says so (issue 10): the Coulomb
// data with the candidates restricted to effects that cannot express a
// velocity-sign step (cogging, payload, spring), one step with one refit
// (measured with three steps: cogging kept, then payload and spring
// rejected, s² = 21.8).
// Whatever the loop adds leaves a residual far above the noise that depends
// on the velocity:
// `incomplete`, s² far above 1, a binned-v structure named, and the
// selected effects flagged as possible stand-ins.
TEST(DiscoveryTest, LibraryRunsOutVerdictIsIncomplete) {
  FitJob job = LoadFitJob(kRoot + "/configs/jobs/discover/coulomb.yaml");
  job.problem.solver.progress = false;
  job.problem.validate.clear();
  job.discover.candidates = {"cogging", "payload", "spring"};
  job.discover.max_effects = 1;  // one step shows it
  job.discover.tries = 1;        // and one refit, the top-ranked candidate's,
  job.discover.misspecified_tries = 1;  // also when s² > 2 (it is: 21.8)
  FitResult result = FitParameters(job.problem);
  const DiscoveryReport report = Discover(job.discover, &job.problem, &result, nullptr);
  EXPECT_EQ(report.verdict.verdict, "incomplete");
  EXPECT_GT(report.verdict.s2, 2.0);
  bool velocity = false;
  for (const std::string& r : report.verdict.remains) {
    velocity = velocity || r.find("depends on v") != std::string::npos;
  }
  EXPECT_TRUE(velocity) << FormatVerdict(report.verdict);
  const nlohmann::json j = DiscoveryToJson(report);
  EXPECT_EQ(j["verdict"], "incomplete");
  EXPECT_EQ(j["verdict_detail"]["stand_ins_possible"], !report.selected.empty());
  EXPECT_NE(FormatDiscovery(report).find("Verdict: incomplete"), std::string::npos);
}

// Values without physical meaning are named (issue 10): a negative payload
// (seen: -4.4 kg on unseen data) and a friction level below zero (issue 42:
// T_c = -0.0197 N*m accepted on records behind an anti-alias filter); a
// front-end term is physical at any length (issue 42: a sensor delay of
// 0.207 ms, below the 1 ms sample period, is what an anti-alias filter
// gives); the committed cases' values (25 kg, 2 ms, 40 N) pass.
TEST(DiscoveryTest, ImplausibleValuesAreNamed) {
  const FitJob job = LoadFitJob(kRoot + "/configs/jobs/discover/none.yaml");
  const auto fit_with = [](const std::string& name, double value) {
    FitResult r;
    ParameterEstimate p;
    p.name = name;
    p.value = value;
    p.free = true;
    r.parameters.push_back(p);
    return r;
  };
  const std::string payload = ImplausibleValue("payload", fit_with("Delta_M", -4.4), job.problem);
  EXPECT_NE(payload.find("Delta_M = -4.4 kg is below zero"), std::string::npos) << payload;
  EXPECT_EQ(ImplausibleValue("payload", fit_with("Delta_M", 25.0), job.problem), "");
  EXPECT_EQ(ImplausibleValue("sensor_delay.a", fit_with("tau_d.a", 2.07e-4), job.problem), "");
  EXPECT_EQ(ImplausibleValue("sensor_delay.a", fit_with("tau_d.a", -2.07e-4), job.problem), "");
  EXPECT_EQ(ImplausibleValue("sensor_delay.a", fit_with("tau_d.a", 0.002), job.problem), "");
  // A filter must be one of this 1 kHz record. Under a declared sampling
  // convention a cut-off above its 500 Hz Nyquist frequency (τ below
  // T/π = 0.318 ms) cannot be told from none; on `a` under a convention
  // nobody declared the bound is the 1 kHz sample rate (τ below T/(2π)),
  // since a period mean read as the wrong convention moves the filter's
  // apparent cut-off (issue 56); a second-order one at its damping bound is
  // a stand-in.
  const std::string fast = ImplausibleValue("sensor_lowpass.a", fit_with("tau_lp.a", 1e-5), job.problem);
  EXPECT_NE(fast.find("above the record's sample rate 1000 Hz"), std::string::npos) << fast;
  EXPECT_EQ(ImplausibleValue("sensor_lowpass.a", fit_with("tau_lp.a", 4e-4), job.problem), "");
  EXPECT_EQ(ImplausibleValue("sensor_lowpass.a", fit_with("tau_lp.a", 2e-4), job.problem), "");
  EstimationProblem declared = job.problem;
  declared.model.declared.insert("accelerometer");
  const std::string nyquist = ImplausibleValue("sensor_lowpass.a", fit_with("tau_lp.a", 2e-4), declared);
  EXPECT_NE(nyquist.find("above the record's Nyquist frequency 500 Hz"), std::string::npos) << nyquist;
  FitResult second = fit_with("tau_lp2.a", 6.4e-4);
  second.parameters.push_back(fit_with("zeta_lp2.a", 0.0502).parameters[0]);
  const std::string resonant = ImplausibleValue("sensor_lowpass2.a", second, job.problem);
  EXPECT_NE(resonant.find("zeta_lp2.a = 0.0502 is at its bound"), std::string::npos) << resonant;
  second.parameters[1].value = 0.707;
  EXPECT_EQ(ImplausibleValue("sensor_lowpass2.a", second, job.problem), "");
  second.parameters[0].value = 2e-4;  // 796 Hz natural frequency
  EXPECT_EQ(ImplausibleValue("sensor_lowpass2.a", second, job.problem), "");
  EXPECT_NE(ImplausibleValue("sensor_lowpass2.a", second, declared).find("Nyquist"),
            std::string::npos);
  const std::string motor = ImplausibleValue("motor_coulomb", fit_with("T_c", -0.0197), job.problem);
  EXPECT_NE(motor.find("T_c = -0.0197 N*m is below zero"), std::string::npos) << motor;
  const std::string coulomb = ImplausibleValue("coulomb", fit_with("F_c", -3.0), job.problem);
  EXPECT_NE(coulomb.find("F_c = -3 N is below zero"), std::string::npos) << coulomb;
  EXPECT_EQ(ImplausibleValue("coulomb", fit_with("F_c", 40.0), job.problem), "");
  EXPECT_NE(ImplausibleValue("stribeck", fit_with("F_st", -1.0), job.problem), "");
}

// The sensor front end's candidates (issue 42): a first- and a second-order
// low-pass beside the delay and the bias on every fitted channel, reported
// apart from the plant's effects.
TEST(DiscoveryTest, FrontEndCandidatesAreListedAndReportedApart) {
  const FitJob job = LoadFitJob(kRoot + "/configs/jobs/discover/none.yaml");
  std::vector<std::string> names;
  for (const Candidate& c : ListCandidates(job.problem)) names.push_back(c.name);
  for (const std::string& fitted : {std::string("a"), std::string("tach")}) {
    for (const char* effect : {"sensor_delay.", "sensor_bias.", "sensor_lowpass.",
                               "sensor_lowpass2."}) {
      EXPECT_NE(std::find(names.begin(), names.end(), effect + fitted), names.end())
          << effect << fitted;
    }
  }
  EXPECT_EQ(FreedParameters("sensor_lowpass2.a"),
            (std::vector<std::string>{"tau_lp2.a", "zeta_lp2.a"}));
  const SelectedParts parts = SplitSelected({"coulomb", "sensor_lowpass.a", "spring"});
  EXPECT_EQ(parts.plant, (std::vector<std::string>{"coulomb", "spring"}));
  EXPECT_EQ(parts.front_end, (std::vector<std::string>{"sensor_lowpass.a"}));
  DiscoveryReport report;
  report.selected = {"sensor_delay.tach"};
  const nlohmann::json j = DiscoveryToJson(report);
  EXPECT_EQ(j["selected_front_end"], nlohmann::json::array({"sensor_delay.tach"}));
  EXPECT_TRUE(j["selected_plant"].empty());
}

// The front-end case anti_alias (configs/jobs/front_end/anti_alias.yaml:
// instant samples of `a` behind a 250 Hz Butterworth filter, read as period
// means; a tachometer filter; no plant effect) as fit-params runs it: the
// loop keeps a filter and a delay on `a` as stand-ins, then the convention
// judged by BIC against them (run/job_run.cc CheckTheConventionAgain) is
// adopted and the stand-in delay dropped: the run ends with the generating
// front end (instant, sensor_lowpass2.a, sensor_lowpass.tach), no plant
// effect, and the filter's τ and ζ within 4 standard errors of the truth
// (ExpectNearTruth; under the period-mean convention τ_lp2.a was 0.58 ms,
// 2.4 standard errors off, ζ 0.67, 5).
TEST(DiscoveryTest, AntiAliasFrontEndEndsUnderItsConvention) {
  FitJob job = LoadFitJob(kRoot + "/configs/jobs/front_end/anti_alias.yaml");
  job.problem.solver.progress = false;
  std::ostringstream out;
  const JobRun run = RunJob(job, /*discover=*/true, out);
  std::vector<std::string> selected = run.discovery.selected;
  std::sort(selected.begin(), selected.end());
  EXPECT_EQ(selected, (std::vector<std::string>{"accelerometer.instant", "sensor_lowpass.tach",
                                                "sensor_lowpass2.a"}))
      << out.str();
  EXPECT_EQ(run.job.problem.model.structure.accelerometer, AccelerometerSampling::kInstant);
  ExpectNearTruth(run.result, "tau_lp2.a", 6.3662e-4);
  ExpectNearTruth(run.result, "zeta_lp2.a", 0.70711);
  ExpectNearTruth(run.result, "tau_lp.tach", 3.9789e-4);
  for (const auto& [name, truth] : {std::pair<std::string, double>{"V_L", 2.7}, {"B_a", 200},
                                    {"b_g", 1500}, {"k_g", 5.0e6}, {"T_p", 0.04}}) {
    ExpectNearTruth(run.result, name, truth);
  }
}

// Stribeck friction is a candidate only once Coulomb friction is in the
// model (MODEL.md §7: its term rides on F_c), and an enabled effect is no
// longer a candidate.
TEST(DiscoveryTest, StribeckIsACandidateOnlyWithCoulomb) {
  FitJob job = LoadFitJob(kRoot + "/configs/jobs/discover/none.yaml");
  const auto names = [](const FitJob& j) {
    std::vector<std::string> out;
    for (const Candidate& c : ListCandidates(j.problem)) out.push_back(c.name);
    return out;
  };
  const auto has = [](const std::vector<std::string>& list, const std::string& name) {
    return std::find(list.begin(), list.end(), name) != list.end();
  };
  ASSERT_FALSE(job.problem.model.structure.effects.coulomb);
  const std::vector<std::string> without = names(job);
  EXPECT_TRUE(has(without, "coulomb"));
  EXPECT_FALSE(has(without, "stribeck"));
  job.problem.model.structure.effects.coulomb = true;
  const std::vector<std::string> with = names(job);
  EXPECT_FALSE(has(with, "coulomb"));
  EXPECT_TRUE(has(with, "stribeck"));
  EXPECT_FALSE(has(with, "stribeck_shape"));
  // Its shape exponent once a Gaussian Stribeck term is in; not where δ is
  // the model's own or the job fits it.
  job.problem.model.structure.effects.stribeck = true;
  EXPECT_TRUE(has(names(job), "stribeck_shape"));
  EXPECT_TRUE(RefinedInModel("coulomb", job.problem.model.structure));
  EXPECT_FALSE(RefinedInModel("stribeck", job.problem.model.structure));
  FitJob shaped = job;
  shaped.problem.model.params.delta_st = 1.5;
  EXPECT_FALSE(has(names(shaped), "stribeck_shape"));
  FitJob fitted = job;
  fitted.problem.free.push_back({"delta_st", "1", 2.0, 0.5, 4.0, 1.0, true});
  EXPECT_FALSE(has(names(fitted), "stribeck_shape"));
  // Switched on, the Stribeck term stays while it does; switched off again,
  // δ is the Gaussian 2 and no longer free.
  shaped.problem.model.structure.effects.stribeck_shape = true;
  shaped.problem.free.push_back({"delta_st", "1", 1.5, 0.1, 20.0, 1.0, true});
  EXPECT_TRUE(RefinedInModel("stribeck", shaped.problem.model.structure));
  const EstimationProblem off = JobWithout(shaped.problem, "stribeck_shape");
  EXPECT_FALSE(off.model.structure.effects.stribeck_shape);
  EXPECT_TRUE(off.model.structure.effects.stribeck);
  EXPECT_EQ(off.model.params.delta_st, 2.0);
  EXPECT_EQ(off.free.size(), job.problem.free.size());
}

// The small campaign of the suite (issue 10): 10 seeds of
// configs/campaigns/null_prbs_chirp.yaml (null data, PRBS and chirp inputs,
// which the discovery cases do not use). At the family-wise level 1e-3 the
// expected number of false discoveries over 10 seeds is 0.01, and of
// `incomplete` verdicts on the right model ≤ 0.01: both must be 0. The full
// campaign (100 seeds) is fit-campaign's job (README).
TEST(DiscoveryTest, NoFalseDiscoveryOverTenNullSeeds) {
  CampaignConfig config = LoadCampaign(kRoot + "/configs/campaigns/null_prbs_chirp.yaml");
  config.first_seed = 1;
  config.last_seed = 10;
  const std::vector<SeedOutcome> outcomes = RunCampaign(config, 2, &std::cout);
  const CampaignSummary summary = Summarize(config, outcomes);
  EXPECT_EQ(summary.failed, 0);
  EXPECT_EQ(summary.false_discovery.n, 10);
  EXPECT_EQ(summary.false_discovery.k, 0) << FormatCampaign(config, summary, outcomes);
  EXPECT_EQ(summary.explained, 10) << FormatCampaign(config, summary, outcomes);
  RecordProperty("false_discoveries", std::to_string(summary.false_discovery.k) + "/10");
}

// The Stribeck refit starts from one column's own step. Seed 1 of
// configs/campaigns/power_stribeck.yaml (F_c = 30 N, F_st = 50 N, v_st =
// 0.05 m/s), with Coulomb friction declared and Stribeck friction the only
// candidate: the score test's three columns (v_st = 0.005, 0.02, 0.1 m/s)
// are nearly parallel, and their joint Gauss–Newton step, taken for the
// grid value of the largest component, started the refit far from the data
// (it ended at v_st = 0.40 m/s, F_st = 47.6 N, BIC 1.51e4, where the true
// minimum is at 1.20e4, and the loop then added an offset as a stand-in:
// 4 seeds of 20). Started at each grid value with that column's step alone
// (Score::single_step) it reaches v_st = 0.0505 ± 0.0005 m/s.
TEST(DiscoveryTest, StribeckRefitStartsFromEachColumnsOwnStep) {
  CampaignConfig config = LoadCampaign(kRoot + "/configs/campaigns/power_stribeck.yaml");
  YAML::Node job = YAML::LoadFile(config.job_path);
  job["model"] = kRoot + "/configs/axes/x_axis.yaml";
  job["effects"]["coulomb"]["F_c"] = 40.0;
  job["free"]["F_c"]["initial"] = 40.0;
  job["free"]["F_c"]["lower"] = 0.0;
  job["free"]["F_c"]["upper"] = 200.0;
  job["solver"]["starts"] = 0;
  job["discover"]["candidates"].push_back("stribeck");
  job["discover"]["max_effects"] = 1;
  config.job_path = axis::testing_files::TestTempDir() + "stribeck_coulomb_declared.yaml";
  std::ofstream(config.job_path) << YAML::Dump(job);
  const SeedOutcome o = RunCampaignSeed(config, 1, 2);
  ASSERT_EQ(o.error, "");
  EXPECT_EQ(o.selected, std::vector<std::string>{"stribeck"});
  EXPECT_EQ(o.verdict, "explained");
  // The truth values (F_c, F_st, v_st) inside their 95 % intervals: each
  // misses with probability 5 % with right intervals; v_st's interval at
  // the wrong minimum ([0.397, 0.406] m/s) is 70 of its widths away.
  ASSERT_EQ(o.value.size(), config.truth_values.size());
  for (size_t k = 0; k < o.value.size(); ++k) {
    const auto& [name, truth] = config.truth_values[k];
    EXPECT_LE(o.ci95_low[k], truth) << name << " = " << o.value[k];
    EXPECT_GE(o.ci95_high[k], truth) << name << " = " << o.value[k];
    RecordProperty(name, std::to_string(o.value[k]));
  }
}

// Motion in one direction only (the +4 V step of the coulomb case): a
// Coulomb force and a constant offset both act as a constant force while the
// axis moves, so their projected columns are nearly parallel (cos 0.988)
// and the loop must not pick one at random. Here the record starts at rest,
// where sgn_ε(v) is still 0 but an offset would already push: the
// conditional score of Coulomb given the offset is 259, that of the offset
// given Coulomb 0.007, so the data do decide, for Coulomb (the truth). The
// pair is reported as nearly parallel and the decision as the residual's.
TEST(DiscoveryTest, OneDirectionCoulombAndOffsetAreDecidedOnlyByEvidence) {
  FitJob job = LoadFitJob(kRoot + "/configs/jobs/discover/coulomb.yaml");
  job.problem.experiments.resize(1);  // step_p4V only
  job.problem.validate.clear();
  job.problem.solver.progress = false;
  FitResult result = FitParameters(job.problem);
  const DiscoveryReport report = Discover(job.discover, &job.problem, &result, nullptr);
  const ParallelPair* pair = nullptr;
  for (const ParallelPair& q : report.ranking.parallel) {
    if ((q.a == "coulomb" && q.b == "load_offset") ||
        (q.a == "load_offset" && q.b == "coulomb")) {
      pair = &q;
    }
  }
  ASSERT_NE(pair, nullptr);
  EXPECT_GT(pair->cosine, 0.95);
  const double coulomb_given_offset =
      pair->a == "coulomb" ? pair->chi2_a_given_b : pair->chi2_b_given_a;
  const double offset_given_coulomb =
      pair->a == "coulomb" ? pair->chi2_b_given_a : pair->chi2_a_given_b;
  // The loop's level: Bonferroni over the 11 candidates of this job.
  const double threshold = job.discover.alpha / 11.0;
  EXPECT_LT(ChiSquaredSurvival(coulomb_given_offset, 1), threshold);
  EXPECT_GT(ChiSquaredSurvival(offset_given_coulomb, 1), threshold);
  EXPECT_TRUE(pair->separated);
  ASSERT_FALSE(report.selected.empty()) << report.stop_reason;
  EXPECT_EQ(report.selected.front(), "coulomb");
  RecordProperty("chi2_coulomb_given_offset", std::to_string(coulomb_given_offset));
  RecordProperty("chi2_offset_given_coulomb", std::to_string(offset_given_coulomb));
}

TEST(DiscoveryTest, UnknownCandidateNameIsAnError) {
  std::ifstream in(kRoot + "/configs/jobs/discover/none.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::string key = "  max_effects: 3";
  text.replace(text.find(key), key.size(),
               key + "\n  candidates: [coulomb, magic_friction]");
  // Make the job's relative paths absolute so it can live in a temp folder.
  for (const std::string rel : {"../../../", "../../"}) {
    const std::string abs = rel == "../../" ? kRoot + "/configs/" : kRoot + "/";
    for (size_t at; (at = text.find(rel)) != std::string::npos;) {
      text.replace(at, rel.size(), abs);
    }
  }
  const std::string path = axis::testing_files::TestTempDir() + "bad_candidates.yaml";
  std::ofstream(path) << text;
  try {
    LoadFitJob(path);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find("discover.candidates"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'magic_friction'"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace axis
