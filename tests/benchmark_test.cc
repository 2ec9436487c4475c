// The job key `benchmark:` (run/benchmark.h, issue 16) on
// configs/jobs/emps_benchmark.yaml: its strict loader, the criteria's jobs,
// the table against the runs it reports, and the benchmark's rule that the
// test run is never fitted and never chooses an effect.
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run/benchmark_settings.h"
#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "run/benchmark.h"
#include "run/fit_params.h"
#include "run/job_run.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;

// configs/jobs/emps_benchmark.yaml with its paths made absolute, every
// experiment cut to [0, `seconds`] s, `replace` applied (pairs of text to
// find once and its replacement) and `extra` appended; written to `name` in
// the test's folder. Returns the path.
std::string BenchmarkJobText(double seconds, const std::string& name,
                             const std::vector<std::pair<std::string, std::string>>& replace = {},
                             const std::string& extra = "") {
  std::string text = testing_files::JobTextWithAbsolutePaths("emps_benchmark.yaml");
  const std::string window = "    window: [0, " + std::to_string(seconds) + "]\n";
  for (size_t at = 0; (at = text.find("\n  - name: ", at)) != std::string::npos;) {
    at = text.find('\n', at + 1) + 1;
    text.insert(at, window);
  }
  for (const auto& [from, to] : replace) {
    const size_t at = text.find(from);
    if (at == std::string::npos) {
      ADD_FAILURE() << "not in the job: " << from;
      continue;
    }
    text.replace(at, from.size(), to);
  }
  return testing_files::WriteTemp(name, text + extra);
}

