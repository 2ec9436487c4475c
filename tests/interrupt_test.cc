// SIGINT and SIGTERM (io/interrupt.h): exit 130/143 with one line saying
// what was not written, outputs held back while they are being committed,
// and no partial output left by the command-line tools.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/wait.h>
#include <gtest/gtest.h>

#include "io/interrupt.h"
#include "tests/test_files.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using axis::testing_files::CommandResult;

const std::string kRoot = PROJECT_SOURCE_DIR;
const std::string kBin = BINARY_DIR;

TEST(InterruptTest, OutsideADeferredScopeExitsAtOnce) {
  EXPECT_EXIT(
      {
        axis::InstallInterruptHandlers("tool");
        axis::SetInterruptTarget("out/run");
        std::raise(SIGTERM);
        std::exit(0);
      },
      ::testing::ExitedWithCode(143), "^tool: interrupted by SIGTERM: nothing written to out/run\n$");
}

TEST(InterruptTest, HeldWhileCommittingThenReported) {
  EXPECT_EXIT(
      {
        axis::InstallInterruptHandlers("tool");
        axis::SetInterruptTarget("out/run");
        {
          axis::DeferInterrupts defer;
          std::raise(SIGINT);  // held: the commit completes
          defer.Committed();
        }
        std::exit(0);
      },
      ::testing::ExitedWithCode(130), "^tool: interrupted by SIGINT after out/run was written\n$");
  EXPECT_EXIT(
      {
        axis::InstallInterruptHandlers("tool");
        axis::SetInterruptTarget("out/run");
        {
          axis::DeferInterrupts defer;
          std::raise(SIGINT);  // the commit failed (no Committed())
        }
        std::exit(0);
      },
      ::testing::ExitedWithCode(130), "^tool: interrupted by SIGINT: nothing written to out/run\n$");
}

// CPU time (user + system) the process `pid` has used so far, from fields 14
// and 15 of /proc/PID/stat (proc(5)), in seconds; -1 if it cannot be read.
double CpuSeconds(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat((std::istreambuf_iterator<char>(in)), {});
  const std::size_t close = stat.rfind(')');  // the command name may hold spaces
  if (close == std::string::npos) return -1;
  std::istringstream fields(stat.substr(close + 2));
  std::string field;
  long ticks = 0;
  for (int i = 3; i <= 15 && fields >> field; ++i) {
    if (i >= 14) ticks += std::stol(field);
  }
  return static_cast<double>(ticks) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

// Starts `binary args...` with stdout to /dev/null and stderr to a file,
// sends `signal` once the process has used `cpu` seconds of CPU time (so it
// is past start-up and into its work however loaded the machine is; a wall
// clock delay was not: under a loaded CI the signal once arrived before the
// tool had named its output), and waits for it.
CommandResult RunAndSignal(const std::string& binary, std::vector<std::string> args,
                           double cpu, int signal) {
  const std::string err_path = axis::testing_files::TestTempDir() + "stderr.txt";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  args.insert(args.begin(), binary);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, binary.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return {-1, "cannot start " + binary};
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (CpuSeconds(pid) < cpu && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ::kill(pid, signal);
  int status = 0;
  ::waitpid(pid, &status, 0);
  std::ifstream in(err_path);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1,
          std::string((std::istreambuf_iterator<char>(in)), {})};
}

// Entries of `dir` whose names start with `prefix`.
std::vector<std::string> EntriesStartingWith(const std::string& dir, const std::string& prefix) {
  std::vector<std::string> out;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) == 0) out.push_back(name);
  }
  return out;
}

// The paper job runs for seconds of CPU time: interrupted after 0.5 s of it
// it has written nothing, not even the staging folder.
TEST(InterruptTest, FitParamsInterruptedLeavesNoOutputFolder) {
  const std::string dir = axis::testing_files::TestTempDir();
  const std::string out = dir + "paper_out";
  fs::remove_all(out);
  const CommandResult r =
      RunAndSignal(kBin + "/fit-params", {kRoot + "/configs/jobs/x_axis_paper.yaml", "--out", out},
                   0.5, SIGINT);
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_NE(r.err.find("fit-params: interrupted by SIGINT: nothing written to " + out),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(EntriesStartingWith(dir, "paper_out").empty());
}

// A 2000 s simulation (minutes of work) terminated after 0.3 s of CPU time:
// no CSV and no temporary file.
TEST(InterruptTest, SimulateAxisTerminatedLeavesNoFile) {
  const std::string dir = axis::testing_files::TestTempDir();
  const std::string experiment = dir + "long.yaml";
  std::ofstream(experiment) << "model: " << kRoot << "/configs/axes/x_axis.yaml\n"
                            << "duration: 2000\nstep: 1.0e-5\noutput_rate: 100\n"
                            << "channels: [u, v]\ninput: {type: step, amplitude: 1}\n";
  const std::string out = dir + "long.csv";
  fs::remove(out);
  const CommandResult r = RunAndSignal(kBin + "/simulate-axis", {experiment, "--out", out},
                                       0.3, SIGTERM);
  EXPECT_EQ(r.exit_code, 143) << r.err;
  EXPECT_NE(r.err.find("simulate-axis: interrupted by SIGTERM: nothing written to " + out),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(EntriesStartingWith(dir, "long.csv").empty());
}

}  // namespace
