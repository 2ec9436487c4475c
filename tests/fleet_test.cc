// fit-fleet (issue 12), the quick part: the manifest loader and its errors,
// the fleet table's JSON and its comparison with a baseline on rows made up
// here, fleet.html's escaping, and one small fleet run on two MPI ranks in
// which two jobs are broken (a malformed data file, a missing job file):
// they are reported and the others complete; its fleet.html in Chromium.
// The whole synthetic fleet on one and two ranks is tests/fleet_run_test.cc
// (slow).
#include <cmath>
#include <filesystem>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "fleet/internal/fleet_html.h"
#include "fleet/fleet_table.h"
#include "fleet/write_fleet_table.h"
#include "fleet/manifest.h"
#include "run/fit_job.h"
#include "io/yaml_util.h"
#include "tests/fleet_checks.h"
#include "tests/test_files.h"

namespace axis {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

const std::string kSource = PROJECT_SOURCE_DIR;
const std::string kFleet = kSource + "/configs/fleet";
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The manifest `text` written to the test's folder, loaded; the error
// message if it throws std::invalid_argument, else "".
std::string ManifestError(const std::string& text) {
  const std::string path = testing_files::WriteTemp("manifest.yaml", text);
  try {
    LoadFleetManifest(path);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// A manifest of the fleet's template and r01's model, with `axes` lines.
std::string WithTemplate(const std::string& rest) {
  return "template: " + kFleet + "/fleet_job.yaml\n" + rest;
}

std::string Axis(const std::string& axis, const std::string& data) {
  return "  - {axis: " + axis + ", model: " + kFleet + "/axes/r01_x.yaml, data: " + data + "}\n";
}

TEST(FleetManifestTest, LoadsTheSyntheticFleet) {
  const FleetManifest m = LoadFleetManifest(kFleet + "/now.yaml");
  EXPECT_EQ(m.title, "Synthetic fleet, now");
  ASSERT_EQ(m.entries.size(), 8u);
  EXPECT_EQ(m.entries[2].axis, "r03/x");
  EXPECT_EQ(m.entries[2].log, "now");
  EXPECT_EQ(m.entries[2].Folder(), "r03/x/now");
  EXPECT_TRUE(m.entries[2].job_path.empty());
  EXPECT_THAT(m.entries[2].model_path, HasSubstr("axes/r03_x.yaml"));
  EXPECT_THAT(m.entries[2].data_path, HasSubstr("testdata/fleet/r03_x/now.csv"));
  EXPECT_GT(m.entries[2].expected_cost, 0.0);
  EXPECT_THAT(m.out_dir, HasSubstr("build/fleet/now"));
  EXPECT_EQ(m.threads, 1);
  EXPECT_FALSE(m.discover);
  EXPECT_EQ(m.alpha, 0.05);
}

TEST(FleetManifestTest, GlobListsEveryLogOfAnAxisSorted) {
  const std::string path = testing_files::WriteTemp(
      "manifest.yaml", WithTemplate("axes:\n" + Axis("r01/x", kSource + "/testdata/fleet/r01_x/*.csv") +
                                    "jobs:\n  - {axis: paper/x, job: " + kSource +
                                    "/configs/jobs/x_axis_paper.yaml}\nthreads: 2\n"));
  const FleetManifest m = LoadFleetManifest(path);
  ASSERT_EQ(m.entries.size(), 3u);
  EXPECT_EQ(m.entries[0].log, "last_month");
  EXPECT_EQ(m.entries[1].log, "now");
  EXPECT_EQ(m.entries[2].axis, "paper/x");
  EXPECT_EQ(m.entries[2].log, "x_axis_paper");  // the job file's stem
  EXPECT_GT(m.entries[2].expected_cost, 0.0);
  EXPECT_EQ(m.threads, 2);

  // The job of an entry: the template filled in, one thread, the folder.
  const FitJob job = MakeFleetJob(m, m.entries[1], "/tmp/out");
  EXPECT_EQ(job.title, "r01/x now: fleet axis: B_a, F_c, F_0 from a 2 Hz sine");
  EXPECT_EQ(job.problem.solver.threads, 2);
  EXPECT_FALSE(job.problem.solver.progress);
  EXPECT_EQ(job.out_dir, "/tmp/out/r01/x/now");
  ASSERT_EQ(job.problem.experiments.size(), 1u);
  EXPECT_THAT(job.problem.experiments[0].data_path, HasSubstr("r01_x/now.csv"));
  ASSERT_EQ(job.problem.free.size(), 3u);
  EXPECT_EQ(job.problem.free[1].name, "F_c");
  EXPECT_EQ(job.problem.free[1].initial, 20.0);  // r01's model value
}

TEST(FleetManifestTest, ErrorsNameFileLineAndKey) {
  const std::string data = kSource + "/testdata/fleet/r01_x/now.csv";
  EXPECT_THAT(ManifestError(WithTemplate("axes:\n" + Axis("r01/x", data) + "colour: red\n")),
              HasSubstr("manifest.yaml:4: key 'colour': expected one of the known keys"));
  EXPECT_THAT(ManifestError(WithTemplate("axes:\n" + Axis("r01/x", data) + "threads: 1\nthreads: 2\n")),
              HasSubstr("expected each key once in a mapping, got 'threads' again (first on line 4)"));
  EXPECT_THAT(ManifestError(WithTemplate("axes:\n" + Axis("r01//x", data))),
              HasSubstr("manifest.yaml:3: key 'axes[0].axis': expected an axis name"));
  EXPECT_THAT(ManifestError(WithTemplate("axes:\n" + Axis("../x", data))),
              HasSubstr("expected an axis name"));
  EXPECT_THAT(ManifestError(WithTemplate("axes:\n" + Axis("r01/x", data) + Axis("r01/x", data))),
              HasSubstr("manifest.yaml:4: key 'axes/jobs': expected each axis and log once (one "
                        "output folder each), got axis 'r01/x' log 'now' again (first on line 3)"));
  EXPECT_THAT(ManifestError(WithTemplate("axes:\n" + Axis("r01/x", kSource + "/testdata/fleet/r01_x/*.mat"))),
              HasSubstr("key 'axes[0].data': expected a glob pattern matching at least one file"));
  EXPECT_THAT(ManifestError("axes:\n" + Axis("r01/x", data)),
              HasSubstr("key 'axes': expected a 'template' key beside 'axes'"));
  EXPECT_THAT(ManifestError("title: nothing\n"), HasSubstr("expected at least one job"));
  EXPECT_THAT(ManifestError(WithTemplate("axes:\n" + Axis("r01/x", data) + "threads: 0\n")),
              HasSubstr("key 'threads'"));
  EXPECT_THAT(ManifestError(WithTemplate("axes:\n" + Axis("r01/x", data) + "alpha: 1\n")),
              HasSubstr("key 'alpha': expected a level in (0, 1), got '1'"));
  EXPECT_THAT(ManifestError(WithTemplate("axes:\n" + Axis("r01/x", data) + "discover: yes\n")),
              HasSubstr("key 'discover': expected true or false, got 'yes'"));
  EXPECT_THAT(ManifestError("jobs:\n  - {axis: a, job: x.yaml, jobb: x.yaml}\n"),
              HasSubstr("key 'jobs[0].jobb': expected one of the known keys"));
  EXPECT_THAT(ManifestError("jobs:\n  - {axis: a, job: x.yaml, log: 'a b'}\n"),
              HasSubstr("key 'jobs[0].log': expected a log name"));
  EXPECT_THAT(ManifestError("template: missing.yaml\naxes:\n" + Axis("r01/x", data)),
              HasSubstr("missing.yaml: cannot read"));
  try {
    LoadFleetManifest(testing_files::TestTempDir() + "nowhere.yaml");
    ADD_FAILURE() << "no error for a missing manifest";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("nowhere.yaml: cannot read"));
  }
}

// An empty output.dir meant the manifest's own folder (--out "" is
// refused); a second document was ignored and a merge key not applied
// (issue 46): each refused naming the file, line and key.
TEST(FleetManifestTest, EmptyOutputDirSecondDocumentAndMergeKeyAreRefused) {
  const std::string data = kSource + "/testdata/fleet/r01_x/now.csv";
  const std::string manifest = WithTemplate("axes:\n" + Axis("r01/x", data));
  EXPECT_EQ(ManifestError(manifest + "output: {dir: out}\n"), "");
  EXPECT_THAT(ManifestError(manifest + "output: {dir: ''}\n"),
              HasSubstr("manifest.yaml:4: key 'output.dir': expected a folder path (relative to "
                        "the file's folder, or absolute), got ''"));
  EXPECT_THAT(ManifestError(manifest + "---\noutput: {dir: out}\n"),
              HasSubstr("manifest.yaml:4: expected one YAML document, got a second one"));
  EXPECT_THAT(ManifestError("common: &c {model: " + kFleet + "/axes/r01_x.yaml}\n" +
                            WithTemplate("axes:\n  - <<: *c\n    axis: r01/x\n    data: " +
                                         data + "\n")),
              HasSubstr("manifest.yaml:4: key 'axes[0].<<': expected no YAML merge key"));
}

TEST(FleetManifestTest, TemplateMustLeaveModelDataAndOutputToTheManifest) {
  const std::string data = kSource + "/testdata/fleet/r01_x/now.csv";
  const auto template_error = [&data](const std::string& text) {
    const std::string t = testing_files::WriteTemp("template.yaml", text);
    return ManifestError("template: " + t + "\naxes:\n" + Axis("r01/x", data));
  };
  const std::string experiment =
      "experiments:\n  - {name: s, channels: {u: u, a: a}, input: {column: u}, fit: {a: 0.02}}\n";
  const std::string free = "free:\n  B_a: {lower: 10, upper: 2000}\n";
  EXPECT_EQ(template_error(free + experiment), "");
  EXPECT_THAT(template_error("model: m.yaml\n" + free + experiment),
              HasSubstr("template.yaml:1: key 'model': expected no 'model' in a job template"));
  EXPECT_THAT(template_error(free + experiment + "output: {dir: x}\n"),
              HasSubstr("key 'output': expected no 'output' in a job template"));
  EXPECT_THAT(template_error(free + "experiments:\n  - {name: s, data: d.csv}\n"),
              HasSubstr("key 'experiments[0].data': expected no 'data' in a job template"));
  EXPECT_THAT(template_error(free + "experiments: []\n"),
              HasSubstr("key 'experiments': expected exactly one experiment entry"));
}

TEST(FleetManifestTest, ABrokenDataFileFailsOnlyWhenItsJobIsMade) {
  const std::string bad = testing_files::WriteTemp("bad.csv", "t,u,a,tach,i\n0,1,2,3\n");
  const std::string path = testing_files::WriteTemp("manifest.yaml",
                                                    WithTemplate("axes:\n" + Axis("r01/x", bad)));
  const FleetManifest m = LoadFleetManifest(path);  // the manifest itself is fine
  try {
    MakeFleetJob(m, m.entries[0], testing_files::TestTempDir() + "out");
    ADD_FAILURE() << "no error for a malformed data file";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("bad.csv:2"));
  }
}

// A template whose experiment has a key no job has fails each job with the
// template's file and line (its copy per job kept the line marks; it said
// ":1:").
TEST(FleetManifestTest, ATemplateErrorNamesItsLine) {
  const std::string t = testing_files::WriteTemp("typo_template.yaml",
      "free:\n"
      "  B_a: {lower: 10, upper: 2000}\n"
      "experiments:\n"
      "  - name: s\n"
      "    channels: {u: u, a: a}\n"
      "    input: {column: u}\n"
      "    typo_key: 3\n"
      "    fit: {a: 0.02}\n");
  const std::string path = testing_files::WriteTemp(
      "manifest.yaml", "template: " + t + "\naxes:\n" +
                           Axis("r01/x", kSource + "/testdata/fleet/r01_x/now.csv"));
  const FleetManifest m = LoadFleetManifest(path);
  try {
    MakeFleetJob(m, m.entries[0], testing_files::TestTempDir() + "out");
    ADD_FAILURE() << "no error for an unknown key";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("typo_template.yaml:7:"));
    EXPECT_THAT(e.what(), HasSubstr("typo_key"));
  }
}

