#include "common/gnuplot.h"

#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>

extern char** environ;

namespace axis {
namespace {

namespace fs = std::filesystem;

// The executable `name` in a directory of $PATH, or "" if none.
std::string FindOnPath(const std::string& name) {
  const char* env = std::getenv("PATH");
  const std::string path = env != nullptr ? env : "/usr/local/bin:/usr/bin:/bin";
  size_t begin = 0;
  while (begin <= path.size()) {
    size_t end = path.find(':', begin);
    if (end == std::string::npos) end = path.size();
    std::string dir = path.substr(begin, end - begin);
    if (dir.empty()) dir = ".";
    const std::string candidate = dir + "/" + name;
    struct stat st;
    if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
        ::access(candidate.c_str(), X_OK) == 0) {
      return candidate;
    }
    begin = end + 1;
  }
  return "";
}

// Runs `program` with `args` (argv[1..]), stdin and stdout on /dev/null;
// returns the wait status (-1 if it could not be started, errno in *err) and
// its stderr in *errors.
int Run(const std::string& program, const std::vector<std::string>& args,
        std::string* errors, int* err) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    *err = errno;
    return -1;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 2);
  std::vector<std::string> storage;
  storage.push_back(program);
  storage.insert(storage.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& s : storage) argv.push_back(&s[0]);
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int spawned = ::posix_spawn(&pid, program.c_str(), &actions, nullptr,
                                    argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  if (spawned != 0) {
    ::close(fds[0]);
    *err = spawned;
    return -1;
  }
  char buf[4096];
  for (;;) {
    const ssize_t got = ::read(fds[0], buf, sizeof(buf));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    if (errors->size() < 65536) errors->append(buf, static_cast<size_t>(got));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      *err = errno;
      return -1;
    }
  }
  return status;
}

// The last non-blank line of `text`, trimmed (gnuplot echoes the failing
// command and a caret before its message).
std::string LastLine(const std::string& text) {
  std::string last;
  size_t begin = 0;
  while (begin < text.size()) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(begin, end - begin);
    const size_t a = line.find_first_not_of(" \t\r");
    if (a != std::string::npos) {
      const size_t b = line.find_last_not_of(" \t\r");
      last = line.substr(a, b - a + 1);
    }
    begin = end + 1;
  }
  return last;
}

std::atomic<unsigned> plot_counter{0};

}  // namespace

bool HasLineBreak(const std::string& s) {
  return s.find_first_of("\r\n") != std::string::npos;
}

std::string FindExecutable(const std::string& name) { return FindOnPath(name); }

namespace {

// Runs gnuplot on script(temp) so that it draws into `temp`; true if it
// exited 0 and left a non-empty file there. Else removes `temp`, sets
// *warning (naming `what` and `target`) and returns false.
bool RunGnuplot(const std::string& temp, const std::string& target,
                const std::function<std::string(const std::string&)>& script,
                const std::string& what, std::string* warning) {
  const std::string gnuplot = FindOnPath("gnuplot");
  if (gnuplot.empty()) {
    *warning = "gnuplot not found: no plot written for " + what;
    return false;
  }
  if (HasLineBreak(temp)) {
    *warning = "a path contains a line break: no plot written for " + what;
    return false;
  }
  std::string errors;
  int err = 0;
  const int status = Run(gnuplot, {"-e", script(temp)}, &errors, &err);
  std::error_code ec;
  const bool written = fs::is_regular_file(temp, ec) && fs::file_size(temp, ec) > 0;
  const bool ok = status >= 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (ok && written) return true;
  ::unlink(temp.c_str());
  std::string why;
  if (status < 0) {
    why = "cannot run " + gnuplot + ": " + std::generic_category().message(err);
  } else if (WIFEXITED(status)) {
    why = "gnuplot exited with status " + std::to_string(WEXITSTATUS(status));
  } else if (WIFSIGNALED(status)) {
    why = "gnuplot killed by signal " + std::to_string(WTERMSIG(status));
  } else {
    why = "gnuplot failed";
  }
  if (ok) why = "gnuplot wrote no image";
  const std::string last = LastLine(errors);
  *warning = why + (last.empty() ? "" : " (" + last + ")") +
             ": no plot written for " + what + " (" + target + ")";
  return false;
}

// A temporary file name beside `path` for gnuplot's output.
std::string GnuplotTemp(const std::string& path, const char* extension) {
  return path + ".tmp." + std::to_string(static_cast<long>(::getpid())) + "." +
         std::to_string(plot_counter++) + extension;
}

void ReplaceAll(std::string* s, const std::string& from, const std::string& to) {
  for (size_t at = s->find(from); at != std::string::npos; at = s->find(from, at + to.size())) {
    s->replace(at, from.size(), to);
  }
}

}  // namespace

