// The report writers: a hand-built FitResult written to a temporary
// directory and read back.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/output_staging.h"
#include "estimation/fit_result.h"
#include "report/report.h"
#include "io/csv.h"
#include "tests/fit_result_fixture.h"
#include "tests/test_files.h"

namespace axis {
namespace {

namespace fs = std::filesystem;
using fixture::MakeResult;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Names of the files in `dir` that look like leftover temporaries.
std::vector<std::string> Temporaries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.find(".tmp.") != std::string::npos) out.push_back(name);
  }
  return out;
}

bool HaveGnuplot() {
  return std::system("command -v gnuplot >/dev/null 2>&1") == 0;
}

class ReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const ::testing::TestInfo* info =
        ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(axis::testing_files::TestTempDir()) /
           ("report_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  fs::path dir_;
};

TEST_F(ReportTest, WritesEveryFile) {
  std::vector<std::string> warnings;
  WriteFitOutputs((dir_ / "out").string(), MakeResult(), "Test fit", &warnings);
  for (const char* name :
       {"params.csv", "params.md", "report.json", "fit_step_1.csv", "fit_chirp.csv"}) {
    EXPECT_TRUE(fs::is_regular_file(dir_ / "out" / name)) << name;
  }
  if (HaveGnuplot()) {
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    EXPECT_TRUE(fs::is_regular_file(dir_ / "out" / "fit_step_1.png"));
    EXPECT_TRUE(fs::is_regular_file(dir_ / "out" / "fit_chirp.png"));
  } else {
    ASSERT_EQ(warnings.size(), 2u);
    EXPECT_EQ(warnings[0], "gnuplot not found: no plot written for step 1");
  }
  EXPECT_TRUE(Temporaries(dir_ / "out").empty());
}

