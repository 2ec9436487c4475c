// fit-params on bad input: a clear message naming the file, line or key and
// what was expected, exit code 2, and nothing written in the output folder.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <sys/wait.h>
#include <gtest/gtest.h>

#include "tests/test_files.h"

namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;
const std::string kBin = std::string(BINARY_DIR) + "/fit-params";

using Result = axis::testing_files::CommandResult;

Result RunCli(const std::string& args) {
  return axis::testing_files::RunCommand(kBin, args, true);
}

constexpr auto Write = axis::testing_files::WriteTemp;

// A one-experiment job on `csv`, with `free` as the free block.
std::string Job(const std::string& name, const std::string& csv,
                const std::string& free =
                    "  B_a: {initial: 150, lower: 10, upper: 2000}\n") {
  return Write(name, "model: " + kRoot + "/configs/axes/x_axis.yaml\n"
                     "free:\n" + free +
                     "experiments:\n"
                     "  - name: e\n"
                     "    data: " + csv + "\n"
                     "    channels: {u: u, tach: tach}\n"
                     "    input: {column: u}\n"
                     "    fit: {tach: 0.005}\n");
}

class FitParamsBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    out_ = axis::testing_files::TestTempDir() + "fit_out_bad_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::filesystem::remove_all(out_);
  }
  // Runs the job, expects exit 2, every `needles` in stderr, and no output.
  void ExpectRejected(const std::string& job,
                      const std::vector<std::string>& needles) {
    const Result r = RunCli(job + " --out " + out_);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    for (const std::string& n : needles) {
      EXPECT_NE(r.err.find(n), std::string::npos) << "missing '" << n << "' in: " << r.err;
    }
    EXPECT_FALSE(std::filesystem::exists(out_)) << "output written";
  }
  std::string out_;
};

TEST_F(FitParamsBadInput, MissingColumn) {
  const std::string csv = Write("nocol.csv", "t,u\n0,1\n0.001,1\n0.002,1\n");
  ExpectRejected(Job("nocol.yaml", csv), {"nocol.yaml", "channels.tach", "'tach'"});
}

TEST_F(FitParamsBadInput, NaNCell) {
  const std::string csv = Write("nan.csv", "t,u,tach\n0,1,0\n0.001,nan,0\n0.002,1,0\n");
  ExpectRejected(Job("nan.yaml", csv), {"nan.csv:3", "column 'u'"});
}

TEST_F(FitParamsBadInput, EmptyCell) {
  const std::string csv = Write("empty_cell.csv", "t,u,tach\n0,1,0\n0.001,,0\n0.002,1,0\n");
  ExpectRejected(Job("empty_cell.yaml", csv), {"empty_cell.csv:3", "empty"});
}

TEST_F(FitParamsBadInput, TimeNotStrictlyIncreasing) {
  const std::string csv = Write("time.csv", "t,u,tach\n0,1,0\n0.001,1,0\n0.001,1,0\n");
  ExpectRejected(Job("time.yaml", csv), {"time.csv:4", "strictly increasing"});
}

TEST_F(FitParamsBadInput, EmptyAndHeaderOnlyFiles) {
  ExpectRejected(Job("empty.yaml", Write("empty.csv", "")), {"empty.csv"});
  ExpectRejected(Job("header.yaml", Write("header.csv", "t,u,tach\n")),
                 {"header.csv", "data row"});
}

TEST_F(FitParamsBadInput, FreeParameterTheModelDoesNotHave) {
  const std::string csv = kRoot + "/testdata/x_step_10V_clean.csv";
  ExpectRejected(Job("unknown_free.yaml", csv,
                     "  Q_x: {initial: 1, lower: 0.1, upper: 10}\n"),
                 {"unknown_free.yaml:3", "free.Q_x", "parameter name"});
}

TEST_F(FitParamsBadInput, BoundsReversed) {
  const std::string csv = kRoot + "/testdata/x_step_10V_clean.csv";
  ExpectRejected(Job("reversed.yaml", csv,
                     "  B_a: {initial: 150, lower: 2000, upper: 10}\n"),
                 {"reversed.yaml:3", "free.B_a", "expected lower < upper"});
}

