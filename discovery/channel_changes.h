// The channels' figures before and after a change of the model (a discovery
// step, the force map), side by side.
#ifndef DISCOVERY_CHANNEL_CHANGES_H_
#define DISCOVERY_CHANNEL_CHANGES_H_

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "estimation/fit_result.h"

namespace axis {

// Before/after figures of one channel across a discovery step.
struct ChannelChange {
  std::string experiment, channel;
  double rms_before = 0.0, rms_after = 0.0;
  double fit_percent_before = 0.0, fit_percent_after = 0.0;
};

// The channels of `before` and `after` (same experiments), RMS and fit %
// side by side; channels replayed exactly in both (RMS 0) are left out.
std::vector<ChannelChange> ChannelChanges(const FitResult& before, const FitResult& after);

// The changes as a JSON array of {"experiment", "channel", "rms_before",
// "rms_after", "fit_percent_before", "fit_percent_after"} (report.json:
// discovery steps, force map); non-finite numbers as null.
nlohmann::json ChannelChangesToJson(const std::vector<ChannelChange>& changes);

}  // namespace axis

#endif  // DISCOVERY_CHANNEL_CHANGES_H_
