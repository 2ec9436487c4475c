#include "discovery/channel_changes.h"

#include "common/format.h"

namespace axis {

nlohmann::json ChannelChangesToJson(const std::vector<ChannelChange>& changes) {
  nlohmann::json out = nlohmann::json::array();
  for (const ChannelChange& c : changes) {
    out.push_back({{"experiment", c.experiment},
                   {"channel", c.channel},
                   {"rms_before", JsonNumber(c.rms_before)},
                   {"rms_after", JsonNumber(c.rms_after)},
                   {"fit_percent_before", JsonNumber(c.fit_percent_before)},
                   {"fit_percent_after", JsonNumber(c.fit_percent_after)}});
  }
  return out;
}

std::vector<ChannelChange> ChannelChanges(const FitResult& before, const FitResult& after) {
  std::vector<ChannelChange> out;
  for (const ExperimentFit& b : before.experiments) {
    for (const ExperimentFit& a : after.experiments) {
      if (a.name != b.name) continue;
      for (const ChannelFit& cb : b.channels) {
        for (const ChannelFit& ca : a.channels) {
          if (ca.channel != cb.channel) continue;
          // An open-loop input is replayed exactly: nothing to compare.
          if (cb.rms == 0.0 && ca.rms == 0.0) continue;
          out.push_back({b.name, cb.channel, cb.rms, ca.rms, cb.fit_percent,
                         ca.fit_percent});
        }
      }
    }
  }
  return out;
}

}  // namespace axis
