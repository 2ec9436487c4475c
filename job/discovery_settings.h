// Settings of the model-discovery loop (discovery/discovery.h), the job key
// `discover:`. Separate so that job/fit_job.h does not depend on the loop.
#ifndef JOB_DISCOVERY_SETTINGS_H_
#define JOB_DISCOVERY_SETTINGS_H_

#include <string>
#include <vector>

namespace axis {

struct DiscoverySettings {
  bool enabled = false;        // `discover:` present, or --discover
  int max_effects = 3;         // at most this many effects added
  double alpha = 1e-3;         // family-wise level, Bonferroni over candidates
  int tries = 3;               // refits per step: significant candidates in
                               // rank order until one improves BIC
  // Refits per step when the model is far from the data (s² above
  // kMisspecifiedS2, discovery/discovery_loop.cc): the top `misspecified_tries`
  // significant candidates, all screened (discovery/screen.h), those
  // GoOnPastScreen names (the top `tries` by score or by screen bound)
  // refitted to the whole record (concurrently), the lowest BIC wins. The
  // default exceeds the number of candidates: all significant ones. On power_payload (20 seeds) with the top 3 only the payload was
  // never first (ninth by score on the case's data, its refit BIC 1.19e4
  // against 1.03e5 for the best of the others).
  int misspecified_tries = 20;
  std::vector<std::string> candidates;  // restrict the list (empty: all)
  // The force-map step after the loop (discovery/force_map.h, issue 15): when
  // the verdict is `incomplete` with binned structure against x or v, learn
  // the missing force as a spline of about `force_map_knots` knots
  // (8..kMaxForceMapKnots: half at quantiles, half uniform, merged).
  bool force_map = false;
  int force_map_knots = 24;
};

}  // namespace axis

#endif  // JOB_DISCOVERY_SETTINGS_H_
