// The next experiment (issue 15 part 2, design/experiment_design.h): a record
// taken in motion (testdata/generate/design/: it starts at 0.3 m/s and
// never reverses), on which Coulomb friction and a constant load force are
// the same force; the loop stops on the pair, the design proposes a record,
// and that record — simulated with each of the two truths by the full
// model at 10 µs, as the test data are, with noise — added to the job makes
// the loop pick the true one. Also the D-optimal branch and the keys.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "design/experiment_design.h"
#include "discovery/discovery.h"
#include "estimation/fit.h"
#include "estimation/fit_result.h"
#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "report/html_report.h"
#include "run/job_run.h"
#include "sim/config.h"
#include "sim/experiment.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;
const std::string kJob = kRoot + "/configs/jobs/design/coulomb_or_offset.yaml";

// The committed job on the in-motion record of `truth` ("coulomb" or
// "load_offset"), with `extra` experiments appended (YAML maps), written
// into the test's temporary folder and loaded.
FitJob JobOn(const std::string& truth, const std::vector<YAML::Node>& extra = {}) {
  YAML::Node job = YAML::LoadFile(kJob);
  job["model"] = kRoot + "/configs/axes/x_axis.yaml";
  job["experiments"][0]["data"] = kRoot + "/testdata/design/" + truth + "_in_motion.csv";
  for (const YAML::Node& e : extra) job["experiments"].push_back(e);
  job["output"]["dir"] = testing_files::TestTempDir() + "design_out";
  const std::string path = testing_files::TestTempDir() + "design_" + truth + "_" +
                           std::to_string(extra.size()) + ".yaml";
  std::ofstream(path) << YAML::Dump(job);
  FitJob out = LoadFitJob(path);
  out.problem.solver.progress = false;
  return out;
}

TEST(ExperimentDesignTest, ARecordInMotionGetsTheExperimentThatDecides) {
  // The records cannot tell the pair apart: the loop stops, and the
  // design proposes an input of the family inside the travel.
  std::ostringstream log;
  JobRun run = RunJob(JobOn("coulomb"), true, log);
  EXPECT_NE(run.discovery.stop_reason.find("cannot be told apart"), std::string::npos)
      << run.discovery.stop_reason;
  EXPECT_TRUE(run.discovery.selected.empty());
  const ExperimentProposal& p = run.proposal;
  ASSERT_TRUE(p.proposed) << p.reason;
  EXPECT_EQ(p.criterion, "T-optimal");
  EXPECT_EQ(std::vector<std::string>({p.a, p.b}),
            std::vector<std::string>({"coulomb", "load_offset"}));
  // On the records the conditional statistics are at round-off (the two
  // columns are the same force); with the proposal far above the critical
  // value both ways.
  EXPECT_LT(p.chi2_a_given_b_now, p.critical_a);
  EXPECT_LT(p.chi2_b_given_a_now, p.critical_b);
  EXPECT_GT(p.best.chi2_a_given_b, 10.0 * p.critical_a);
  EXPECT_GT(p.best.chi2_b_given_a, 10.0 * p.critical_b);
  EXPECT_GE(p.best.x_min, run.job.design.travel_low);
  EXPECT_LE(p.best.x_max, run.job.design.travel_high);
  int infeasible = 0;
  for (const DesignCandidate& c : p.candidates) infeasible += !c.feasible;
  EXPECT_GT(infeasible, 0) << "the 1 m travel rules out the long fast steps";

  // report.html's section: the text and the best inputs, the proposed
  // one first.
  HtmlReportInput html;
  html.result = &run.result;
  html.job = &run.job.problem;
  html.proposal = &p;
  const std::string page = RenderHtmlReport(html, testing_files::TestTempDir(), nullptr);
  const size_t section = page.find("id=\"next-experiment\"");
  ASSERT_NE(section, std::string::npos);
  // The table's first row (the best by the criterion) is the proposal.
  const size_t body = page.find("<tbody>", section);
  ASSERT_NE(body, std::string::npos);
  const size_t first_cell = page.find("<td", body);
  ASSERT_NE(first_cell, std::string::npos);
  EXPECT_EQ(page.find(HtmlEscape(p.best.description), first_cell),
            page.find('>', first_cell) + 1);
  EXPECT_NE(page.find("chi2 coulomb beyond load_offset", section), std::string::npos);

  // The proposal as written: an experiment file simulate-axis loads.
  const std::string dir = testing_files::TestTempDir() + "proposal";
  std::filesystem::create_directories(dir);
  WriteProposal(dir, run.job.problem, run.job.title, run.result, p);
  const ExperimentConfig proposed = LoadExperiment(dir + "/experiment_proposed.yaml");
  EXPECT_NEAR(proposed.options.duration, p.duration, 1e-9);
  EXPECT_NEAR(proposed.initial_state[0], p.start_x, 1e-12);
  for (double t = 0.0; t <= p.duration; t += 1e-3) {
    ASSERT_NEAR(proposed.drive.input.Evaluate(t), p.best.input.Evaluate(t), 1e-9) << t;
  }

  for (const std::string truth : {"coulomb", "load_offset"}) {
    SCOPED_TRACE(truth);
    // The machine: the generating config's model (the full current loop at
    // 10 µs), the proposed input, noise with a fixed seed.
    ExperimentConfig machine = proposed;
    const ExperimentConfig generator =
        LoadExperiment(kRoot + "/testdata/generate/design/" + truth + "_in_motion.yaml");
    machine.model = generator.model;
    machine.options.step = generator.options.step;
    machine.initial_state = ConsistentInitialState(machine.model, machine.initial_state);
    machine.seed = 303;
    SimulateAxisOptions options;
    const std::string csv = dir + "/" + truth + "_proposed.csv";
    WriteTraceCsv(csv, SimulateExperiment(machine, options), machine.options.channels);
    YAML::Node e;
    e["name"] = "proposed";
    e["data"] = csv;
    e["channels"]["u"] = "u";
    e["channels"]["x"] = "x";
    e["channels"]["a"] = "a";
    e["channels"]["tach"] = "tach";
    e["input"]["column"] = "u";
    if (p.best.family == "steps" || p.best.family == "prbs") {
      e["input"]["interpolation"] = "hold";
    }
    e["initial_state"]["y0"] = p.start_x;
    e["initial_state"]["y2"] = proposed.initial_state[2];
    e["fit"]["a"] = 0.02;
    e["fit"]["tach"] = 0.005;
    std::ostringstream again;
    FitJob job = JobOn(truth, {e});
    job.design.enabled = false;
    const JobRun decided = RunJob(job, true, again);
    EXPECT_EQ(decided.discovery.selected, std::vector<std::string>{truth})
        << FormatDiscovery(decided.discovery);
  }
}