TEST_F(FitParamsBadInput, InitialOutsideBounds) {
  const std::string csv = kRoot + "/testdata/x_step_10V_clean.csv";
  ExpectRejected(Job("outside.yaml", csv,
                     "  B_a: {initial: 5000, lower: 10, upper: 2000}\n"),
                 {"outside.yaml:3", "free.B_a", "within [10, 2000]", "5000"});
}

// A free parameter's initial value and bounds are finite and in the
// parameter's range, as set: requires of a value (configs/README.md, free:):
// an infinite B_a used to fit inf/nan and a negative mass to fit, both with
// exit 0. V_L may be .inf in a model, never as a bound.
TEST_F(FitParamsBadInput, FreeParameterOutsideItsRange) {
  const std::string csv = kRoot + "/testdata/x_step_10V_clean.csv";
  struct Case {
    std::string free, key, expected;
  };
  const Case cases[] = {
      {"  B_a: {initial: .inf, lower: 10, upper: .inf}\n", "free.B_a.initial",
       "expected a finite number, got '.inf'"},
      {"  B_a: {initial: 150, lower: 10, upper: .inf}\n", "free.B_a.upper",
       "expected a finite number, got '.inf'"},
      {"  B_a: {initial: 150, lower: -1, upper: 2000}\n", "free.B_a.lower",
       "expected a finite number >= 0 (the range of B_a), got '-1'"},
      {"  M: {initial: -100, lower: -500, upper: 1000}\n", "free.M.initial",
       "expected a finite positive number (the range of M), got '-100'"},
      {"  M: {initial: 100, lower: -500, upper: 1000}\n", "free.M.lower",
       "expected a finite positive number (the range of M), got '-500'"},
      {"  T_p: {lower: 0, upper: 1}\n", "free.T_p.lower",
       "expected a finite positive number (the range of T_p), got '0'"},
      {"  V_L: {initial: 2.7, lower: 0.5, upper: .inf}\n", "free.V_L.upper",
       "expected a finite number, got '.inf'"},
      {"  V_L: {initial: 2.7, lower: -1, upper: 20}\n", "free.V_L.lower",
       "expected a finite positive number (the range of V_L), got '-1'"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.key);
    ExpectRejected(Job("free_range.yaml", csv, c.free),
                   {"free_range.yaml:3: key '" + c.key + "': " + c.expected});
  }
}

TEST_F(FitParamsBadInput, UnknownJobKey) {
  const std::string job = Job("unknown_key.yaml", kRoot + "/testdata/x_step_10V_clean.csv");
  std::ofstream(job, std::ios::app) << "solvr: {starts: 2}\n";
  ExpectRejected(job, {"unknown_key.yaml:10", "'solvr'"});
}

// A free parameter listed twice, or a job key given twice, is refused with
// the file, the line of the second and the line of the first.
TEST_F(FitParamsBadInput, RepeatedKeys) {
  const std::string csv = kRoot + "/testdata/x_step_10V_clean.csv";
  ExpectRejected(Job("twice_free.yaml", csv,
                     "  B_a: {initial: 150, lower: 10, upper: 2000}\n"
                     "  B_a: {initial: 200, lower: 10, upper: 2000}\n"),
                 {"twice_free.yaml:4", "free.B_a", "again (first on line 3)"});
  const std::string job = Job("twice_title.yaml", csv);
  std::ofstream(job, std::ios::app) << "title: a\ntitle: b\n";
  ExpectRejected(job, {"twice_title.yaml:11", "'title'", "again (first on line 10)"});
}

// A simulation step beyond RK4's stability limit is refused before any
// data is read or simulated.
TEST_F(FitParamsBadInput, UnstableSimulationStep) {
  const std::string job = Job("unstable.yaml", kRoot + "/testdata/x_step_10V_clean.csv");
  std::ofstream(job, std::ios::app) << "simulation: {step: 1.0e-3}\n";
  ExpectRejected(job, {"unstable.yaml:10", "'simulation.step'", "RK4 stability limit",
                       "got 0.001 s"});
}

