// report.html (report/html_report.h) and the progress line (common/progress.h):
// the page from a hand-built result (escaping, plots, ids, thinning, a
// missing gnuplot), and short fits of the paper and EMPS jobs written by
// fit-params and checked in headless Chromium (tests/browser_checks.h).
// The whole jobs are in tests/html_report_jobs_test.cc (slow).
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "common/progress.h"
#include "estimation/fit_result.h"
#include "report/html_report.h"
#include "tests/browser_checks.h"
#include "tests/fit_result_fixture.h"
#include "tests/test_files.h"

namespace axis {
namespace {

namespace fs = std::filesystem;
using browser_checks::Count;

const std::string kRoot = PROJECT_SOURCE_DIR;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool HaveGnuplot() { return std::system("command -v gnuplot >/dev/null 2>&1") == 0; }

// The fixture's result with names from a job and a data file that try to
// be markup; the fitted experiment has `samples` samples.
FitResult HostileResult(int samples) {
  FitResult r = fixture::MakeResult(samples);
  r.experiments[0].name = "step<script>alert(1)</script>";
  r.experiments[1].name = "move \"1 m\" & back";
  return r;
}

class HtmlReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing_files::TestTempDir() + "page";
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  std::string dir_;
};

TEST(HtmlEscapeTest, EscapesMarkupAndRepairsBadUtf8) {
  EXPECT_EQ(HtmlEscape("a<b>&\"c\"'d'"), "a&lt;b&gt;&amp;&quot;c&quot;&#39;d&#39;");
  EXPECT_EQ(HtmlEscape("σ = 0.1 N·s/m ±"), "σ = 0.1 N·s/m ±");
  EXPECT_EQ(HtmlEscape(std::string("x\xff" "y")), "x\xEF\xBF\xBDy");
  EXPECT_EQ(HtmlEscape(std::string("\xC3")), "\xEF\xBF\xBD");          // truncated
  EXPECT_EQ(HtmlEscape(std::string("\xC0\xAF")), "\xEF\xBF\xBD\xEF\xBF\xBD");  // overlong
  EXPECT_EQ(HtmlEscape(std::string("a\x01" "b\tc\n")), "a\xEF\xBF\xBD" "b\tc\n");
}

// Every text from the job or the data is escaped; the page loads nothing;
// the plots' ids are unique on the page.
TEST_F(HtmlReportTest, EscapesEveryTextAndKeepsIdsUnique) {
  const FitResult result = HostileResult(300);
  HtmlReportInput input;
  input.title = "<b>X axis</b> & \"friends\"";
  input.result = &result;
  input.input_notes = {"e: <img src=x onerror=alert(2)> held"};
  std::vector<std::string> warnings;
  const std::string page = RenderHtmlReport(input, dir_, &warnings);
  EXPECT_EQ(page.find("<script>alert"), std::string::npos);
  EXPECT_EQ(page.find("<img"), std::string::npos);
  EXPECT_EQ(page.find("<b>X axis"), std::string::npos);
  EXPECT_NE(page.find("&lt;b&gt;X axis&lt;/b&gt; &amp; &quot;friends&quot;"), std::string::npos);
  EXPECT_NE(page.find("step&lt;script&gt;alert(1)&lt;/script&gt;"), std::string::npos);
  EXPECT_EQ(Count(page, "<script>"), 1u);  // the sorting script
  // ("src=" is there, as text of the escaped note.)
  for (const char* outside : {"http:", "https:", "@import", "<link"}) {
    EXPECT_EQ(page.find(outside), std::string::npos) << outside;
  }
  EXPECT_NE(page.find("<section id=\"validation\">"), std::string::npos);
  EXPECT_EQ(page.find("<section id=\"discovery\">"), std::string::npos);  // no loop ran
  // The scratch files are gone.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 0);
  if (!HaveGnuplot()) GTEST_SKIP() << "gnuplot is not installed: no plots to check";
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(static_cast<int>(Count(page, "<svg")), HtmlReportPlotCount(input));
  EXPECT_EQ(HtmlReportPlotCount(input), 2);
  std::set<std::string> ids;
  for (size_t at = page.find(" id="); at != std::string::npos; at = page.find(" id=", at + 1)) {
    const char quote = page[at + 4];
    const size_t end = page.find(quote, at + 5);
    const std::string id = page.substr(at + 5, end - at - 5);
    EXPECT_TRUE(ids.insert(id).second) << "id '" << id << "' twice";
  }
}

// A long record is thinned for the plot (the extremes kept), so that the
// page stays small; the caption says so.
TEST_F(HtmlReportTest, LongTracesAreThinned) {
  if (!HaveGnuplot()) GTEST_SKIP() << "gnuplot is not installed";
  FitResult result = HostileResult(50000);
  result.experiments.resize(1);
  result.experiments[0].channels[0].measured[31234] = 40.0;  // a spike
  HtmlReportInput input;
  input.result = &result;
  std::vector<std::string> warnings;
  const std::string page = RenderHtmlReport(input, dir_, &warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_LT(page.size(), 600000u);
  EXPECT_NE(page.find(" of 50000 samples drawn"), std::string::npos);
  // The spike sets the y range of the measured panel: gnuplot labels 40.
  EXPECT_NE(page.find("<text> 40</text>"), std::string::npos) << "spike lost";
}

TEST_F(HtmlReportTest, WithoutGnuplotThePlotsAreNotes) {
  const FitResult result = HostileResult(100);
  HtmlReportInput input;
  input.result = &result;
  const char* old_path = std::getenv("PATH");
  const std::string saved = old_path != nullptr ? old_path : "";
  ::setenv("PATH", dir_.c_str(), 1);
  std::vector<std::string> warnings;
  const std::string page = RenderHtmlReport(input, dir_, &warnings);
  ::setenv("PATH", saved.c_str(), 1);
  EXPECT_EQ(Count(page, "<svg"), 0u);
  EXPECT_EQ(Count(page, "<figure class=\"missing\">"), 2u);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("gnuplot not found"), std::string::npos) << warnings[0];
}

// The frequency response section: its table, the note of a record
// without a band (escaped), one Bode plot per experiment and channel.
TEST_F(HtmlReportTest, FrequencyResponseHasABodePlotPerChannel) {
  const FitResult result = HostileResult(100);
  std::vector<ExperimentFrequencyResponse> fr(2);
  fr[0].experiment = "chirp <1>";
  fr[0].input = "U";
  fr[0].input_unit = "V";
  fr[0].band.band = true;
  fr[0].band.f_low = 1.0;
  fr[0].band.f_high = 100.0;
  fr[0].averages = 9;
  fr[0].linear.blocker = "a closed loop (the sampled controller is not linearised)";
  ChannelFrequencyResponse c;
  c.channel = "v";
  c.unit = "m/s";
  for (int k = 1; k <= 50; ++k) {
    c.frequency.push_back(2.0 * k);
    c.data.push_back({1.0 / k, -0.1 * k});
    c.model.push_back({1.1 / k, -0.1 * k});
    c.data_coherence.push_back(0.9);
    c.model_coherence.push_back(1.0);
  }
  fr[0].channels = {c, c};
  fr[0].channels[1].channel = "a";
  fr[1].experiment = "square & wave";
  fr[1].input = "U";
  fr[1].note = "U: no band: the longest run of bins within 20 dB of the input's peak is 3 bins";
  HtmlReportInput input;
  input.result = &result;
  input.frequency_response = &fr;
  EXPECT_EQ(HtmlReportPlotCount(input), 4);  // two experiments, two channels
  std::vector<std::string> warnings;
  const std::string page = RenderHtmlReport(input, dir_, &warnings);
  EXPECT_NE(page.find("<section id=\"frequency-response\">"), std::string::npos);
  EXPECT_NE(page.find("square &amp; wave: U: no band"), std::string::npos);
  EXPECT_NE(page.find("chirp &lt;1&gt;: U to a"), std::string::npos);
  if (!HaveGnuplot()) GTEST_SKIP() << "gnuplot is not installed: no plots to check";
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(static_cast<int>(Count(page, "<svg")), HtmlReportPlotCount(input));
}

TEST(HtmlReportInputTest, ResultIsRequired) {
  HtmlReportInput input;
  try {
    RenderHtmlReport(input, ".", nullptr);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("expected a fit result, got none"), std::string::npos);
  }
}

