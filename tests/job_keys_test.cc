// Job keys added for the EMPS benchmark (issue 5): the initial state from
// the first samples (the benchmark's protocol), the published reference
// beside the fit, and the errors for keys that would otherwise be ignored.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "estimation/fit.h"
#include "estimation/fit_result.h"
#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "report/published.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;

constexpr auto Write = testing_files::WriteTemp;

// x = 0.2 + 0.5·t (m), a ramp: the line through the first 20 samples,
// extrapolated to sample 20, is the exact state there.
std::string RampCsv() {
  std::string csv = "t,u,x\n";
  for (int k = 0; k < 100; ++k) {
    const double t = 0.001 * k;
    csv += std::to_string(t) + ",1," + std::to_string(0.2 + 0.5 * t) + "\n";
  }
  return Write("ramp.csv", csv);
}

// The ramp job with `channels` and `input` (YAML flow maps), the
// experiment's `experiment_extra` keys and the top level's `top_extra`.
std::string JobWith(const std::string& channels, const std::string& input,
                    const std::string& experiment_extra, const std::string& top_extra) {
  return "model: " + kRoot + "/configs/axes/emps.yaml\n"
         "free:\n"
         "  M: {initial: 95, lower: 10, upper: 500}\n"
         "experiments:\n"
         "  - name: ramp\n"
         "    data: " + RampCsv() + "\n"
         "    channels: " + channels + "\n"
         "    input: " + input + "\n"
         "    fit: {x: 1.0e-6}\n" + experiment_extra + top_extra;
}

std::string Job(const std::string& experiment_extra, const std::string& top_extra = "") {
  return JobWith("{u: u, x: x}", "{column: u}", experiment_extra, top_extra);
}

double Estimate(const FitResult& r) {
  for (const ParameterEstimate& p : r.parameters) {
    if (p.name == "M") return p.value;
  }
  return std::nan("");
}

