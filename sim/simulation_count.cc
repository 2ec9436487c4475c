#include "sim/simulation_count.h"

#include <atomic>

namespace axis {
namespace {

std::atomic<long long> values{0};
std::atomic<long long> derivatives{0};

}  // namespace

SimulationCount SimulationsSoFar() {
  SimulationCount c;
  c.values = values.load(std::memory_order_relaxed);
  c.derivatives = derivatives.load(std::memory_order_relaxed);
  return c;
}

namespace internal {

void CountSimulation(bool with_derivatives) {
  (with_derivatives ? derivatives : values).fetch_add(1, std::memory_order_relaxed);
}

}  // namespace internal
}  // namespace axis