TEST_F(ReportTest, ReportJsonHasTheRequiredShape) {
  std::vector<std::string> warnings;
  WriteFitOutputs(dir_.string(), MakeResult(), "Test fit", &warnings);
  const nlohmann::json j = nlohmann::json::parse(ReadText(dir_ / "report.json"));

  ASSERT_EQ(j.at("parameters").size(), 3u);
  const auto& p0 = j["parameters"][0];  // free first
  EXPECT_EQ(p0.at("name"), "V_L");
  EXPECT_EQ(p0.at("unit"), "V");
  EXPECT_DOUBLE_EQ(p0.at("value").get<double>(), 0.1234);
  EXPECT_DOUBLE_EQ(p0.at("std_error").get<double>(), 0.002);
  EXPECT_DOUBLE_EQ(p0.at("ci95_low").get<double>(), 0.1194);
  EXPECT_DOUBLE_EQ(p0.at("ci95_high").get<double>(), 0.1274);
  EXPECT_DOUBLE_EQ(p0.at("initial").get<double>(), 0.1);
  EXPECT_EQ(p0.at("free"), true);
  EXPECT_EQ(p0.at("determined"), true);
  const auto& p1 = j["parameters"][1];
  EXPECT_EQ(p1.at("name"), "K_t");
  EXPECT_TRUE(p1.at("std_error").is_null());  // NaN → null
  EXPECT_EQ(p1.at("determined"), false);
  const auto& p2 = j["parameters"][2];
  EXPECT_EQ(p2.at("name"), "m_L");
  EXPECT_EQ(p2.at("free"), false);
  EXPECT_TRUE(p2.at("std_error").is_null());
  EXPECT_TRUE(p2.at("ci95_low").is_null());
  EXPECT_TRUE(p2.at("ci95_high").is_null());
  EXPECT_DOUBLE_EQ(p2.at("value").get<double>(), 2.5);

  ASSERT_EQ(j.at("experiments").size(), 2u);
  const auto& e0 = j["experiments"][0];
  EXPECT_EQ(e0.at("name"), "step 1");
  EXPECT_EQ(e0.at("role"), "fit");
  ASSERT_EQ(e0.at("channels").size(), 2u);
  const auto& c0 = e0["channels"][0];
  EXPECT_EQ(c0.at("channel"), "a");
  EXPECT_DOUBLE_EQ(c0.at("rms").get<double>(), 0.012);
  EXPECT_DOUBLE_EQ(c0.at("fit_percent").get<double>(), 98.5);
  EXPECT_DOUBLE_EQ(c0.at("max_error").get<double>(), 0.03);
  EXPECT_DOUBLE_EQ(c0.at("relative_error_percent").get<double>(), 1.5);
  EXPECT_DOUBLE_EQ(c0.at("ljung_box_q").get<double>(), 42.0);
  EXPECT_DOUBLE_EQ(c0.at("ljung_box_p").get<double>(), 0.0025);
  EXPECT_DOUBLE_EQ(c0.at("input_xcorr_peak").get<double>(), -0.31);
  EXPECT_EQ(c0.at("input_xcorr_lag"), 2);
  EXPECT_DOUBLE_EQ(c0.at("sigma").get<double>(), 0.01);
  EXPECT_EQ(c0.at("fitted"), true);
  const auto& e1 = j["experiments"][1];
  EXPECT_EQ(e1.at("role"), "validate");
  EXPECT_EQ(e1["channels"][0].at("fitted"), false);
  EXPECT_TRUE(e1["channels"][0].at("ljung_box_p").is_null());
  EXPECT_TRUE(e1["channels"][0].at("fit_percent").is_null());  // −inf

  EXPECT_DOUBLE_EQ(j.at("cost").at("initial").get<double>(), 120.5);
  EXPECT_DOUBLE_EQ(j.at("cost").at("final").get<double>(), 3.25);
  EXPECT_EQ(j.at("converged"), true);
  ASSERT_EQ(j.at("starts").size(), 3u);
  EXPECT_DOUBLE_EQ(j["starts"][1].get<double>(), 7.5);
  EXPECT_TRUE(j["starts"][2].is_null());
  EXPECT_DOUBLE_EQ(j.at("aic").get<double>(), 10.5);
  EXPECT_DOUBLE_EQ(j.at("bic").get<double>(), 6.5 + 2.0 * std::log(600.0));
  EXPECT_EQ(j.at("num_residuals"), 600);
  EXPECT_DOUBLE_EQ(j.at("residual_variance").get<double>(), 6.5 / 598.0);
  EXPECT_EQ(j.at("iterations"), 17);
  EXPECT_EQ(j.at("simulations"), 40);
  EXPECT_EQ(j.at("jacobian_evaluations"), 18);
  EXPECT_EQ(j.at("correlation").at("names"),
            nlohmann::json::array({"V_L", "K_t"}));
  const auto& m = j["correlation"].at("matrix");
  ASSERT_EQ(m.size(), 2u);
  EXPECT_DOUBLE_EQ(m[0][1].get<double>(), 0.995);
  EXPECT_DOUBLE_EQ(m[1][1].get<double>(), 1.0);
  EXPECT_EQ(j.at("undetermined"), nlohmann::json::array({"K_t"}));
}

TEST_F(ReportTest, ParamsCsvHeaderAndRows) {
  fs::create_directories(dir_);
  const fs::path path = dir_ / "params.csv";
  WriteParamsCsv(path.string(), MakeResult());
  std::istringstream in(ReadText(path));
  std::string header, vl, kt, ml, extra;
  std::getline(in, header);
  std::getline(in, vl);
  std::getline(in, kt);
  std::getline(in, ml);
  EXPECT_EQ(header, "name,unit,value,std_error,ci95_low,ci95_high,initial,free");
  EXPECT_EQ(vl, "V_L,V,0.1234,0.002,0.1194,0.1274,0.1,free");
  EXPECT_EQ(kt, "K_t,V*s/rad,0.05,nan,nan,nan,0.04,free");
  EXPECT_EQ(ml, "m_L,kg,2.5,,,,2.5,fixed");
  EXPECT_FALSE(std::getline(in, extra));
}