std::string LoadError(const std::string& path) {
  try {
    LoadFitJob(path);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(loaded)";
}

TEST(BenchmarkJobTest, LoadsTheCommittedJob) {
  const FitJob job = LoadFitJob(kRoot + "/configs/jobs/emps_benchmark.yaml");
  ASSERT_TRUE(job.benchmark.present);
  ASSERT_EQ(job.benchmark.criteria.size(), 3u);
  EXPECT_EQ(job.benchmark.criteria[2].name, "joint");
  EXPECT_EQ(job.benchmark.criteria[2].experiments.size(), 2u);
  ASSERT_EQ(job.benchmark.columns.size(), 4u);
  EXPECT_EQ(job.benchmark.columns[0].experiment, "emps_pulses_open_loop");
  EXPECT_EQ(job.benchmark.columns[0].unit, "mm");
  EXPECT_EQ(job.benchmark.columns[2].unit, "%");  // relative errors default to %
  EXPECT_EQ(job.benchmark.quoted.size(), 4u);
}

// The physical structure fitted on the benchmark's criterion (README, The
// benchmark on its own protocol): it loads, fits only the training run's
// open-loop error, and simulates the test run open loop from its first 20
// samples.
TEST(BenchmarkJobTest, OpenLoopAsymmetricJobLoads) {
  const FitJob job = LoadFitJob(kRoot + "/configs/jobs/emps_open_loop_asymmetric.yaml");
  ASSERT_EQ(job.problem.experiments.size(), 1u);
  EXPECT_EQ(job.problem.experiments[0].name, "emps_open_loop");
  EXPECT_FALSE(job.problem.experiments[0].drive.closed_loop);
  EXPECT_TRUE(job.problem.model.structure.effects.coulomb);
  EXPECT_TRUE(job.problem.model.structure.effects.viscous_asymmetry);
  EXPECT_FALSE(job.problem.model.structure.effects.load_offset);
  ASSERT_FALSE(job.problem.validate.empty());
  EXPECT_EQ(job.problem.validate[0].name, "emps_pulses_open_loop");
  EXPECT_NEAR(job.problem.validate[0].t_offset, 0.020, 1e-4);  // starts at sample 20
}

TEST(BenchmarkJobTest, BadKeysNameTheKeyAndWhatWasExpected) {
  struct Case {
    std::string from, to, expected;
  };
  const std::vector<Case> cases = {
      {"- {experiment: emps_pulses_open_loop, channel: x,", "- {experiment: emps_open_loop, channel: x,",
       "key 'benchmark.columns[0].experiment': expected the score (the first column) on a "
       "'validate:' experiment, which no criterion fits, got 'emps_open_loop', a fitted "
       "experiment"},
      {"open_loop: [emps_open_loop]", "open_loop: [emps_pulses_open_loop]",
       "key 'benchmark.criteria.open_loop': expected names of 'experiments:' entries (the fitted "
       "ones; 'validate:' entries are never fitted), got 'emps_pulses_open_loop'"},
      {"joint: [emps, emps_open_loop]", "joint: [emps, emps]",
       "key 'benchmark.criteria.joint': expected each experiment once, got 'emps' again"},
      {"- {experiment: emps, channel: u,", "- {experiment: emps_open_loop, channel: u,",
       "key 'benchmark.columns[2].channel': expected a channel that experiment 'emps_open_loop' "
       "measures (x), got 'u'"},
      {"measure: relative_error_percent}\n    - {experiment: emps_pulses,",
       "measure: percent}\n    - {experiment: emps_pulses,", "key 'benchmark.columns[2].measure'"},
      {"  criteria:\n", "  critera: {}\n  criteria:\n", "critera"},
      {"closed_loop: [emps]", "closed/loop: [emps]", "key 'benchmark.criteria.closed/loop'"},
      {"      value: 2.64\n", "      value: -2.64\n", "key 'benchmark.quoted[0].value'"},
      {"      experiment: emps_open_loop\n", "      experiment: emps_steps\n",
       "key 'benchmark.quoted[0].experiment': expected the experiment of one of "
       "'benchmark.columns', got 'emps_steps'"},
      {"closed_loop: [emps]", "closed_loop: []",
       "key 'benchmark.criteria.closed_loop': expected a non-empty list"},
      {"joint: [emps, emps_open_loop]", "benchmark.md: [emps, emps_open_loop]",
       "key 'benchmark.criteria.benchmark.md': expected a criterion name"},
      {"scale: 1000, unit: mm}", "scale: 1000}",
       "key 'benchmark.columns[0].unit': expected the unit of the scaled figure"},
      {"    reference: {column: qg_m}\n    fit: {x: 5.0e-6, u: 0.1}\n",
       "    reference: {column: qg_m}\n    fit: {x: 5.0e-6, u: 0.1}\n    initial_state: estimate\n",
       "key 'benchmark.criteria.open_loop': expected every experiment with 'initial_state: "
       "estimate' (its state is fitted, it cannot only be simulated), got a list without 'emps'"},
      // Names are unique over both lists (run/load_fit_job.cc), so the score cannot
      // find a fitted run by a shared name.
      {"  - name: emps_pulses_open_loop\n", "  - name: emps_open_loop\n",
       "key 'validate[1].name': expected a name no other experiment of the job has, got "
       "'emps_open_loop', the name of experiments[1].name"},
  };
  for (size_t k = 0; k < cases.size(); ++k) {
    const std::string path =
        BenchmarkJobText(2.0, "bad_" + std::to_string(k) + ".yaml", {{cases[k].from, cases[k].to}});
    const std::string error = LoadError(path);
    // "<file>:<line>: key '…'" — the line of the offending entry.
    const size_t at = error.find(path + ":");
    ASSERT_NE(at, std::string::npos) << error;
    EXPECT_TRUE(std::isdigit(static_cast<unsigned char>(error[at + path.size() + 1]))) << error;
    EXPECT_NE(error.find(cases[k].expected), std::string::npos) << error;
  }
}

TEST(BenchmarkJobTest, CriterionJobFitsOnlyItsExperiments) {
  const FitJob job = LoadFitJob(BenchmarkJobText(2.0, "criteria.yaml"));
  const FitJob open_loop = CriterionJob(job, job.benchmark.criteria[1]);
  ASSERT_EQ(open_loop.problem.experiments.size(), 1u);
  EXPECT_EQ(open_loop.problem.experiments[0].name, "emps_open_loop");
  EXPECT_FALSE(open_loop.problem.experiments[0].fitted.empty());
  // The closed-loop run is simulated first among the validation runs, with
  // nothing fitted; the job's own validation runs follow unchanged.
  ASSERT_EQ(open_loop.problem.validate.size(), job.problem.validate.size() + 1);
  EXPECT_EQ(open_loop.problem.validate[0].name, "emps");
  EXPECT_EQ(open_loop.problem.validate[0].role, "validate");
  EXPECT_TRUE(open_loop.problem.validate[0].fitted.empty());
  EXPECT_EQ(open_loop.problem.validate[1].name, job.problem.validate[0].name);
  EXPECT_EQ(open_loop.out_dir, job.out_dir + "/open_loop");
  BenchmarkCriterion unknown{"x", {"nope"}};
  EXPECT_THROW(CriterionJob(job, unknown), std::invalid_argument);
  // A criterion's job is a plain job; the benchmark job itself is not one.
  EXPECT_FALSE(open_loop.benchmark.present);
  std::ostringstream quiet;
  EXPECT_THROW(RunJob(job, false, quiet), std::invalid_argument);
}

// The whole command on 3 s of both runs (one effect per criterion): the
// table's values are the runs' own figures, the files are written, and
// changing the test run's measured qm changes its score but no fitted value
// and no effect the discovery loop selects in any criterion — the test run is only simulated.
TEST(BenchmarkJobTest, TableIsTheRunsFiguresAndTheTestRunChoosesNothing) {
  const std::string out = testing_files::TestTempDir() + "out";
  const std::string path =
      BenchmarkJobText(3.0, "short.yaml", {{"max_effects: 5", "max_effects: 1"}});
  FitParamsOptions options;
  options.job_path = path;
  options.out_dir = out;
  std::ostringstream log, err;
  RunFitParams(options, log, err);
  for (const char* file : {"benchmark.md", "benchmark.json", "closed_loop/params.md",
                           "open_loop/report.json", "joint/report.html"}) {
    EXPECT_TRUE(std::filesystem::exists(out + "/" + file)) << file;
  }
  std::ifstream json_in(out + "/benchmark.json");
  const nlohmann::json table = nlohmann::json::parse(json_in);
  ASSERT_EQ(table["rows"].size(), 3u + 1u + 4u);  // criteria, published, quoted
  // Each criterion's row holds its own report's RMS of the test run's qm, in mm.
  for (size_t k = 0; k < 3; ++k) {
    const std::string name = table["rows"][k]["model"].get<std::string>().substr(21);
    std::ifstream report_in(out + "/" + name + "/report.json");
    const nlohmann::json report = nlohmann::json::parse(report_in);
    double rms = NAN;
    for (const auto& e : report["experiments"]) {
      if (e["name"] != "emps_pulses_open_loop") continue;
      for (const auto& c : e["channels"]) {
        if (c["channel"] == "x") rms = c["rms"].get<double>();
      }
    }
    EXPECT_DOUBLE_EQ(table["rows"][k]["values"][0].get<double>(), 1000.0 * rms) << name;
    // ... and the free parameters its report marks undetermined.
    std::vector<std::string> undetermined;
    for (const auto& p : report["parameters"]) {
      if (p["free"].get<bool>() && !p["determined"].get<bool>()) {
        undetermined.push_back(p["name"].get<std::string>());
      }
    }
    EXPECT_EQ(table["rows"][k]["undetermined"].get<std::vector<std::string>>(), undetermined)
        << name;
  }
  // dynoNet's figure sits on the training run (its `experiment:`), the
  // others on the score column.
  EXPECT_EQ(table["rows"][4]["model"], "dynoNet (quoted)");
  EXPECT_TRUE(table["rows"][4]["values"][0].is_null());
  EXPECT_DOUBLE_EQ(table["rows"][4]["values"][1].get<double>(), 2.64);
  EXPECT_EQ(table["rows"][5]["model"], "linear state-space model (quoted)");
  EXPECT_DOUBLE_EQ(table["rows"][5]["values"][0].get<double>(), 5.53);
  EXPECT_TRUE(table["rows"][5]["values"][1].is_null());

  // The same job with the test run's qm moved by 1 cm: in every criterion
  // the same effects and the same estimates, bit for bit; only the score moves.
  FitJob job = LoadFitJob(path);
  job.problem.solver.progress = false;
  FitJob shifted = job;
  for (FitExperiment& e : shifted.problem.validate) {
    if (e.name != "emps_pulses_open_loop") continue;
    for (std::vector<double>& column : e.measured) {
      for (double& v : column) v += 0.01;
    }
  }
  std::ostringstream quiet;
  int chosen = 0;  // effects the loop selected, over the criteria
  for (const BenchmarkCriterion& c : job.benchmark.criteria) {
    const JobRun a = RunJob(CriterionJob(job, c), false, quiet);
    const JobRun b = RunJob(CriterionJob(shifted, c), false, quiet);
    ASSERT_TRUE(a.discovered);  // the job's discover: key
    EXPECT_EQ(a.discovery.selected, b.discovery.selected) << c.name;
    chosen += static_cast<int>(a.discovery.selected.size());
    ASSERT_EQ(a.result.parameters.size(), b.result.parameters.size());
    for (size_t k = 0; k < a.result.parameters.size(); ++k) {
      EXPECT_EQ(a.result.parameters[k].value, b.result.parameters[k].value)
          << c.name << " " << a.result.parameters[k].name;
    }
    const BenchmarkColumn& score = job.benchmark.columns[0];
    const double score_a = MakeBenchmarkTable(job.benchmark, {a}).rows[0].values[0];
    const double score_b = MakeBenchmarkTable(job.benchmark, {b}).rows[0].values[0];
    EXPECT_NE(score_a, score_b) << c.name << " " << score.experiment;
  }
  // The loop did choose (so the equal selections above mean something): on
  // these 3 s, one effect under closed_loop and under joint, none open loop.
  EXPECT_GE(chosen, 2);
}

}  // namespace
}  // namespace axis
