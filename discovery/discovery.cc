#include "discovery/discovery.h"

#include "discovery/discovery_loop.h"

namespace axis {

DiscoveryReport Discover(const DiscoverySettings& settings, FitJob* job,
                         FitResult* result, std::ostream* progress) {
  DiscoveryLoop loop(settings, job, result, progress);
  return loop.Run();
}

}  // namespace axis
