// The EMPS controller reconstruction (MODEL.md §5, configs/axes/emps.yaml)
// checked on the real data: replaying the estimation run in closed loop with
// the published parameters reproduces the measured controller output and
// position about as well as the authors' own simulation does.
#include <cmath>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "fit/discovery.h"
#include "fit/fit.h"
#include "fit/job.h"
#include "fit/statistics.h"
#include "sim/csv.h"
#include "sim/experiment.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;

TEST(EmpsReplayTest, PublishedModelReproducesTheMeasuredRun) {
  const ExperimentConfig e =
      LoadExperiment(kRoot + "/configs/experiments/emps_replay.yaml");
  const Trace<double> trace = RunExperiment(e);
  const CsvTable data = ReadCsv(kRoot + "/testdata/emps/DATA_EMPS.csv");
  ASSERT_EQ(trace.t.size(), data.num_rows());
  const double vir_error = RelativeErrorPercent(data.Column("vir_V"), trace[Channel::kU]);
  const double qm_error = RelativeErrorPercent(data.Column("qm_m"), trace[Channel::kX]);
  RecordProperty("vir_relative_error_percent", std::to_string(vir_error));
  RecordProperty("qm_relative_error_percent", std::to_string(qm_error));
  // The authors' simulation of the same model: 5.85 % (vir) and 0.0138 %
  // (qm). Measured here without controller delay (configs/axes/emps.yaml):
  // 5.14 % and 0.0012 %; with their one-sample delay 6.59 % and 0.0016 %.
  // Bounds: within 20 % of their vir figure, and below their qm figure.
  EXPECT_LT(vir_error, 1.2 * 5.85);
  EXPECT_LT(qm_error, 0.0138);
}

// configs/jobs/emps.yaml on the first 12 s of the estimation run (half the
// record, one discovery step and no validation runs, to keep the suite
// fast): starting from M and B_a only, the discovery loop's first addition
// is Coulomb friction, near the published 20.39 N, and M lands within 2 % of
// the published 95.11 kg.
TEST(EmpsJobTest, DiscoveryFindsCoulombFrictionOnAShortWindow) {
  std::ifstream in(kRoot + "/configs/jobs/emps.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  for (const std::string rel : {"../../", "../axes"}) {
    const std::string abs = rel == "../axes" ? kRoot + "/configs/axes" : kRoot + "/";
    for (size_t at; (at = text.find(rel)) != std::string::npos;) {
      text.replace(at, rel.size(), abs);
    }
  }
  for (size_t at = 0; (at = text.find("    reference: {column: qg_m}", at)) != std::string::npos;) {
    text.insert(at, "    window: [0, 12]\n");
    at += 40;
  }
  const std::string path = axis::testing_files::TestTempDir() + "emps_short.yaml";
  std::ofstream(path) << text;
  FitJob job = LoadFitJob(path);
  ASSERT_NEAR(job.experiments[0].t.back(), 12.0, 0.002);
  job.solver.progress = false;
  job.validate.clear();
  job.discover.max_effects = 1;
  FitResult result = FitParameters(job);
  const DiscoveryReport report = Discover(job.discover, &job, &result, nullptr);
  ASSERT_FALSE(report.selected.empty()) << report.stop_reason;
  EXPECT_EQ(report.selected.front(), "coulomb");
  double f_c = 0.0, mass = 0.0;
  for (const ParameterEstimate& p : result.parameters) {
    if (p.name == "F_c") f_c = p.value;
    if (p.name == "M") mass = p.value;
  }
  RecordProperty("F_c", std::to_string(f_c));
  RecordProperty("M", std::to_string(mass));
  // Loose: a different estimator (closed-loop output error, with whatever
  // else the loop adds) from the published IDIM-LS figure.
  EXPECT_NEAR(f_c, 20.39, 0.25 * 20.39);
  EXPECT_NEAR(mass, 95.11, 0.02 * 95.11);
}

}  // namespace
}  // namespace axis
