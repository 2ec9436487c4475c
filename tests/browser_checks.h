// Checks of report.html in a real browser (issue 14): headless Chromium
// renders the page to a PNG (decoded with libpng: not blank) and dumps the
// DOM after loading (the tables and every plot present, nothing loaded from
// outside). Shared by tests/html_report_test.cc (quick) and
// tests/html_report_jobs_test.cc (the whole paper and EMPS jobs, slow).
#ifndef TESTS_BROWSER_CHECKS_H_
#define TESTS_BROWSER_CHECKS_H_

#include <png.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/gnuplot.h"
#include "tests/test_files.h"

namespace axis {
namespace browser_checks {

// The Chromium executable on PATH ("chromium", Debian's name, or
// "chromium-browser"), or "" if there is none.
inline std::string FindChromium() {
  const std::string chromium = FindExecutable("chromium");
  return chromium.empty() ? FindExecutable("chromium-browser") : chromium;
}

inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Runs headless Chromium on `html` with its own profile folder in `work`:
// `mode` is "--screenshot=<png>" or "--dump-dom" (the DOM into `dom`).
// Chromium's own messages (dbus and GPU warnings) go to a log file.
// Returns the exit code.
inline int RunChromium(const std::string& chromium, const std::string& html,
                       const std::string& work, const std::string& mode,
                       const std::string& dom = "") {
  const std::string command =
      "timeout 180 " + chromium +
      " --headless --no-sandbox --disable-gpu --no-first-run --hide-scrollbars"
      " --window-size=1280,4000 --user-data-dir=" + work + "/chromium-profile " + mode +
      " 'file://" + html + "'" + (dom.empty() ? " >/dev/null" : " >'" + dom + "'") + " 2>>'" +
      work + "/chromium.log'";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Runs fit-params on `job` (a path) with --out `out`; returns its exit code
// and its stdout and stderr in *log (also kept in `out`.log).
inline int RunFitParamsCli(const std::string& job, const std::string& out, std::string* log) {
  const std::string log_path = out + ".log";
  const std::string command = std::string(BINARY_DIR) + "/fit-params '" + job + "' --out '" +
                              out + "' >'" + log_path + "' 2>&1";
  const int status = std::system(command.c_str());
  *log = ReadFile(log_path);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// What a screenshot shows, decoded with libpng.
struct Picture {
  bool decoded = false;
  int width = 0, height = 0;
  size_t colours = 0;          // distinct colours, 4 bits per channel
  double non_white = 0.0;      // fraction of pixels not near white
  double dark = 0.0;           // fraction of pixels dark enough to be text or lines
};

inline Picture DecodePng(const std::string& path) {
  Picture p;
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return p;
  image.format = PNG_FORMAT_RGB;
  std::vector<unsigned char> pixels(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr)) return p;
  p.decoded = true;
  p.width = static_cast<int>(image.width);
  p.height = static_cast<int>(image.height);
  std::set<unsigned> colours;
  size_t non_white = 0, dark = 0;
  const size_t n = static_cast<size_t>(p.width) * static_cast<size_t>(p.height);
  for (size_t k = 0; k < n; ++k) {
    const unsigned r = pixels[3 * k], g = pixels[3 * k + 1], b = pixels[3 * k + 2];
    colours.insert(((r >> 4) << 8) | ((g >> 4) << 4) | (b >> 4));
    if (r < 240 || g < 240 || b < 240) ++non_white;
    if (r + g + b < 300) ++dark;
  }
  p.colours = colours.size();
  p.non_white = static_cast<double>(non_white) / static_cast<double>(n);
  p.dark = static_cast<double>(dark) / static_cast<double>(n);
  return p;
}

// Number of non-overlapping occurrences of `needle` in `text`.
inline size_t Count(const std::string& text, const std::string& needle) {
  size_t n = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) {
    ++n;
  }
  return n;
}

// The first reference `opening` ("href=" or "url(") in `text` that does not
// point at an id of the page itself ("#…" after optional quotes and
// blanks), with some context; "" if there is none.
inline std::string ReferencesOutside(const std::string& text, const std::string& opening) {
  for (size_t at = text.find(opening); at != std::string::npos;
       at = text.find(opening, at + 1)) {
    size_t k = at + opening.size();
    while (k < text.size() && (text[k] == '"' || text[k] == '\'' || text[k] == ' ')) ++k;
    if (k >= text.size() || text[k] != '#') return text.substr(at, 80);
  }
  return "";
}

// The plots report.html of the run in `dir` must hold: one per experiment
// of report.json, one per fitted channel of the fitted experiments (the
// residual diagnostics), as many again for the final model if discovery
// ran.
inline size_t ExpectedPlots(const nlohmann::json& report) {
  size_t plots = report["experiments"].size();
  size_t diagnosed = 0;
  for (const auto& e : report["experiments"]) {
    if (e["role"] != "fit") continue;
    for (const auto& c : e["channels"]) diagnosed += c["fitted"].get<bool>() ? 1 : 0;
  }
  plots += diagnosed;
  if (report.contains("discovery")) plots += diagnosed;
  return plots;
}

// A page rendered by headless Chromium: its screenshot and its DOM after
// loading.
struct RenderedPage {
  bool loaded = false;  // false: skipped (no Chromium) or failed (an ASSERT)
  Picture picture;
  std::string dom;
};

// Renders the page `html` (a path) with Chromium into the screenshot `png`
// (1280 x 4000) and dumps its DOM; skips the test if Chromium is not
// installed. The caller returns unless page->loaded.
inline void RenderInChromium(const std::string& html, const std::string& png,
                             RenderedPage* page) {
  const std::string chromium = FindChromium();
  if (chromium.empty()) {
    GTEST_SKIP() << "chromium is not installed (scripts/install-deps installs it): "
                 << html << " not checked in a browser";
  }
  ASSERT_TRUE(std::filesystem::exists(html)) << html;
  const std::string work = testing_files::TestTempDir() + "browser";
  std::filesystem::create_directories(work);
  std::filesystem::remove(png);
  ASSERT_EQ(RunChromium(chromium, html, work, "--screenshot=" + png), 0)
      << ReadFile(work + "/chromium.log");
  page->picture = DecodePng(png);
  ASSERT_TRUE(page->picture.decoded) << png;
  EXPECT_EQ(page->picture.width, 1280);
  EXPECT_EQ(page->picture.height, 4000);
  const std::string dom_path = work + "/dom.html";
  ASSERT_EQ(RunChromium(chromium, html, work, "--dump-dom", dom_path), 0)
      << ReadFile(work + "/chromium.log");
  page->dom = ReadFile(dom_path);
  ASSERT_GT(page->dom.size(), 1000u) << "empty DOM";
  page->loaded = true;
}

// Nothing from outside: no URL with a scheme, no src at all, no style sheet
// import, no frame, object or image, no url() but to the page's own ids.
inline void ExpectNothingLoadedFromOutside(const std::string& dom) {
  for (const char* forbidden : {"http:", "https:", "file://", "ftp:", "src=", "@import",
                                "<link", "<iframe", "<object", "<embed", "<img"}) {
    EXPECT_EQ(dom.find(forbidden), std::string::npos) << "'" << forbidden << "' in the page";
  }
  EXPECT_EQ(ReferencesOutside(dom, "url("), "") << "a url() out of the page";
}

// Renders `dir`/report.html with Chromium and checks it as a reader would
// see it: a screenshot that is not blank, and in the loaded DOM the
// sections, the parameter table with every free parameter of report.json,
// one SVG per expected plot, and no reference to anything outside the page.
// `sections` are the ids that must be present. The screenshot stays in
// `dir`/report.png for a person to look at.
inline void CheckInBrowser(const std::string& dir, const std::vector<std::string>& sections) {
  RenderedPage page;
  RenderInChromium(std::filesystem::absolute(dir + "/report.html").string(),
                   std::filesystem::absolute(dir + "/report.png").string(), &page);
  if (!page.loaded) return;
  const Picture& picture = page.picture;
  const std::string png = dir + "/report.png";
  // A blank page is one colour; this one has text, tables and plots.
  EXPECT_GT(picture.colours, 100u) << png;
  EXPECT_GT(picture.non_white, 0.03) << png;
  EXPECT_GT(picture.dark, 0.005) << png;

  const std::string& dom = page.dom;
  for (const std::string& id : sections) {
    EXPECT_NE(dom.find("<section id=\"" + id + "\">"), std::string::npos) << "no section " << id;
  }
  std::ifstream in(dir + "/report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  for (const auto& p : report["parameters"]) {
    if (!p["free"].get<bool>()) continue;
    EXPECT_NE(dom.find("<td>" + p["name"].get<std::string>() + "</td>"), std::string::npos)
        << "parameter " << p["name"] << " not in a table";
  }
  EXPECT_GE(Count(dom, "<table"), 5u);
  EXPECT_EQ(Count(dom, "<svg"), ExpectedPlots(report)) << "plots";
  EXPECT_EQ(Count(dom, "<figure class=\"missing\""), 0u) << "a plot could not be drawn";
  // No link but to the page's own anchors.
  ExpectNothingLoadedFromOutside(dom);
  EXPECT_EQ(ReferencesOutside(dom, "href="), "") << "a link out of the page";
}

}  // namespace browser_checks
}  // namespace axis

#endif  // TESTS_BROWSER_CHECKS_H_