// Without a pair to tell apart and with design.rel_se below the largest
// relative standard error, the design is D-optimal and predicts smaller
// errors; with rel_se 0 nothing is proposed.
TEST(ExperimentDesignTest, DOptimalWhenAParameterIsKnownTooPoorly) {
  FitJob job = JobOn("coulomb");
  job.discover.enabled = false;
  job.problem.model.structure.effects.coulomb = true;
  job.problem.model.params.F_c = 40.0;
  const FitResult result = FitParameters(job.problem);
  ExperimentProposal none = ProposeExperiment(job.problem, result, job.design, job.discover);
  EXPECT_FALSE(none.proposed);
  EXPECT_NE(none.reason.find("design.rel_se not set"), std::string::npos) << none.reason;
  job.design.rel_se = 1e-4;
  const ExperimentProposal p = ProposeExperiment(job.problem, result, job.design, job.discover);
  ASSERT_TRUE(p.proposed) << p.reason;
  EXPECT_EQ(p.criterion, "D-optimal");
  ASSERT_EQ(p.rel_se_predicted.size(), job.problem.free.size());
  for (size_t k = 0; k < job.problem.free.size(); ++k) {
    // Added information can only shrink (JᵀJ grows by a PSD term).
    EXPECT_LE(p.rel_se_predicted[k], p.rel_se_now[k] * (1.0 + 1e-9)) << p.names[k];
  }
  // T_p (the preamp pole) is the worst known on a record without a step:
  // the proposal must improve it.
  const size_t tp = std::find(p.names.begin(), p.names.end(), "T_p") - p.names.begin();
  ASSERT_LT(tp, p.names.size());
  EXPECT_LT(p.rel_se_predicted[tp], 0.5 * p.rel_se_now[tp]);
}