std::string LoadError(const std::string& path) {
  try {
    LoadFitJob(path);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

// An input column without `interpolation`: a piecewise-constant one (here
// changing every 5th sample: 80 of 99 consecutive pairs equal, 80.8 %) is held and
// the job says so, naming the key; a column that changes at every sample is
// read linearly without a note; an explicit `interpolation` is obeyed.
// Every committed job (configs/jobs/, recursively) loads under the strict
// loader as it is now (a rule added to it must not refuse the project's own
// jobs), and every model config and experiment (configs/, the generating
// configs of testdata/) too.
TEST(JobKeysTest, EveryCommittedJobLoads) {
  namespace fs = std::filesystem;
  // The YAML files under `dir` (of the project) loaded by `load`; how many.
  const auto load_all = [](const std::string& dir, const auto& load) {
    int n = 0;
    for (const auto& entry : fs::recursive_directory_iterator(kRoot + dir)) {
      if (entry.path().extension() != ".yaml") continue;
      SCOPED_TRACE(entry.path().string());
      EXPECT_NO_THROW(load(entry.path().string()));
      ++n;
    }
    return n;
  };
  EXPECT_GE(load_all("/configs/jobs", LoadFitJob), 10);
  EXPECT_GE(load_all("/configs/axes", LoadAxisConfig), 1);
  EXPECT_GE(load_all("/configs/experiments", LoadExperiment) +
                load_all("/testdata/generate", LoadExperiment),
            10);
}

TEST(JobKeysTest, PiecewiseConstantInputColumnIsHeld) {
  std::string csv = "t,held,smooth,x\n";
  for (int k = 0; k < 100; ++k) {
    const double t = 0.001 * k;
    csv += std::to_string(t) + "," + std::to_string(0.5 * (k / 5)) + "," +
           std::to_string(std::sin(30.0 * t)) + ",0\n";
  }
  const std::string data = Write("levels.csv", csv);
  const auto job = [&](const std::string& input) {
    return "model: " + kRoot + "/configs/axes/emps.yaml\n"
           "free:\n"
           "  M: {initial: 95, lower: 10, upper: 500}\n"
           "experiments:\n"
           "  - name: levels\n"
           "    data: " + data + "\n"
           "    channels: {x: x}\n"
           "    input: " + input + "\n"
           "    fit: {x: 1.0e-6}\n";
  };
  const FitJob held = LoadFitJob(Write("held.yaml", job("{column: held}")));
  EXPECT_TRUE(held.problem.experiments[0].drive.input.hold);
  ASSERT_EQ(held.problem.experiments[0].input_notes.size(), 1u);
  const std::string& note = held.problem.experiments[0].input_notes[0];
  EXPECT_NE(note.find("'held' read as held (piecewise constant: 80.8 % of consecutive samples "
                      "equal, 19 changes)"),
            std::string::npos) << note;
  EXPECT_NE(note.find("input.interpolation: linear"), std::string::npos) << note;

  const FitJob smooth = LoadFitJob(Write("smooth.yaml", job("{column: smooth}")));
  EXPECT_FALSE(smooth.problem.experiments[0].drive.input.hold);
  EXPECT_TRUE(smooth.problem.experiments[0].input_notes.empty());

  const FitJob linear =
      LoadFitJob(Write("linear.yaml", job("{column: held, interpolation: linear}")));
  EXPECT_FALSE(linear.problem.experiments[0].drive.input.hold);
  EXPECT_TRUE(linear.problem.experiments[0].input_notes.empty());
}

TEST(JobKeysTest, InitialStateFromTheFirstSamples) {
  const FitJob job = LoadFitJob(
      Write("from_samples.yaml", Job("    initial_state: {from_samples: 20}\n")));
  const FitExperiment& e = job.problem.experiments[0];
  // std::to_string keeps 6 decimals: x is exact to 5e-7 m.
  EXPECT_NEAR(e.initial_state[0], 0.2 + 0.5 * 0.020, 1e-6);
  EXPECT_NEAR(e.initial_state[1], 0.5, 1e-3);
  EXPECT_EQ(e.t.size(), 80u);  // the experiment starts at sample 20
  EXPECT_NEAR(e.t_offset, 0.020, 1e-12);
  EXPECT_NEAR(e.measured[1][0], 0.21, 1e-6);
}

// An accelerating start, x = 0.1 + 0.2·t + 0.5·a·t² with a = 1 m/s² (as
// the EMPS runs start: 0.95 m/s² over their first 20 ms): the default
// quadratic through the first 20 samples is the exact state at sample 20
// (v = 0.2 + a·0.020 = 0.22 m/s), the line (degree: 1) returns the velocity
// at the window's middle (9.5 ms), 10.5 samples before sample 20:
// 0.2095 m/s. Positions are written with 12 significant digits, so both to
// 1e-9 m/s, not 1e-3.
TEST(JobKeysTest, InitialStateFromAcceleratingSamples) {
  std::string csv = "t,u,x\n";
  char row[96];
  for (int k = 0; k < 100; ++k) {
    const double t = 0.001 * k;
    std::snprintf(row, sizeof row, "%.6f,1,%.12g\n", t, 0.1 + 0.2 * t + 0.5 * t * t);
    csv += row;
  }
  const std::string data = Write("accelerating.csv", csv);
  auto job = [&](const std::string& init) {
    return "model: " + kRoot + "/configs/axes/emps.yaml\n"
           "free:\n"
           "  M: {initial: 95, lower: 10, upper: 500}\n"
           "experiments:\n"
           "  - name: accelerating\n"
           "    data: " + data + "\n"
           "    channels: {u: u, x: x}\n"
           "    input: {column: u}\n"
           "    fit: {x: 1.0e-6}\n"
           "    initial_state: " + init + "\n";
  };
  const double t20 = 0.020;
  const FitJob quadratic = LoadFitJob(Write("quadratic.yaml", job("{from_samples: 20}")));
  EXPECT_NEAR(quadratic.problem.experiments[0].initial_state[0], 0.1 + 0.2 * t20 + 0.5 * t20 * t20,
              1e-9);
  EXPECT_NEAR(quadratic.problem.experiments[0].initial_state[1], 0.2 + t20, 1e-9);
  const FitJob line = LoadFitJob(Write("line.yaml", job("{from_samples: 20, degree: 1}")));
  EXPECT_NEAR(line.problem.experiments[0].initial_state[1], 0.2 + 0.0095, 1e-9);
  const std::string too_few = LoadError(Write("two_samples.yaml", job("{from_samples: 2}")));
  EXPECT_NE(too_few.find("initial_state.from_samples': expected more samples than the degree 2"),
            std::string::npos)
      << too_few;
  EXPECT_EQ(LoadError(Write("two_line.yaml", job("{from_samples: 2, degree: 1}"))), "no error");
  const std::string bad = Write("degree3.yaml", job("{from_samples: 20, degree: 3}"));
  const std::string msg = LoadError(bad);
  EXPECT_NE(msg.find("initial_state.degree"), std::string::npos) << msg;
  EXPECT_NE(msg.find("got '3'"), std::string::npos) << msg;
}

// A declared start state (a record taken in motion): the states as given,
// the record kept whole; with from_samples beside it the map is refused.
TEST(JobKeysTest, DeclaredInitialState) {
  const FitJob job = LoadFitJob(
      Write("declared_state.yaml", Job("    initial_state: {y0: 0.25, y1: 0.5}\n")));
  const FitExperiment& e = job.problem.experiments[0];
  EXPECT_EQ(e.initial_state[0], 0.25);
  EXPECT_EQ(e.initial_state[1], 0.5);
  EXPECT_EQ(e.t.size(), 100u);  // nothing dropped
  const std::string msg = LoadError(Write(
      "declared_and_samples.yaml", Job("    initial_state: {y1: 0.5, from_samples: 20}\n")));
  EXPECT_NE(msg.find("from_samples"), std::string::npos) << msg;
}

// The optimum check's "lower" follows function_tolerance (estimation/fit.cc
// LowerThan): above 1 % it is refused, naming the key.
TEST(JobKeysTest, FunctionToleranceAboveOnePercentIsAnError) {
  const std::string msg = LoadError(
      Write("loose_tolerance.yaml", Job("", "solver: {function_tolerance: 2}\n")));
  EXPECT_NE(msg.find("solver.function_tolerance"), std::string::npos) << msg;
  EXPECT_NE(msg.find("got 2"), std::string::npos) << msg;
}

TEST(JobKeysTest, TooManyInitialSamplesIsAnError) {
  const std::string path =
      Write("from_samples_bad.yaml", Job("    initial_state: {from_samples: 98}\n"));
  const std::string msg = LoadError(path);
  EXPECT_NE(msg.find(path + ":"), std::string::npos) << msg;
  EXPECT_NE(msg.find("initial_state.from_samples"), std::string::npos) << msg;
  EXPECT_NE(msg.find("got 98"), std::string::npos) << msg;
}

TEST(JobKeysTest, ControllerInAnOpenLoopExperimentIsAnError) {
  const std::string msg = LoadError(
      Write("open_loop_controller.yaml", Job("    controller: {delay_samples: 1}\n")));
  EXPECT_NE(msg.find("experiments[0].controller"), std::string::npos) << msg;
  EXPECT_NE(msg.find("closed loop"), std::string::npos) << msg;
}

// Numbers are finite (configs/README.md, Ranges): an infinite scale or
// offset of a drive column or a measured channel, or an infinite solver
// tolerance, is refused naming its key; `input: {column: u, scale: .inf}`
// used to fit NaN and exit 0.
TEST(JobKeysTest, InfiniteNumbersAreRefusedNamingTheKey) {
  const auto job = [](const std::string& channels, const std::string& input,
                      const std::string& top) { return JobWith(channels, input, "", top); };
  const std::string channels = "{u: u, x: x}", input = "{column: u}";
  struct Case {
    std::string yaml, key, expected;
  };
  const Case cases[] = {
      {job(channels, "{column: u, scale: .inf}", ""), "experiments[0].input.scale",
       "a finite number, got '.inf'"},
      {job(channels, "{column: u, offset: -.inf}", ""), "experiments[0].input.offset",
       "a finite number, got '-.inf'"},
      {job("{u: u, x: {column: x, scale: .inf}}", input, ""), "experiments[0].channels.x.scale",
       "a finite number, got '.inf'"},
      {job(channels, input, "solver: {parameter_tolerance: .inf}\n"),
       "solver.parameter_tolerance", "a finite number >= 0, got '.inf'"},
  };
  EXPECT_EQ(LoadError(Write("finite.yaml", job(channels, input, ""))), "no error");
  for (const Case& c : cases) {
    SCOPED_TRACE(c.key);
    const std::string path = Write("infinite.yaml", c.yaml);
    const std::string msg = LoadError(path);
    EXPECT_NE(msg.find(path + ":"), std::string::npos) << msg;
    EXPECT_NE(msg.find("key '" + c.key + "': expected " + c.expected), std::string::npos) << msg;
  }
}

// A misspelt required key is named at its own line (it read as a missing
// key at the map's line: `experimnts:` gave "job.yaml:1: key 'experiments':
// expected a value (required key), got nothing").
TEST(JobKeysTest, AMisspeltRequiredKeyIsNamedAtItsLine) {
  std::string text = Job("");
  const size_t at = text.find("experiments:");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 12, "experimnts:");
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + at, '\n'));
  const std::string path = Write("misspelt.yaml", text);
  const std::string msg = LoadError(path);
  EXPECT_NE(msg.find(path + ":" + std::to_string(line) + ":"), std::string::npos) << msg;
  EXPECT_NE(msg.find("unknown key 'experimnts' here: misspelt?"), std::string::npos) << msg;
  const std::string column =
      LoadError(Write("misspelt_column.yaml", JobWith("{u: u, x: x}", "{colum: u}", "", "")));
  EXPECT_NE(column.find("key 'experiments[0].input.column'"), std::string::npos) << column;
  EXPECT_NE(column.find("unknown key 'colum'"), std::string::npos) << column;
}

