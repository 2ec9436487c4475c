// fit-fleet (issue 12) on the synthetic fleet's eight "last month" jobs
// (configs/fleet/last_month.yaml, about 1.3 s each on one core), on 1 and
// on 2 MPI ranks: the wall time of the whole run, fit-fleet started as a
// subprocess (alone, or under `mpirun --oversubscribe -np 2`), and on the
// 2-rank run the speed-up over the 1-rank one (counter `speedup`). Run it on
// an otherwise idle machine with at least 2 cores: the ranks share them.
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <benchmark/benchmark.h>
#include <sys/wait.h>

namespace {

double one_rank_seconds = 0.0;  // the 1-rank run's mean wall time, for the speed-up

void BM_FleetEightJobs(benchmark::State& state) {
  const int ranks = static_cast<int>(state.range(0));
  const std::string out = std::filesystem::temp_directory_path().string() + "/bench_fleet_" +
                          std::to_string(getpid()) + "_" + std::to_string(ranks);
  std::string command;
  if (ranks > 1) {
    if (geteuid() == 0) command += "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ";
    command += "mpirun --oversubscribe -np " + std::to_string(ranks) + " ";
  }
  command += std::string(BINARY_DIR) + "/fit-fleet " + PROJECT_SOURCE_DIR +
             "/configs/fleet/last_month.yaml --out '" + out + "' >/dev/null 2>&1";
  double total = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const int status = std::system(command.c_str());
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      state.SkipWithError(("fit-fleet failed: " + command).c_str());
      break;
    }
    state.SetIterationTime(seconds);
    total += seconds;
  }
  std::filesystem::remove_all(out);
  if (state.iterations() == 0) return;
  const double mean = total / static_cast<double>(state.iterations());
  if (ranks == 1) one_rank_seconds = mean;
  if (ranks > 1 && one_rank_seconds > 0.0) state.counters["speedup"] = one_rank_seconds / mean;
}
// The 1-rank run first: the 2-rank one divides by its time.
BENCHMARK(BM_FleetEightJobs)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("ranks")
    ->UseManualTime()
    ->Unit(benchmark::kSecond)
    ->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
