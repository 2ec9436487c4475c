// The benchmarks' main: Google Benchmark's, with the allocator set as the
// front ends set it (common/allocator.h), so that a benchmark measures what
// a run of fit-params pays.
#include <benchmark/benchmark.h>

#include "common/allocator.h"

int main(int argc, char** argv) {
  axis::KeepFreedMemory();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