TEST_F(ReportTest, ExperimentCsvResidualIsSimulatedMinusMeasured) {
  fs::create_directories(dir_);
  const FitResult r = MakeResult();
  const fs::path path = dir_ / "fit_step_1.csv";
  WriteExperimentCsv(path.string(), r.experiments[0]);
  const CsvTable table = ReadCsv(path.string());
  ASSERT_EQ(table.names,
            (std::vector<std::string>{"t", "a_measured", "a_simulated",
                                      "a_residual", "x_measured",
                                      "x_simulated", "x_residual"}));
  ASSERT_EQ(table.num_rows(), 200u);
  for (const char* ch : {"a", "x"}) {
    const std::string c = ch;
    const auto& y = table.Column(c + "_measured");
    const auto& yhat = table.Column(c + "_simulated");
    const auto& e = table.Column(c + "_residual");
    for (size_t k = 0; k < y.size(); ++k) {
      // 12 significant digits in the file.
      EXPECT_NEAR(e[k], yhat[k] - y[k], 1e-11 * (std::abs(y[k]) + 1e-3))
          << c << " row " << k;
    }
  }
  EXPECT_DOUBLE_EQ(table.Column("t")[10], 0.05);
  EXPECT_NEAR(table.Column("a_measured")[10],
              r.experiments[0].channels[0].measured[10], 1e-11);
}

TEST_F(ReportTest, ExperimentCsvRejectsLengthMismatch) {
  fs::create_directories(dir_);
  ExperimentFit e = MakeResult().experiments[0];
  e.channels[1].simulated.pop_back();
  const fs::path path = dir_ / "bad.csv";
  EXPECT_THROW(WriteExperimentCsv(path.string(), e), std::invalid_argument);
  EXPECT_FALSE(fs::exists(path));
}