// A row of a made-up fleet.
FleetRow Row(const std::string& axis, const std::string& log, double F_c, double F_c_se,
             double B_a = 200.0) {
  FleetRow r;
  r.axis = axis;
  r.log = log;
  r.job = "job.yaml";
  r.folder = axis + "/" + log;
  r.status = "ok";
  r.parameters = {{"F_c", "N", F_c, F_c_se, F_c - 2 * F_c_se, F_c + 2 * F_c_se, true},
                  {"B_a", "N*s/m", B_a, 0.3, B_a - 0.6, B_a + 0.6, true}};
  r.effects = {"coulomb"};
  r.verdict = "explained";
  r.s2 = 1.01;
  r.fits = {{"sine", "a", true, 99.2}};
  r.seconds = 1.25;
  return r;
}

TEST(FleetTableTest, RowJsonRoundTripsExactly) {
  FleetRow r = Row("r01/x", "now", 20.123456789012345, 0.0371);
  r.parameters[1].std_error = kNaN;
  r.s2 = kNaN;
  r.remains = {"sine/a: not white"};
  r.discovery = true;
  r.discovered = {"stribeck"};
  r.rank = 3;
  const FleetRow back = FleetRowFromJson(nlohmann::json::parse(FleetRowToJson(r).dump()), "row");
  EXPECT_EQ(FleetRowToJson(back).dump(), FleetRowToJson(r).dump());
  EXPECT_EQ(back.parameters[0].value, r.parameters[0].value);
  EXPECT_TRUE(std::isnan(back.parameters[1].std_error));
  EXPECT_TRUE(std::isnan(back.s2));
  EXPECT_EQ(back.rank, 3);

  nlohmann::json broken = nlohmann::json::parse(FleetRowToJson(r).dump());
  broken["status"] = "fine";
  EXPECT_THROW(FleetRowFromJson(broken, "row"), std::invalid_argument);
  broken = nlohmann::json::parse(FleetRowToJson(r).dump());
  broken["parameters"][0]["value"] = "1";
  try {
    FleetRowFromJson(broken, "f.json: rows[0]");
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("f.json: rows[0].parameters[0].value: expected a number or "
                                    "null, got \"1\""));
  }
}

