// Settings of the model-discovery loop (fit/discovery.h), the job key
// `discover:`. Separate so that fit/job.h does not depend on the loop.
#ifndef FIT_DISCOVERY_SETTINGS_H_
#define FIT_DISCOVERY_SETTINGS_H_

#include <string>
#include <vector>

namespace axis {

struct DiscoverySettings {
  bool enabled = false;        // `discover:` present, or --discover
  int max_effects = 3;         // at most this many effects added
  double alpha = 1e-3;         // family-wise level, Bonferroni over candidates
  int tries = 3;               // refits per step: significant candidates in
                               // rank order until one improves BIC
  std::vector<std::string> candidates;  // restrict the list (empty: all)
};

}  // namespace axis

#endif  // FIT_DISCOVERY_SETTINGS_H_