// ---------------------------------------------------------------- progress

TEST(ProgressTest, FormatDuration) {
  EXPECT_EQ(FormatDuration(0.4), "0 s");
  EXPECT_EQ(FormatDuration(59.4), "59 s");
  EXPECT_EQ(FormatDuration(65), "1 min 05 s");
  EXPECT_EQ(FormatDuration(3725), "1 h 02 min");
  EXPECT_EQ(FormatDuration(-3), "0 s");
  EXPECT_EQ(FormatDuration(kNaN), "0 s");
}

// Not a terminal: one plain line per status, other text unchanged, no
// carriage return, the iteration detail left out.
TEST(ProgressTest, PlainLinesOutsideATerminal) {
  std::ostringstream sink;
  {
    ProgressStream out(sink, 0);
    EXPECT_FALSE(out.terminal());
    out << "fit-params: job\n";
    out.BeginPhase("starts");
    out.Status("fit: start 1 of 2, horizon 0.050 s (stage 1 of 3)", 0.0);
    out.Detail("iter 3, cost 12");
    out << "start  0  horizon 0.050 s  iter   3\n";
  }
  EXPECT_EQ(sink.str(),
            "fit-params: job\n"
            "progress: 0 s elapsed; fit: start 1 of 2, horizon 0.050 s (stage 1 of 3)\n"
            "start  0  horizon 0.050 s  iter   3\n");
}

