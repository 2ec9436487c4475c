// simulate-axis EXPERIMENT.yaml --out trace.csv [--seed N] [--set NAME=VALUE ...]
//               [--no-noise]
//
// Simulates one experiment file (configs/experiments/*.yaml) and writes the
// recorded channels as CSV. Exit codes: 0 success, 2 bad input (command
// line, config, data file), 1 other failures, 130/143 interrupted by
// SIGINT/SIGTERM (nothing written; io/interrupt.h).
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <stdexcept>

#include <CLI/CLI.hpp>

#include "common/allocator.h"
#include "apps/integer_option.h"
#include "sim/config.h"
#include "sim/experiment.h"
#include "io/interrupt.h"

int main(int argc, char** argv) {
  axis::KeepFreedMemory();  // common/allocator.h: a fit reuses its buffers
  axis::InstallInterruptHandlers("simulate-axis");
  CLI::App app{"Simulate one servo-axis experiment (Nelson & Chang 1984 model)"};
  axis::SimulateAxisOptions options;
  app.add_option("experiment", options.experiment_path, "experiment YAML file")
      ->required();
  app.add_option("--out", options.out_path, "output CSV file")->required();
  auto* seed = app.add_option("--seed", options.seed,
                              "noise seed (overrides the experiment's)")
                   ->check(axis::IntegerIn(0, axis::kMaxExperimentSeed,
                                           "the range of the experiment's seed key"));
  app.add_option("--set", options.sets,
                 "parameter override NAME=VALUE (MODEL.md names), repeatable");
  app.add_flag("--no-noise", options.no_noise,
               "write the noise-free trace (ignore the experiment's noise)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  options.has_seed = seed->count() > 0;
  options.show_progress = isatty(STDERR_FILENO) != 0;
  try {
    axis::SimulateAxis(options);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "simulate-axis: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "simulate-axis: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