TEST_F(ReportTest, PlotIsWrittenWithGnuplot) {
  if (!HaveGnuplot()) GTEST_SKIP() << "gnuplot is not installed";
  fs::create_directories(dir_);
  const FitResult r = MakeResult();
  const fs::path csv = dir_ / "fit_step_1.csv";
  const fs::path png = dir_ / "fit_step_1.png";
  WriteExperimentCsv(csv.string(), r.experiments[0]);
  std::string warning = "stale";
  ASSERT_TRUE(WriteExperimentPlot(png.string(), csv.string(), r.experiments[0],
                                  &warning))
      << warning;
  EXPECT_EQ(warning, "");
  const std::string bytes = ReadText(png);
  ASSERT_GT(bytes.size(), 1000u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  EXPECT_TRUE(Temporaries(dir_).empty());
}

TEST_F(ReportTest, PlotOfDivergedSimulationIsWritten) {
  if (!HaveGnuplot()) GTEST_SKIP() << "gnuplot is not installed";
  fs::create_directories(dir_);
  ExperimentFit e = MakeResult().experiments[0];
  for (double& v : e.channels[1].simulated) v = kNaN;  // no finite sample
  const fs::path csv = dir_ / "d.csv";
  const fs::path png = dir_ / "d.png";
  WriteExperimentCsv(csv.string(), e);
  std::string warning;
  EXPECT_TRUE(WriteExperimentPlot(png.string(), csv.string(), e, &warning))
      << warning;
  EXPECT_TRUE(fs::is_regular_file(png));
}

TEST_F(ReportTest, FailingGnuplotIsAWarning) {
  if (!HaveGnuplot()) GTEST_SKIP() << "gnuplot is not installed";
  fs::create_directories(dir_);
  const fs::path png = dir_ / "x.png";
  std::string warning;
  EXPECT_FALSE(WriteExperimentPlot(png.string(), (dir_ / "missing.csv").string(),
                                   MakeResult().experiments[0], &warning));
  EXPECT_EQ(warning.rfind("gnuplot exited with status ", 0), 0u) << warning;
  EXPECT_NE(warning.find("no plot written for step 1"), std::string::npos)
      << warning;
  EXPECT_FALSE(fs::exists(png));
  EXPECT_TRUE(Temporaries(dir_).empty());
}

TEST_F(ReportTest, MissingGnuplotIsAWarning) {
  fs::create_directories(dir_ / "empty_bin");
  const FitResult r = MakeResult();
  const fs::path csv = dir_ / "fit_step_1.csv";
  WriteExperimentCsv(csv.string(), r.experiments[0]);
  const char* old = std::getenv("PATH");
  const std::string saved = old != nullptr ? old : "";
  ::setenv("PATH", (dir_ / "empty_bin").c_str(), 1);
  std::string warning;
  bool written = true;
  EXPECT_NO_THROW(written = WriteExperimentPlot((dir_ / "p.png").string(),
                                                csv.string(), r.experiments[0],
                                                &warning));
  ::setenv("PATH", saved.c_str(), 1);
  EXPECT_FALSE(written);
  EXPECT_EQ(warning, "gnuplot not found: no plot written for step 1");
  EXPECT_FALSE(fs::exists(dir_ / "p.png"));
}

TEST_F(ReportTest, UnwritablePathThrowsAndLeavesNoFile) {
  try {
    WriteFitOutputs("/proc/nonexistent/out", MakeResult(), "t", nullptr);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/nonexistent/out"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists("/proc/nonexistent"));
  try {
    WriteParamsCsv("/proc/nonexistent.csv", MakeResult());
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/nonexistent.csv"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists("/proc/nonexistent.csv"));
}

TEST_F(ReportTest, FailedFileLeavesNoPartialFile) {
  // params.md is a directory: renaming the finished temporary over it fails.
  fs::create_directories(dir_ / "params.md");
  try {
    WriteFitOutputs(dir_.string(), MakeResult(), "t", nullptr);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("params.md"), std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(Temporaries(dir_).empty());
  EXPECT_TRUE(fs::is_directory(dir_ / "params.md"));
  EXPECT_TRUE(fs::is_empty(dir_ / "params.md"));
  // Written before the failure, and complete.
  EXPECT_EQ(ReadText(dir_ / "params.csv").substr(0, 9), "name,unit");
}

// A second run into the same folder leaves one run's outputs: the first
// run's files the second does not write are removed (also in a merged
// subfolder, a benchmark criterion's, and in a dropped one), the user's own
// files stay, a dropped subfolder with one of them too.
TEST_F(ReportTest, ARerunReplacesTheEarlierRunsOutputs) {
  const fs::path out = dir_ / "out";
  const auto stage = [&](const std::map<std::string, std::string>& files) {
    const std::string staging = MakeStagingDirectory(out.string());
    for (const auto& [name, text] : files) {
      fs::create_directories((fs::path(staging) / name).parent_path());
      std::ofstream(fs::path(staging) / name) << text;
    }
    CommitStagingDirectory(staging, out.string());
  };
  stage({{"params.csv", "1"}, {"fit_v1.csv", "1"}, {"crit/fit_a.csv", "1"},
         {"crit/fit_b.csv", "1"}, {"old/x.csv", "1"}, {"dropped/y.csv", "1"}});
  std::ofstream(out / "notes.txt") << "mine";
  std::ofstream(out / "crit" / "mine.txt") << "mine";
  std::ofstream(out / "dropped" / "mine.txt") << "mine";
  stage({{"params.csv", "2"}, {"crit/fit_a.csv", "2"}});
  EXPECT_EQ(ReadText(out / "params.csv"), "2");
  EXPECT_EQ(ReadText(out / "crit" / "fit_a.csv"), "2");
  EXPECT_FALSE(fs::exists(out / "fit_v1.csv"));
  EXPECT_FALSE(fs::exists(out / "old"));
  EXPECT_FALSE(fs::exists(out / "crit" / "fit_b.csv"));
  EXPECT_EQ(ReadText(out / "notes.txt"), "mine");
  EXPECT_EQ(ReadText(out / "crit" / "mine.txt"), "mine");
  EXPECT_FALSE(fs::exists(out / "dropped" / "y.csv"));
  EXPECT_EQ(ReadText(out / "dropped" / "mine.txt"), "mine");
  EXPECT_EQ(ReadText(out / kOutputList), "crit\nparams.csv\n");
  EXPECT_TRUE(Temporaries(dir_).empty());
}

TEST_F(ReportTest, MarkdownReport) {
  fs::create_directories(dir_);
  FitResult r = MakeResult();
  WriteParamsMarkdown((dir_ / "a.md").string(), r, "Axis 1 | slow");
  const std::string md = ReadText(dir_ / "a.md");
  EXPECT_EQ(md.substr(0, 16), "# Axis 1 | slow\n");
  for (const char* s :
       {"## Parameters", "| V_L | V |", "(not determined by the data)",
        "## Correlation of the free parameters", "0.995",
        "## Not determined by the data", "- K_t", "## Fit", "step 1",
        "chirp", "initial 120.5, final 3.25", "converged: yes",
        "final cost of each start: 3.25, 7.5, nan", "AIC: 10.5",
        "residuals: 600", "iterations: 17, simulations: 40, Jacobian "
        "evaluations: 18",
        "termination: Function tolerance reached. |cost_change|/cost: 1e-9"}) {
    EXPECT_NE(md.find(s), std::string::npos) << s << "\n" << md;
  }
  r.undetermined.clear();
  WriteParamsMarkdown((dir_ / "b.md").string(), r, "t");
  EXPECT_NE(ReadText(dir_ / "b.md").find("## Not determined by the data\n\nnone\n"),
            std::string::npos);
}

TEST(ReportTablesTest, ParameterTable) {
  const std::string table = FormatParameterTable(MakeResult());
  std::cout << table;
  std::istringstream in(table);
  std::string header, rule, vl, kt, ml;
  std::getline(in, header);
  std::getline(in, rule);
  std::getline(in, vl);
  std::getline(in, kt);
  std::getline(in, ml);
  for (const char* column :
       {"name", "unit", "value", "std error", "95 % interval", "initial",
        "free/fixed"}) {
    EXPECT_NE(header.find(column), std::string::npos) << column;
  }
  EXPECT_EQ(vl.rfind("V_L", 0), 0u);
  EXPECT_NE(vl.find("[0.1194, 0.1274]"), std::string::npos) << vl;
  EXPECT_EQ(kt.rfind("K_t", 0), 0u);
  EXPECT_NE(kt.find("free (not determined by the data)"), std::string::npos);
  EXPECT_EQ(ml.rfind("m_L", 0), 0u);
  EXPECT_NE(ml.find("fixed"), std::string::npos);
  EXPECT_EQ(vl.find("(not determined"), std::string::npos);
  // Fixed width: the value column ends at the same place in every row.
  EXPECT_EQ(header.find("value") + 5, vl.find("0.1234") + 6);
}

TEST(ReportTablesTest, FitTable) {
  const std::string table = FormatFitTable(MakeResult());
  std::cout << table;
  EXPECT_NE(table.find("step 1"), std::string::npos);
  EXPECT_NE(table.find("validate"), std::string::npos);
  EXPECT_NE(table.find("m/s^2"), std::string::npos);
  EXPECT_NE(table.find("0.0025 (20)"), std::string::npos);
  EXPECT_NE(table.find("-0.31"), std::string::npos);
  // Header, rule, one row per channel.
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 2 + 3);
}

TEST(ReportTablesTest, FileStemsAreSafeAndUnique) {
  FitResult r;
  r.experiments.resize(4);
  r.experiments[0].name = "step 1";
  r.experiments[1].name = "step/1";
  r.experiments[2].name = "";
  r.experiments[3].name = "a.b-c_D";
  EXPECT_EQ(ExperimentFileStems(r),
            (std::vector<std::string>{"fit_step_1", "fit_step_1_2",
                                      "fit_experiment3", "fit_a.b-c_D"}));
}

}  // namespace
}  // namespace axis
