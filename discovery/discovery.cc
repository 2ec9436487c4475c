#include "discovery/discovery.h"

#include "discovery/internal/discovery_loop.h"

namespace axis {

DiscoveryReport Discover(const DiscoverySettings& settings, EstimationProblem* job,
                         FitResult* result, std::ostream* progress) {
  DiscoveryLoop loop(settings, job, result, progress);
  return loop.Run();
}

}  // namespace axis
