// The EMPS controller reconstruction (MODEL.md §5, configs/axes/emps.yaml)
// checked on the real data: replaying the estimation run in closed loop with
// the published parameters reproduces the measured controller output and
// position about as well as the authors' own simulation does.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "fit/statistics.h"
#include "sim/csv.h"
#include "sim/experiment.h"

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
  // (qm). Measured here with their one-sample delay: 6.59 % and 0.0016 %.
  // Bounds: within 20 % of their vir figure, and below their qm figure.
  EXPECT_LT(vir_error, 1.2 * 5.85);
  EXPECT_LT(qm_error, 0.0138);
}

}  // namespace
}  // namespace axis
