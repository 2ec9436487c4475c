// Helpers shared by the test suites: files written into GoogleTest's
// temporary directory, and command-line runs of the apps.
#ifndef TESTS_TEST_FILES_H_
#define TESTS_TEST_FILES_H_

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

namespace axis {
namespace testing_files {

// A directory of the running test's own, ::testing::TempDir() +
// "<suite>.<test>/" (created), so that tests run in parallel by ctest
// (each case a process) never share a file name.
inline std::string TestTempDir() {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string dir =
      ::testing::TempDir() +
      (info != nullptr ? std::string(info->test_suite_name()) + "." + info->name()
                       : std::string("outside_a_test")) +
      "/";
  std::filesystem::create_directories(dir);
  return dir;
}

// Writes `text` to `name` in TestTempDir() and returns its path.
inline std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path = TestTempDir() + name;
  std::ofstream(path) << text;
  return path;
}

// The text of a job file of configs/jobs/ (`name` relative to it) with its
// relative paths ("../../" to the project root, "../axes" to configs/axes)
// made absolute, so that it loads from the test's folder.
inline std::string JobTextWithAbsolutePaths(const std::string& name) {
  const std::string root = PROJECT_SOURCE_DIR;
  std::ifstream in(root + "/configs/jobs/" + name);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  for (const std::string rel : {"../../", "../axes"}) {
    const std::string abs = rel == "../axes" ? root + "/configs/axes" : root + "/";
    for (size_t at; (at = text.find(rel)) != std::string::npos;) text.replace(at, rel.size(), abs);
  }
  return text;
}

// Exit code (-1 if it did not exit) and standard error of a command.
struct CommandResult {
  int exit_code;
  std::string err;
};

// Runs `binary args` through the shell, standard error captured into a file
// named after the current test, standard output discarded if
// `discard_stdout`.
inline CommandResult RunCommand(const std::string& binary, const std::string& args,
                                bool discard_stdout) {
  const std::string err_path =
      ::testing::TempDir() +
      ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_stderr.txt";
  const std::string command = binary + " " + args +
                              (discard_stdout ? " >/dev/null" : "") + " 2>" + err_path;
  const int status = std::system(command.c_str());
  std::ifstream in(err_path);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1,
          std::string((std::istreambuf_iterator<char>(in)), {})};
}

}  // namespace testing_files
}  // namespace axis

#endif  // TESTS_TEST_FILES_H_