TEST(FleetTableTest, ComparisonFlagsOnlyWhatChangedBeyondBothUncertainties) {
  const std::vector<FleetRow> baseline = {Row("a/x", "may", 20.0, 0.04), Row("b/x", "may", 25.0, 0.04),
                                          Row("c/x", "may", 22.0, 0.5), Row("d/x", "may", 18.0, 0.04)};
  std::vector<FleetRow> now = {Row("a/x", "june", 20.1, 0.04),   // z = 1.8: noise
                               Row("b/x", "june", 40.0, 0.04),   // z = 265: grown friction
                               Row("c/x", "june", 23.0, 0.5),    // z = 1.4
                               Row("d/x", "june", 18.0, 0.04, 210.0),  // B_a z = 23.6
                               Row("e/x", "june", 10.0, 0.1)};   // no baseline
  now[2].effects.push_back("load_offset");
  const FleetComparison c = CompareFleets(now, baseline, 0.05, "old/fleet.json");
  EXPECT_EQ(c.tests, 8);  // two parameters of four compared rows
  ASSERT_EQ(c.changes.size(), 3u);
  // The effect first, then by |z|.
  EXPECT_EQ(c.changes[0].kind, "effect appeared");
  EXPECT_EQ(c.changes[0].axis, "c/x");
  EXPECT_EQ(c.changes[0].text, "axis c/x (june): effect load_offset appeared");
  EXPECT_EQ(c.changes[1].axis, "b/x");
  EXPECT_EQ(c.changes[1].name, "F_c");
  EXPECT_EQ(c.changes[1].baseline_log, "may");
  EXPECT_NEAR(c.changes[1].z, 15.0 / std::sqrt(2 * 0.04 * 0.04), 1e-9);
  EXPECT_EQ(c.changes[1].text, "axis b/x (june): F_c 40 ± 0.04 N, was 25 ± 0.04 N (+60 %), z = 265");
  EXPECT_EQ(c.changes[2].axis, "d/x");
  EXPECT_EQ(c.changes[2].name, "B_a");
  ASSERT_EQ(c.not_compared.size(), 1u);
  EXPECT_EQ(c.not_compared[0], "e/x (june): no baseline row");

  // A failed row is not compared; the effect disappears the other way round.
  now[0].status = "failed";
  const FleetComparison back = CompareFleets(baseline, now, 0.05, "x");
  EXPECT_THAT(back.not_compared, ::testing::Contains("a/x (may): baseline row (june) failed"));
  EXPECT_EQ(back.changes[0].kind, "effect disappeared");
  EXPECT_THROW(CompareFleets(now, baseline, 0.0, "x"), std::invalid_argument);
  EXPECT_THROW(CompareFleets(now, baseline, 1.0, "x"), std::invalid_argument);
}