// An empty experiment list says so.
TEST_F(FitParamsBadInput, EmptyExperimentList) {
  const std::string job = Write("no_experiments.yaml",
                                "model: " + kRoot + "/configs/axes/x_axis.yaml\n"
                                "free:\n  B_a: {initial: 150, lower: 10, upper: 2000}\n"
                                "experiments: []\n");
  ExpectRejected(job, {"no_experiments.yaml:4", "expected a non-empty list of experiments",
                       "got an empty list"});
}

// An output folder that cannot be made (an existing file in the way, as
// the folder itself or as one of its parents) is refused before the fit,
// naming the file (it was found after the fit, exit 1, "filesystem
// error"), and the file is left as it was.
TEST_F(FitParamsBadInput, OutputPathThroughAFile) {
  const std::string job = Job("out_file.yaml", kRoot + "/testdata/x_step_10V.csv");
  const std::string file = Write("not_a_folder.csv", "t,u\n0,0\n");
  for (const std::string& out : {file, file + "/sub"}) {
    const Result r = RunCli(job + " --out " + out);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(out + ": expected an output directory"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("got '" + file + "', an existing file"), std::string::npos) << r.err;
  }
  std::ifstream in(file);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "t,u\n0,0\n");
}

// output: {dir: ""} without --out wrote into the job file's folder while
// --out "" is refused (issue 46): refused naming file, line and key, and
// nothing written there.
TEST_F(FitParamsBadInput, EmptyOutputDirInTheJob) {
  const std::string job = Job("empty_out.yaml", kRoot + "/testdata/x_step_10V_clean.csv");
  std::ofstream(job, std::ios::app) << "output: {dir: \"\"}\n";
  const Result r = RunCli(job);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("empty_out.yaml:10: key 'output.dir': expected a folder path"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(axis::testing_files::TestTempDir() + "report.json"));
}

// Text that is not UTF-8 (a UTF-16 job, a NUL byte in a CSV) is named by
// byte offset instead of printed raw and cut at the NUL; a dropped sample
// is named at its line (issue 46).
TEST_F(FitParamsBadInput, NonUtf8TextAndADroppedSample) {
  const std::string csv = kRoot + "/testdata/x_step_10V_clean.csv";
  const std::string job = Job("utf8.yaml", csv);
  std::ifstream in(job);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  std::string utf16 = "\xff\xfe";
  for (const char c : text) utf16 += std::string(1, c) + '\0';
  std::ofstream(job, std::ios::binary) << utf16;
  ExpectRejected(job, {"utf8.yaml:1: expected UTF-8 text, got byte 0xFF at byte offset 0 (not "
                       "UTF-8 text; a UTF-16 file?"});
  const std::string nul = axis::testing_files::TestTempDir() + "nul.csv";
  std::ofstream(nul, std::ios::binary) << std::string("t,u,tach\n0,1,0\n0.001,\0,0\n", 25);
  ExpectRejected(Job("nul.yaml", nul), {"nul.csv:3: expected UTF-8 text, got a NUL byte at byte "
                                         "offset 21"});
  std::string gap = "t,u,tach\n";
  for (int k = 0; k < 10; ++k) {
    if (k != 5) gap += "0.00" + std::to_string(k) + ",1,0\n";
  }
  ExpectRejected(Job("gap.yaml", Write("gap.csv", gap)),
                 {"gap.csv:7: expected uniform sampling", "got a step of 0.002 s from 0.004 to "
                                                         "0.006 s (a gap: a dropped sample?)"});
}

TEST_F(FitParamsBadInput, CommandLine) {
  EXPECT_EQ(RunCli("").exit_code, 2);
  EXPECT_EQ(RunCli("--model " + kRoot + "/configs/axes/x_axis.yaml").exit_code, 2);
}

}  // namespace