// A terminal: the status is one line redrawn in place, erased before other
// text and at the end, and never wider than the terminal.
TEST(ProgressTest, OneUpdatingLineOnATerminal) {
  std::ostringstream sink;
  {
    ProgressStream out(sink, 40);
    EXPECT_TRUE(out.terminal());
    out.Status("fit: start 1 of 2, horizon 0.050 s (stage 1 of 3)", 0.0);
    out << "a table\n";
    out.Status("fit: optimum check", kNaN);
  }
  const std::string text = sink.str();
  const std::string erase = "\r\033[K";
  EXPECT_EQ(text.rfind(erase, 0), 0u) << "starts by drawing the status line";
  const size_t table = text.find("a table\n");
  ASSERT_NE(table, std::string::npos);
  EXPECT_EQ(text.substr(table - erase.size(), erase.size()), erase) << "status erased first";
  EXPECT_NE(text.find(erase + "0 s elapsed; fit: optimum check"), std::string::npos);
  EXPECT_EQ(text.substr(text.size() - erase.size()), erase) << "erased at the end";
  // Each drawn line is cut to 39 columns.
  for (size_t at = text.find(erase); at != std::string::npos; at = text.find(erase, at + 1)) {
    const size_t next = std::min(text.find('\r', at + 1), text.find('\n', at + 1));
    const std::string line = text.substr(at + erase.size(), next - at - erase.size());
    EXPECT_LE(line.size(), 39u) << line;
  }
}

// A remaining time only with a basis: a part of the phase done and at
// least a second spent in it; then marked "~" as the extrapolation it is.
TEST(ProgressTest, RemainingTimeOnlyWithABasis) {
  std::ostringstream sink;
  ProgressStream out(sink, 0);
  out.BeginPhase("starts");
  out.Status("nothing done", 0.0);
  out.Status("unknown share", kNaN);
  out.Status("half done but too soon", 0.5);
  EXPECT_EQ(sink.str().find("left"), std::string::npos) << sink.str();
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  out.Status("half done", 0.5);
  EXPECT_NE(sink.str().find("half done; starts ~"), std::string::npos) << sink.str();
  EXPECT_NE(sink.str().find(" left\n"), std::string::npos) << sink.str();
}

TEST(ProgressTest, FoundBehindAnOstreamPointer) {
  std::ostringstream sink;
  ProgressStream out(sink, 0);
  std::ostream* as_ostream = &out;
  EXPECT_EQ(AsProgressStream(as_ostream), &out);
  EXPECT_EQ(AsProgressStream(&sink), nullptr);
  EXPECT_EQ(AsProgressStream(nullptr), nullptr);
}

// ---------------------------------------------------------------- fit-params