TEST(FleetTableTest, SameLogIsPreferredOverTheAxisLastRow) {
  const std::vector<FleetRow> baseline = {Row("a/x", "may", 20.0, 0.04), Row("a/x", "june", 30.0, 0.04)};
  const std::vector<FleetRow> now = {Row("a/x", "may", 20.0, 0.04)};
  EXPECT_TRUE(CompareFleets(now, baseline, 0.05, "x").changes.empty());
  const std::vector<FleetRow> july = {Row("a/x", "july", 20.0, 0.04)};
  const FleetComparison c = CompareFleets(july, baseline, 0.05, "x");
  ASSERT_EQ(c.changes.size(), 1u);
  EXPECT_EQ(c.changes[0].baseline_log, "june");  // the axis's last row
}

TEST(FleetTableTest, HtmlEscapesEveryText) {
  FleetTable t;
  t.title = "<b>fleet</b>";
  t.manifest = "m&m.yaml";
  t.rows = {Row("a/x", "may", 20.0, 0.04)};
  FleetRow failed = Row("b/x", "may", 20.0, 0.04);
  failed.status = "failed";
  failed.error = "x.csv:3: expected a number, got '<script>'";
  failed.parameters.clear();
  t.rows.push_back(failed);
  const std::string html = RenderFleetHtml(t);
  EXPECT_EQ(html.find("<b>fleet"), std::string::npos);
  EXPECT_NE(html.find("&lt;b&gt;fleet&lt;/b&gt;"), std::string::npos);
  EXPECT_EQ(html.find("<script>'"), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;"), std::string::npos);
  EXPECT_NE(html.find("<section id=\"failed\">"), std::string::npos);
  EXPECT_EQ(html.find("<section id=\"changes\">"), std::string::npos);  // no baseline
  EXPECT_NE(html.find("<a href=\"a/x/may/report.html\">a/x</a>"), std::string::npos);
  EXPECT_EQ(html.find("b/x/may/report.html"), std::string::npos);  // failed: no report
}

TEST(FleetTableTest, WritesEveryFileEvenWithBadUtf8InAnError) {
  FleetTable t;
  t.title = "fleet";
  t.manifest = "m.yaml";
  t.rows = {Row("a/x", "may", 20.0, 0.04), Row("b/x", "may", 20.0, 0.04)};
  t.rows[1].status = "failed";
  t.rows[1].error = "d.csv:2: expected a number, got '\xff\xfe'";  // bytes of a data file
  t.rows[1].parameters.clear();
  const std::string dir = testing_files::TestTempDir() + "out";
  WriteFleetTable(dir, t);
  const nlohmann::json j = fleet_checks::ReadJson(dir + "/fleet.json");
  EXPECT_THAT(j["rows"][1]["error"].get<std::string>(), HasSubstr("\xEF\xBF\xBD"));  // U+FFFD
  EXPECT_EQ(FleetRowFromJson(j["rows"][0], "row").parameters[0].value, 20.0);
  for (const char* file : {"fleet.csv", "fleet.md", "fleet.html"}) {
    EXPECT_TRUE(fs::exists(dir + "/" + file)) << file;
  }
  // Only the table's files, no temporary left beside them.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 4);
}

// Two good jobs, a malformed data file and a missing job file, on two
// ranks: the broken two are reported with their errors, the others
// complete with their own folders, and the table is written.
TEST(FleetRunTest, BrokenJobsAreReportedAndTheRestComplete) {
  const std::string dir = testing_files::TestTempDir();
  const std::string bad = testing_files::WriteTemp("broken.csv", "t,u,a,tach,i\n0,0,0,0,0\n0.001,1,x,0,0\n");
  const std::string manifest = testing_files::WriteTemp(
      "manifest.yaml",
      "title: \"two good, two broken\"\n" +
          WithTemplate("axes:\n" + Axis("r01/x", kSource + "/testdata/fleet/r01_x/now.csv") +
                       Axis("r02/x", bad) +
                       "  - {axis: r04/x, model: " + kFleet + "/axes/r04_x.yaml, data: " + kSource +
                       "/testdata/fleet/r04_x/now.csv}\n"
                       "jobs:\n  - {axis: r09/x, job: " + dir + "no_such_job.yaml, log: now}\n"));
  const std::string out = dir + "out";
  std::string log;
  ASSERT_EQ(fleet_checks::RunFitFleet("'" + manifest + "' --out '" + out + "'", 2, dir + "run.log", &log), 0)
      << log;
  EXPECT_THAT(log, HasSubstr("[4/4]"));
  EXPECT_THAT(log, HasSubstr("4 jobs: 2 ok, 0 not converged, 2 failed"));
  const nlohmann::json table = fleet_checks::ReadJson(out + "/fleet.json");
  ASSERT_EQ(table["rows"].size(), 4u);
  EXPECT_EQ(table["ranks"], 2);
  const auto& rows = table["rows"];
  EXPECT_EQ(rows[0]["axis"], "r01/x");
  EXPECT_EQ(rows[0]["status"], "ok");
  EXPECT_EQ(rows[1]["status"], "failed");
  EXPECT_THAT(rows[1]["error"].get<std::string>(), HasSubstr("broken.csv:3"));
  EXPECT_EQ(rows[2]["status"], "ok");
  EXPECT_EQ(rows[3]["status"], "failed");
  EXPECT_THAT(rows[3]["error"].get<std::string>(), HasSubstr("no_such_job.yaml: cannot read"));
  for (int k : {0, 2}) {
    const std::string folder = out + "/" + rows[k]["folder"].get<std::string>();
    for (const char* file : {"report.html", "report.json", "params.md", "fit.log"}) {
      EXPECT_TRUE(fs::exists(folder + "/" + file)) << folder << "/" << file;
    }
    ASSERT_EQ(rows[k]["parameters"].size(), 3u);
    EXPECT_EQ(rows[k]["verdict"], "explained");
  }
  EXPECT_FALSE(fs::exists(out + "/r02/x/now"));
  for (const char* file : {"fleet.csv", "fleet.md", "fleet.html"}) {
    EXPECT_TRUE(fs::exists(out + "/" + file)) << file;
  }
  const std::string csv = browser_checks::ReadFile(out + "/fleet.csv");
  EXPECT_THAT(csv, HasSubstr("axis,log,status,verdict,s2,effects,discovered,B_a,B_a_se,F_c,F_c_se,"
                             "F_0,F_0_se,fit_sine/a,fit_sine/tach,seconds,rank,folder,error\n"));
  EXPECT_THAT(browser_checks::ReadFile(out + "/fleet.md"), HasSubstr("## Failed jobs"));
  fleet_checks::CheckFleetInBrowser(out, {"axes", "failed"});
}

TEST(FleetRunTest, BadManifestIsRefusedOnEveryRankWithExitCode2) {
  const std::string dir = testing_files::TestTempDir();
  const std::string manifest = testing_files::WriteTemp("manifest.yaml", "jobs: 3\n");
  std::string log;
  EXPECT_EQ(fleet_checks::RunFitFleet("'" + manifest + "' --out '" + dir + "out'", 2, dir + "run.log", &log), 2)
      << log;
  EXPECT_THAT(log, HasSubstr("fit-fleet: error: " + manifest + ":1: key 'jobs'"));
  // Rank 0 alone prints it.
  EXPECT_EQ(browser_checks::Count(log, "fit-fleet: error:"), 1u) << log;
  EXPECT_FALSE(fs::exists(dir + "out"));
  EXPECT_EQ(fleet_checks::RunFitFleet("'" + manifest + "' --baseline", 1, dir + "run1.log", &log), 2)
      << log;
  // A good manifest with an output path through a file, or a folder given
  // as the baseline: refused before any job (they were found after all the
  // jobs, exit 1, and with a message without the path).
  const std::string file = testing_files::WriteTemp("a_file", "x\n");
  EXPECT_EQ(fleet_checks::RunFitFleet(kFleet + "/now.yaml --out '" + file + "/out'", 1,
                                      dir + "run2.log", &log), 2)
      << log;
  EXPECT_THAT(log, HasSubstr(file + "/out: expected an output directory"));
  EXPECT_EQ(fleet_checks::RunFitFleet(kFleet + "/now.yaml --out '" + dir + "out' --baseline '" +
                                          dir + "'", 1, dir + "run3.log", &log), 2)
      << log;
  EXPECT_THAT(log, HasSubstr("expected a fleet.json file, got a directory"));
  EXPECT_FALSE(fs::exists(dir + "out"));
}

}  // namespace
}  // namespace axis
