// Output folders staged and moved into place (io/output_staging.h): a run
// killed with SIGKILL while writing leaves its "<out>.partial.<pid>"
// staging folder (no handler can run); the next run on that output removes
// it and says so, and leaves the staging folder of a process that still runs.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/output_staging.h"

namespace axis {
namespace {

namespace fs = std::filesystem;

class OutputStagingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) /
           ("output_staging_" + std::to_string(static_cast<long>(::getpid())));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// A child process stages `out`, writes a file into the staging folder and
// kills itself with SIGKILL, as a run killed while writing; returns its pid.
pid_t StageAndDie(const std::string& out) {
  const pid_t child = ::fork();
  if (child == 0) {
    const std::string staging = MakeStagingDirectory(out);
    std::ofstream(staging + "/params.csv") << "half";
    ::raise(SIGKILL);
    ::_exit(0);  // not reached
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  return child;
}

TEST_F(OutputStagingTest, ARunRemovesTheStagingFolderOfAKilledRunAndSaysSo) {
  const std::string out = (dir_ / "out").string();
  const pid_t dead = StageAndDie(out);
  const std::string stale = out + ".partial." + std::to_string(static_cast<long>(dead));
  ASSERT_TRUE(fs::is_directory(stale));
  // The folder of a process that runs (pid 1, always there) stays.
  const std::string alive = out + ".partial.1";
  fs::create_directories(alive);
  const std::vector<std::string> warnings =
      WriteStaged(out, [](const std::string& staging, std::vector<std::string>*) {
        std::ofstream(staging + "/params.csv") << "whole";
      });
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::is_directory(alive));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("removed " + stale), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("process is gone"), std::string::npos) << warnings[0];
  std::ifstream in(out + "/params.csv");
  std::string text;
  in >> text;
  EXPECT_EQ(text, "whole");
}

TEST_F(OutputStagingTest, OtherFoldersBesideTheOutputAreNotStagingFolders) {
  const std::string out = (dir_ / "out").string();
  for (const char* name : {"out.partial.x1", "out.partialy", "other.partial.999999999",
                           "out.partial.1234567890"}) {
    fs::create_directories(dir_ / name);
  }
  EXPECT_TRUE(RemoveStaleStagingDirectories(out).empty());
  for (const char* name : {"out.partial.x1", "out.partialy", "other.partial.999999999",
                           "out.partial.1234567890"}) {
    EXPECT_TRUE(fs::is_directory(dir_ / name)) << name;
  }
}

}  // namespace
}  // namespace axis