bool RenderGnuplotPng(const std::string& png_path,
                      const std::function<std::string(const std::string&)>& script,
                      const std::string& what, std::string* warning) {
  std::string ignored;
  if (warning == nullptr) warning = &ignored;
  warning->clear();
  if (HasLineBreak(png_path)) {
    *warning = "a path contains a line break: no plot written for " + what;
    return false;
  }
  const std::string temp = GnuplotTemp(png_path, ".png");
  if (!RunGnuplot(temp, png_path, script, what, warning)) return false;
  if (std::rename(temp.c_str(), png_path.c_str()) != 0) {
    const int e = errno;
    ::unlink(temp.c_str());
    throw std::runtime_error(png_path + ": cannot write: renaming '" + temp +
                             "' over it: " + std::generic_category().message(e));
  }
  return true;
}

bool RenderGnuplotSvg(const std::string& scratch_dir,
                      const std::function<std::string(const std::string&)>& script,
                      const std::string& what, const std::string& id_prefix,
                      std::string* svg, std::string* warning) {
  std::string ignored;
  if (warning == nullptr) warning = &ignored;
  warning->clear();
  svg->clear();
  const std::string temp = GnuplotTemp((fs::path(scratch_dir) / "plot").string(), ".svg");
  if (!RunGnuplot(temp, "inline SVG", script, what, warning)) return false;
  std::ifstream in(temp, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  ::unlink(temp.c_str());
  const size_t begin = text.find("<svg");
  const size_t end = text.rfind("</svg>");
  if (begin == std::string::npos || end == std::string::npos || end < begin) {
    *warning = "gnuplot wrote no SVG document: no plot for " + what;
    return false;
  }
  text = text.substr(begin, end + 6 - begin);
  // Inline in HTML: the namespaces are implied, SVG 2 `href` needs no xlink,
  // and every id gets the plot's prefix (ids are per document).
  ReplaceAll(&text, "xmlns=\"http://www.w3.org/2000/svg\"", "");
  ReplaceAll(&text, "xmlns:xlink=\"http://www.w3.org/1999/xlink\"", "");
  ReplaceAll(&text, "xlink:href=", "href=");
  ReplaceAll(&text, "<title>Gnuplot</title>", "");  // the page's caption says what it is
  // gnuplot names each plot's group for its mouse script, the same names
  // in every panel of a multiplot: ids that nothing here refers to, and
  // titles that a browser would show as the tooltip of a trace.
  for (const std::string& from : {std::string(" id=\"gnuplot_plot_"),
                                  std::string("<title>gnuplot_plot_")}) {
    const char end = from[0] == ' ' ? '"' : '>';
    for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at)) {
      const size_t close = text.find(end, at + from.size());
      if (close == std::string::npos) break;
      text.erase(at, close + 1 - at);
    }
  }
  for (const char* quote : {"'", "\""}) {
    ReplaceAll(&text, std::string("id=") + quote, std::string("id=") + quote + id_prefix);
    ReplaceAll(&text, std::string("href=") + quote + "#",
               std::string("href=") + quote + "#" + id_prefix);
  }
  ReplaceAll(&text, "url(#", "url(#" + id_prefix);
  // Nothing may be loaded from elsewhere (gnuplot's `mouse` option would
  // add a script, an `image` would refer to a file).
  for (const char* external : {"http:", "https:", "<script", "<image", "@import", "src="}) {
    if (text.find(external) != std::string::npos) {
      *warning = std::string("gnuplot's SVG refers to something outside it ('") + external +
                 "'): no plot for " + what;
      return false;
    }
  }
  *svg = std::move(text);
  return true;
}

}  // namespace axis
