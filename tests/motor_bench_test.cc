// A new user's first fit of a new axis (issue 58): a torque-driven motor
// bench (configs/axes/motor_bench.yaml: a rotary load, force_source +
// rigid) recorded by simulate-axis from a committed experiment with a fixed
// seed, then fitted by fit-params with M and B_a free and no step given.
// The estimates cover the truth, the step follows from the record (its
// 1 ms period), the tables print the rotary axis's units, and nothing
// speaks of an accelerometer the record does not have.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "tests/test_files.h"

namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;
const std::string kBin = BINARY_DIR;

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// value and std_error of `name` in params.csv (name,unit,value,std_error,...).
std::pair<double, double> Estimate(const std::string& csv, const std::string& name) {
  std::istringstream lines(csv);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind(name + ",", 0) != 0) continue;
    std::istringstream cells(line);
    std::string cell, unit, value, error;
    std::getline(cells, cell, ',');
    std::getline(cells, unit, ',');
    std::getline(cells, value, ',');
    std::getline(cells, error, ',');
    return {std::stod(value), std::stod(error)};
  }
  return {NAN, NAN};
}

TEST(MotorBenchTest, AFirstFitOfARotaryBenchSpeaksItsUnitsAndCoversTheTruth) {
  const std::string dir = axis::testing_files::TestTempDir() + "motor_bench/";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string csv = dir + "bench.csv";
  const auto simulated = axis::testing_files::RunCommand(
      kBin + "/simulate-axis", kRoot + "/configs/experiments/motor_bench_prbs.yaml --out " + csv,
      true);
  ASSERT_EQ(simulated.exit_code, 0) << simulated.err;
  const std::string job = axis::testing_files::WriteTemp(
      "motor_bench_job.yaml",
      "model: " + kRoot + "/configs/axes/motor_bench.yaml\n"
      "free:\n"
      "  M:   {initial: 0.03, lower: 0.001, upper: 1}\n"
      "  B_a: {initial: 0.01, lower: 0.0001, upper: 0.1}\n"
      "experiments:\n"
      "  - name: bench\n"
      "    data: " + csv + "\n"
      "    channels: {u: u, v: v}\n"
      "    input: {column: u, interpolation: hold}\n"
      "    fit: {v: 0.01}\n");
  const std::string out = dir + "fit";
  const std::string log = dir + "fit.log";
  const auto fitted = axis::testing_files::RunCommand(
      kBin + "/fit-params", job + " --out " + out + " > " + log, false);
  ASSERT_EQ(fitted.exit_code, 0) << fitted.err;
  const std::string text = ReadAll(log) + fitted.err;
  // The truth of the experiment's model config; one seed, the noise the
  // fit's σ: within 3 standard errors.
  const std::string params = ReadAll(out + "/params.csv");
  const auto [M, M_se] = Estimate(params, "M");
  const auto [B, B_se] = Estimate(params, "B_a");
  EXPECT_NEAR(M, 0.01, 3.0 * M_se);
  EXPECT_NEAR(B, 0.002, 3.0 * B_se);
  EXPECT_GT(M_se, 0.0);
  EXPECT_NE(params.find("M,kg*m^2,"), std::string::npos) << params;
  EXPECT_NE(params.find("B_a,N*m*s/rad,"), std::string::npos) << params;
  EXPECT_NE(params.find("g_F,N*m/V,"), std::string::npos) << params;
  EXPECT_NE(text.find("rad/s"), std::string::npos) << text;
  EXPECT_NE(text.find("integration: RK4, step 0.001 s"), std::string::npos) << text;
  EXPECT_EQ(text.find("accelerometer"), std::string::npos) << text;
}

}  // namespace