// A job of configs/jobs/ (`name`) with its relative paths made absolute
// (the test writes it elsewhere) and `insert` added after every line that
// ends in `after`.
std::string JobFile(const std::string& name, const std::string& after,
                    const std::string& insert) {
  std::string job = browser_checks::ReadFile(kRoot + "/configs/jobs/" + name);
  const std::string dir = kRoot + "/configs/jobs/";
  for (const char* relative : {"../axes/", "../../testdata/"}) {
    for (size_t at = job.find(relative); at != std::string::npos;
         at = job.find(relative, at + dir.size() + 1)) {
      job.insert(at, dir);
    }
  }
  for (size_t at = job.find(after + "\n"); at != std::string::npos;
       at = job.find(after + "\n", at + 1)) {
    job.insert(at + after.size() + 1, insert);
  }
  return job;
}

// Writes `job` as <name>.yaml and runs fit-params on it into the folder
// <name> of the test's temporary folder (emptied first); returns the
// folder, the output in *log, and fails the test unless it exits 0.
std::string RunJobText(const std::string& name, const std::string& job, std::string* log) {
  const std::string out = testing_files::TestTempDir() + name;
  fs::remove_all(out);
  const std::string path = testing_files::WriteTemp(name + ".yaml", job);
  EXPECT_EQ(browser_checks::RunFitParamsCli(path, out, log), 0) << *log;
  return out;
}

// The paper job (configs/jobs/x_axis_paper.yaml) on the first 0.3 s of its
// two steps, its validation move whole, one probe round and Gauss–Newton
// intervals (a third of the time of the full check and profile):
// report.html in the output folder, checked in Chromium. Piped output:
// plain progress lines.
TEST(FitParamsHtmlTest, PaperJobShortWindowInChromium) {
  std::string job = JobFile("x_axis_paper.yaml", "V.csv", "    window: [0, 0.3]\n");
  ASSERT_EQ(browser_checks::Count(job, "window: [0, 0.3]"), 2u) << job;
  const size_t solver = job.find("  starts: 0\n");
  ASSERT_NE(solver, std::string::npos);
  job.insert(solver, "  probe_rounds: 1\n  local_starts: 0\n");
  job += "uncertainty: {method: gauss_newton}\n";
  std::string log;
  const std::string out = RunJobText("paper_short", job, &log);
  EXPECT_NE(log.find("progress: 0 s elapsed; fit: start 1 of 1, horizon 0.050 s (stage 1 of "),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("fit: optimum check, probe round 1 (at most 1)"), std::string::npos);
  EXPECT_EQ(log.find('\r'), std::string::npos) << "carriage return in piped output";
  EXPECT_NE(log.find("wrote " + out + "/{report.html, "), std::string::npos);
  browser_checks::CheckInBrowser(out, {"summary", "data", "parameters", "correlation",
                                       "experiments", "validation", "diagnostics", "solver"});
}

// The EMPS job (configs/jobs/emps.yaml: closed loop, real data, the
// published reference) on the first 4 s of each record, one discovery
// step: the discovery, verdict and published sections; a title that tries
// to be markup.
TEST(FitParamsHtmlTest, EmpsShortWindowWithDiscoveryInChromium) {
  std::string job = JobFile("emps.yaml", ".csv", "    window: [0, 4]\n");
  ASSERT_EQ(browser_checks::Count(job, "window: [0, 4]"), 3u) << job;
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"max_effects: 5",
                                                                     "max_effects: 1\n  tries: 1"},
                                 {"title: \"EMPS: M", "title: \"EMPS <short> & M"}}) {
    const size_t at = job.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    job.replace(at, from.size(), to);
  }
  std::string log;
  const std::string out = RunJobText("emps_short", job, &log);
  EXPECT_NE(log.find("discovery step 1 (at most 1): score tests of "), std::string::npos) << log;
  EXPECT_NE(log.find("discovery step 1 (at most 1): "), std::string::npos) << log;
  const std::string page = browser_checks::ReadFile(out + "/report.html");
  EXPECT_NE(page.find("<h1>EMPS &lt;short&gt; &amp; M and B_a"), std::string::npos);
  browser_checks::CheckInBrowser(out, {"summary", "data", "parameters", "correlation",
                                       "experiments", "validation", "diagnostics", "discovery",
                                       "published", "solver"});
}

}  // namespace
}  // namespace axis
