// The accelerometer-convention check (estimation/sampling_check.h) on
// records sampled at the instant and read as period means (issue 42's
// first case): at the truth, the other convention fits to the noise and
// the declared one does not, and the note names the convention.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "estimation/sampling_check.h"
#include "job/load_fit_job.h"
#include "sim/config.h"
#include "tests/test_files.h"

namespace axis {
namespace {

using testing_files::RunCommand;
using testing_files::TestTempDir;
using testing_files::WriteTemp;

const std::string kRoot = PROJECT_SOURCE_DIR;

TEST(SamplingCheckTest, InstantRecordsReadAsPeriodMeansAreNamed) {
  const std::string experiment = WriteTemp(
      "instant.yaml", "model: " + kRoot +
                          "/configs/axes/x_axis.yaml\n"
                          "configuration: {accelerometer: instant}\n"
                          "duration: 1.0\nstep: 1.0e-5\noutput_rate: 1000\n"
                          "channels: [u, a, tach, i]\n"
                          "noise: {a: 0.02, tach: 0.005, i: 0.05}\nseed: 42\n"
                          "input: {type: step, amplitude: 6}\n");
  const std::string csv = TestTempDir() + "instant.csv";
  ASSERT_EQ(RunCommand(std::string(BINARY_DIR) + "/simulate-axis", experiment + " --out " + csv,
                       true)
                .exit_code,
            0);
  const std::string job_path = WriteTemp(
      "job.yaml", "model: " + kRoot +
                      "/configs/axes/x_axis.yaml\n"
                      "free:\n  V_L: {initial: 2.7, lower: 0.5, upper: 20}\n"
                      "  T_p: {initial: 0.04, lower: 0.005, upper: 1.0}\n"
                      "experiments:\n  - name: step\n    data: " +
                      csv +
                      "\n    channels: {u: u, a: a, tach: tach, i: i}\n"
                      "    input: {column: u}\n    fit: {a: 0.02, tach: 0.005}\n"
                      "output: {dir: " + TestTempDir() + "out}\n");
  const FitJob job = LoadFitJob(job_path);
  const AxisConfig truth = LoadAxisConfig(kRoot + "/configs/axes/x_axis.yaml");
  FitResult at_truth;
  for (const char* name : {"V_L", "T_p"}) {
    ParameterEstimate e;
    e.name = name;
    e.free = true;
    e.value = *FindParam(const_cast<AxisParams<double>*>(&truth.params), name);
    at_truth.parameters.push_back(e);
  }
  const SamplingCheck check = CheckAccelerometerSampling(job, at_truth);
  ASSERT_TRUE(check.ran);
  EXPECT_EQ(check.declared, "period_mean");
  EXPECT_EQ(check.other, "instant");
  ASSERT_EQ(check.samples, 1001);
  // χ²/n at the noise is 1 ± √(2/n) = ± 0.045: within five of those.
  EXPECT_NEAR(check.chi2_other / check.samples, 1.0, 5 * std::sqrt(2.0 / check.samples));
  EXPECT_GT(check.chi2_declared, 2.0 * check.chi2_other);
  EXPECT_NE(check.note.find("'accelerometer: instant' better than the declared 'period_mean'"),
            std::string::npos)
      << check.note;
}

}  // namespace
}  // namespace axis
