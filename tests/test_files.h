// Helpers shared by the test suites: files written into GoogleTest's
// temporary directory.
#ifndef TESTS_TEST_FILES_H_
#define TESTS_TEST_FILES_H_

#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace axis {
namespace testing_files {

// Writes `text` to `name` in ::testing::TempDir() and returns its path.
inline std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace testing_files
}  // namespace axis

#endif  // TESTS_TEST_FILES_H_