// A record whose time column is in ms (1 per sample) is refused naming its
// file and row: fitted as seconds it was a 100 s record at 1 Hz (a probe
// of 1.5 s at 1 kHz ran a 1500 s horizon for minutes).
TEST(JobKeysTest, TimeNotInSecondsIsRefused) {
  std::string csv = "t,u,x\n";
  for (int k = 0; k < 100; ++k) {
    csv += std::to_string(k) + ",1," + std::to_string(0.2 + 0.0005 * k) + "\n";
  }
  const std::string data = Write("ramp_ms.csv", csv);
  std::string text = Job("");
  const size_t at = text.find(RampCsv());
  ASSERT_NE(at, std::string::npos);
  text.replace(at, RampCsv().size(), data);
  const std::string msg = LoadError(Write("time_ms.yaml", text));
  EXPECT_NE(msg.find(data + ":"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected time in seconds"), std::string::npos) << msg;
  EXPECT_NE(msg.find("got a period of 1 "), std::string::npos) << msg;
}

// One dropped sample (0.149 -> 0.151 s at 1 ms) is named at its own line
// with the step found there (issue 46): the steps were compared to the
// mean period, which the gap skews, and the record was refused at line 3,
// a normal step.
TEST(JobKeysTest, ADroppedSampleIsNamedAtItsLine) {
  std::string csv = "t,u,x\n";
  char row[64];
  for (int k = 0; k < 300; ++k) {
    if (k == 150) continue;  // dropped
    std::snprintf(row, sizeof row, "%.3f,1,%.6f\n", 0.001 * k, 0.2 + 0.5e-3 * k);
    csv += row;
  }
  const std::string data = Write("gap.csv", csv);
  std::string text = Job("");
  const size_t at = text.find(RampCsv());
  ASSERT_NE(at, std::string::npos);
  text.replace(at, RampCsv().size(), data);
  const std::string msg = LoadError(Write("gap.yaml", text));
  // t = 0.151 s is data row 150, line 152.
  EXPECT_EQ(msg, data + ":152: expected uniform sampling (the median step 0.001 s within "
                        "0.1 %), got a step of 0.002 s from 0.149 to 0.151 s (a gap: a dropped "
                        "sample?)");
}

// output.dir "" resolved to the job file's own folder and the job wrote
// there, while --out "" is refused (issue 46): refused naming file, line, key.
TEST(JobKeysTest, AnEmptyOutputDirIsRefused) {
  for (const std::string dir : {"\"\"", "' '"}) {
    SCOPED_TRACE(dir);
    const std::string path = Write("empty_out.yaml", Job("", "output: {dir: " + dir + "}\n"));
    const std::string msg = LoadError(path);
    EXPECT_NE(msg.find(path + ":"), std::string::npos) << msg;
    EXPECT_NE(msg.find("key 'output.dir': expected a folder path (relative to the file's "
                       "folder, or absolute), got '"),
              std::string::npos)
        << msg;
  }
  EXPECT_EQ(LoadError(Write("out.yaml", Job("", "output: {dir: out}\n"))), "no error");
}

// A second YAML document was silently ignored and a merge key '<<' not
// applied (yaml-cpp reads it as a key named "<<"), the job then failing on a
// key it did not name; a job that is not UTF-8 text printed raw bytes cut
// at the first NUL (issue 46). Each is refused naming the file and line.
TEST(JobKeysTest, SecondDocumentMergeKeyAndNonUtf8AreRefused) {
  const std::string job = Job("");
  const int lines = static_cast<int>(std::count(job.begin(), job.end(), '\n'));
  std::string path = Write("two_documents.yaml", job + "---\nsolver: {starts: 5}\n");
  std::string msg = LoadError(path);
  EXPECT_EQ(msg, path + ":" + std::to_string(lines + 1) +
                     ": expected one YAML document, got a second one (a '---' line; only one "
                     "document per file is read)");
  // A leading '---' (one document) is fine.
  EXPECT_EQ(LoadError(Write("leading_marker.yaml", "---\n" + job)), "no error");

  std::string text = "bounds: &b {lower: 10, upper: 500}\n" + job;
  const size_t at = text.find("  M: {initial: 95, lower: 10, upper: 500}\n");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 42, "  M:\n    <<: *b\n    initial: 95\n");
  path = Write("merge.yaml", text);
  msg = LoadError(path);
  const int merge_line = 2 + static_cast<int>(std::count(text.begin(), text.begin() + at, '\n'));
  EXPECT_EQ(msg, path + ":" + std::to_string(merge_line) +
                     ": key 'free.M.<<': expected no YAML merge key (not supported: write the "
                     "keys out), got '<<' (a merge key)");

  text = job;
  text.replace(text.find("model:"), 1, std::string(1, '\0'));
  path = Write("nul.yaml", "");
  std::ofstream(path, std::ios::binary) << text;
  msg = LoadError(path);
  EXPECT_EQ(msg, path + ":1: expected UTF-8 text, got a NUL byte at byte offset 0 (not UTF-8 "
                        "text; a UTF-16 file? save it as UTF-8)");
  EXPECT_EQ(msg.size(), std::strlen(msg.c_str()));  // no NUL in the message
}

// discover.alpha is a level: in (0, 1), as the fleet's `alpha`; 5 used to
// be accepted (every candidate significant).
TEST(JobKeysTest, DiscoverAlphaIsALevel) {
  EXPECT_EQ(LoadError(Write("alpha_ok.yaml", Job("", "discover: {alpha: 0.05}\n"))), "no error");
  struct Case {
    std::string alpha, expected;
  };
  const Case cases[] = {
      {"5", "expected a level in (0, 1), got '5'"},
      {"1", "expected a level in (0, 1), got '1'"},
      {"0", "expected a finite positive number, got '0'"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.alpha);
    const std::string path = Write("alpha.yaml", Job("", "discover: {alpha: " + c.alpha + "}\n"));
    const std::string msg = LoadError(path);
    EXPECT_NE(msg.find(path + ":"), std::string::npos) << msg;
    EXPECT_NE(msg.find("key 'discover.alpha': " + c.expected), std::string::npos) << msg;
  }
}

// The quick form's bounds (value/10 and value*10, [-1, 1] about zero) are
// clipped to the parameter's range: F_s = 0 (F_s >= 0) gets [0, 1], where
// it used to get [-1, 1]; a parameter without a finite value has none.
TEST(JobKeysTest, QuickFormBoundsRespectTheRange) {
  const std::string model = kRoot + "/configs/axes/x_axis.yaml";
  const std::string data = kRoot + "/testdata/x_step_10V_clean.csv";
  const FitJob job = MakeQuickJob(model, data, "u", {"tach"}, {"F_s", "B_a"});
  ASSERT_EQ(job.problem.free.size(), 2u);
  EXPECT_EQ(job.problem.free[0].name, "F_s");
  EXPECT_EQ(job.problem.free[0].lower, 0.0);
  EXPECT_EQ(job.problem.free[0].upper, 1.0);
  EXPECT_EQ(job.problem.free[1].lower, 20.0);  // B_a = 200: unchanged
  EXPECT_EQ(job.problem.free[1].upper, 2000.0);
  std::ifstream in(model);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  text.replace(text.find("V_L: 2.7"), 8, "V_L: .inf");
  const std::string unlimited = Write("unlimited.yaml", text);
  std::string msg = "no error";
  try {
    MakeQuickJob(unlimited, data, "u", {"tach"}, {"V_L"});
  } catch (const std::invalid_argument& e) {
    msg = e.what();
  }
  EXPECT_NE(msg.find("--free V_L: expected a parameter with a finite value in " + unlimited),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("got inf"), std::string::npos) << msg;
}

TEST(JobKeysTest, PublishedReferenceNamesAKnownExperiment) {
  const std::string msg = LoadError(Write(
      "published_bad.yaml",
      Job("", "published:\n  source: x\n  set: {M: 90}\n"
              "  relative_error_percent: {nowhere: {u: 1}}\n")));
  EXPECT_NE(msg.find("published.relative_error_percent.nowhere"), std::string::npos) << msg;
}

// The published model is simulated on the job's experiments: with the
// published values equal to the fitted ones, both errors agree exactly;
// with another mass they do not.
TEST(JobKeysTest, PublishedModelIsSimulatedHere) {
  FitJob job = LoadFitJob(Write(
      "published.yaml",
      Job("", "published:\n  source: test\n  set: {M: 95}\n"
              "  relative_error_percent: {ramp: {x: 1.5}}\n")));
  job.problem.solver.progress = false;
  job.problem.free[0].initial = 95;
  job.problem.solver.max_iterations = 1;
  FitResult result = FitParameters(job.problem);
  job.published.model.params.M = Estimate(result);
  const PublishedComparison c = ComparePublished(job.problem, result, job.published);
  ASSERT_EQ(c.parameters.size(), 1u);
  EXPECT_EQ(c.parameters[0].name, "M");
  EXPECT_TRUE(c.parameters[0].free);
  bool found = false;
  for (const ChannelComparison& r : c.channels) {
    if (r.channel != "x") continue;
    found = true;
    EXPECT_DOUBLE_EQ(r.published_percent, r.fitted_percent);
    EXPECT_DOUBLE_EQ(r.quoted_percent, 1.5);
  }
  EXPECT_TRUE(found);
  // And with another published M the published error is that model's, not
  // the fit's: with the mass doubled it moves (98.94 % against 98.27 %
  // seen; this ramp from rest is far from the model, both errors are large),
  // where a comparison that ignored the published model would repeat the
  // fitted error to the last digit.
  job.published.model.params.M = 2.0 * Estimate(result);
  const PublishedComparison d = ComparePublished(job.problem, result, job.published);
  found = false;
  for (const ChannelComparison& r : d.channels) {
    if (r.channel != "x") continue;
    found = true;
    std::cout << "x error: fitted " << r.fitted_percent << " %, published (2 M) "
              << r.published_percent << " %\n";
    EXPECT_GT(std::abs(r.published_percent - r.fitted_percent), 0.1);
  }
  EXPECT_TRUE(found);
}

}  // namespace
}  // namespace axis