// A closed-loop job (the EMPS rig, 3 s of its estimation run, M and B_a):
// the proposals are reference positions for its own controller, inside the
// travel; the written experiment file loads as a closed-loop run whose
// reference is the proposal's, sample for sample, and simulate-axis's run of
// it (noise off) is the design's own: the same position range. Also with a
// motor encoder (counts_per_rev), where the controller reads the motor angle
// y2, which the design must start at x0/r_g as simulate-axis does.
TEST(ExperimentDesignTest, ClosedLoopJobsGetReferencePositions) {
  for (const std::string controller : {"", "{counts_per_rev: 10000000}"}) {
    SCOPED_TRACE(controller.empty() ? "load-side encoder" : "motor encoder");
    YAML::Node y = YAML::LoadFile(kRoot + "/configs/jobs/emps.yaml");
    y["model"] = kRoot + "/configs/axes/emps.yaml";
    y["experiments"][0]["data"] = kRoot + "/testdata/emps/DATA_EMPS.csv";
    y["experiments"][0]["window"] = YAML::Load("[0, 3]");
    if (!controller.empty()) y["controller"] = YAML::Load(controller);
    y.remove("validate");
    y.remove("published");
    y.remove("discover");
    y["output"]["dir"] = testing_files::TestTempDir() + "closed_loop_design_out";
    y["design"] = YAML::Load("{travel: [0, 0.25], duration: 3, rel_se: 1.0e-6}");
    const std::string path = testing_files::TestTempDir() + "closed_loop_design.yaml";
    std::ofstream(path) << YAML::Dump(y);
    FitJob job = LoadFitJob(path);
    job.problem.solver.progress = false;
    ASSERT_TRUE(job.problem.experiments[0].drive.closed_loop);
    const FitResult result = FitParameters(job.problem);
    const ExperimentProposal p = ProposeExperiment(job.problem, result, job.design, job.discover);
    ASSERT_TRUE(p.proposed) << p.reason;
    EXPECT_TRUE(p.closed_loop);
    EXPECT_EQ(p.criterion, "D-optimal");
    int feasible = 0;
    for (const DesignCandidate& c : p.candidates) {
      EXPECT_TRUE(c.family == "moves" || c.family == "sine" || c.family == "prbs") << c.family;
      // Every reference starts at rest at the travel's centre.
      EXPECT_EQ(c.input.Evaluate(0.0), p.start_x) << c.description;
      EXPECT_EQ(c.input.Evaluate(0.09), p.start_x) << c.description;
      feasible += c.feasible;
    }
    EXPECT_GT(feasible, 0);
    const std::string dir = testing_files::TestTempDir() + "closed_loop_proposal";
    std::filesystem::create_directories(dir);
    WriteProposal(dir, job.problem, job.title, result, p);
    const ExperimentConfig proposed = LoadExperiment(dir + "/experiment_proposed.yaml");
    ASSERT_TRUE(proposed.drive.closed_loop);
    EXPECT_EQ(proposed.drive.controller.G_p, job.problem.experiments[0].drive.controller.G_p);
    EXPECT_EQ(proposed.drive.controller.counts_per_rev,
              job.problem.experiments[0].drive.controller.counts_per_rev);
    for (double t = 0.0; t <= p.duration; t += 1e-3) {
      ASSERT_NEAR(proposed.drive.reference.table.Evaluate(t), p.best.input.Evaluate(t), 1e-9)
          << t;
    }
    SimulateAxisOptions quiet;
    quiet.no_noise = true;
    const Trace<double> replay = SimulateExperiment(proposed, quiet);
    ASSERT_TRUE(replay.finite);
    const std::vector<double>& x = replay[Channel::kX];
    // The replay reads the model file's values written to 10 digits.
    EXPECT_NEAR(*std::min_element(x.begin(), x.end()), p.best.x_min, 1e-6);
    EXPECT_NEAR(*std::max_element(x.begin(), x.end()), p.best.x_max, 1e-6);
  }
}

TEST(ExperimentDesignTest, BadDesignKeysNameTheKey) {
  const auto error = [](const std::string& design) {
    YAML::Node job = YAML::LoadFile(kJob);
    job["model"] = kRoot + "/configs/axes/x_axis.yaml";
    job["experiments"][0]["data"] = kRoot + "/testdata/design/coulomb_in_motion.csv";
    job["design"] = YAML::Load(design);
    const std::string path = testing_files::TestTempDir() + "bad_design.yaml";
    std::ofstream(path) << YAML::Dump(job);
    try {
      LoadFitJob(path);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("{duration: 4}").find("design.travel"), std::string::npos);
  EXPECT_NE(error("{travel: [1, 0]}").find("design.travel"), std::string::npos);
  EXPECT_NE(error("{travel: [0, 1], max_voltage: 12}").find("design.max_voltage"),
            std::string::npos);
  EXPECT_NE(error("{travel: [0, 1], duration: 100}").find("design.duration"), std::string::npos);
  EXPECT_NE(error("{travel: [0, 1], budget: 3}").find("budget"), std::string::npos);
}

}  // namespace
}  // namespace axis
