// The independent implementation of MODEL.md (tests/independent/
// independent_records.cc: adaptive Dormand–Prince with located branch
// changes, a continuous-time front end) against the simulator (sim/:
// fixed-step RK4 with events) on the same axis and input: two codes written
// apart agree to their integration errors, so records of the first are the
// model's records made otherwise, not another model's.
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/csv.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;
const std::string kBin = BINARY_DIR;

// The largest |a − b| of column `name` of two tables of the same grid.
double LargestDifference(const CsvTable& a, const CsvTable& b, const std::string& name) {
  const std::vector<double>& x = a.Column(name);
  const std::vector<double>& y = b.Column(name);
  EXPECT_EQ(x.size(), y.size()) << name;
  double largest = 0.0;
  for (size_t k = 0; k < std::min(x.size(), y.size()); ++k) {
    largest = std::max(largest, std::abs(x[k] - y[k]));
  }
  return largest;
}

// The X axis (gear backlash, both clamps of the analog loop) on a ±6 V
// square wave for 1.2 s: the instant accelerometer 3 ms late behind a
// 250 Hz Butterworth filter, the tachometer behind a 400 Hz first-order
// one. The simulator runs at a 1 µs step with a 1 µs accelerometer window
// (the independent code samples y1' at the instant); the bounds are a
// hundredth of the noise the campaigns add (σ_a 0.02 m/s², σ_tach 0.005 V).
TEST(IndependentRecordsTest, AgreesWithTheSimulatorOnASquareWave) {
  const std::string dir = testing_files::TestTempDir();
  const std::string model = kRoot + "/configs/axes/x_axis.yaml";
  testing_files::WriteTemp("spec.yaml",
                           "model: " + model + "\n"
                           "duration: 1.2\n"
                           "channels: [u, a, tach]\n"
                           "front_end:\n"
                           "  a: {sampling: instant, delay: 0.003, lowpass2: {tau: 6.366e-4}}\n"
                           "  tach: {lowpass: 3.979e-4}\n"
                           "records:\n"
                           "  - {name: square, input: {type: square, amplitude: 6, period: 0.5,"
                           " start: 0.1}}\n");
  const auto made = testing_files::RunCommand(
      kBin + "/independent-records", dir + "spec.yaml --out " + dir + " --noise-free", false);
  ASSERT_EQ(made.exit_code, 0) << made.err;
  testing_files::WriteTemp("experiment.yaml",
                           "model: " + model + "\n"
                           "configuration: {accelerometer: instant, instant_window: 1.0e-6}\n"
                           "effects:\n"
                           "  sensor_delay: {a: 3.0e-3}\n"
                           "  sensor_lowpass2: {a: 6.366e-4}\n"
                           "  sensor_lowpass: {tach: 3.979e-4}\n"
                           "duration: 1.2\n"
                           "step: 1.0e-6\n"
                           "channels: [u, a, tach]\n"
                           "input: {type: table, interpolation: hold, points: [[0, 0], [0.1, 6],"
                           " [0.35, -6], [0.6, 6], [0.85, -6], [1.1, 6]]}\n");
  const auto simulated = testing_files::RunCommand(
      kBin + "/simulate-axis", dir + "experiment.yaml --out " + dir + "simulated.csv", false);
  ASSERT_EQ(simulated.exit_code, 0) << simulated.err;
  const CsvTable independent = ReadCsv(dir + "square.csv");
  const CsvTable ours = ReadCsv(dir + "simulated.csv");
  EXPECT_EQ(LargestDifference(independent, ours, "u"), 0.0);
  EXPECT_LT(LargestDifference(independent, ours, "a"), 2e-4);
  EXPECT_LT(LargestDifference(independent, ours, "tach"), 5e-5);
}

// A bad spec is refused with exit code 2 and the spec named.
TEST(IndependentRecordsTest, ABadSpecIsRefused) {
  const std::string dir = testing_files::TestTempDir();
  testing_files::WriteTemp("bad.yaml", "model: " + kRoot +
                                           "/configs/axes/x_axis.yaml\nduration: 1\n"
                                           "channels: [u, a]\nrecords:\n"
                                           "  - {name: r, input: {type: ramp, amplitude: 1}}\n");
  const auto r = testing_files::RunCommand(kBin + "/independent-records",
                                           dir + "bad.yaml --out " + dir, false);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.yaml"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("input.type"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace axis
