#include "discovery/discovery.h"

#include "discovery/internal/discovery_loop.h"

namespace axis {

DiscoveryReport Discover(const DiscoverySettings& settings, EstimationProblem* job,
                         FitResult* result, std::ostream* progress,
                         const std::function<void(const char*)>& stage) {
  DiscoveryLoop loop(settings, job, result, progress, stage);
  return loop.Run();
}

}  // namespace axis
