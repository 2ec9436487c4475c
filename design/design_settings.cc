#include "design/design_settings.h"

#include <cmath>
#include <string>

#include "io/yaml_util.h"

namespace axis {

void ReadDesignSettings(const YAML::Node& node, const std::string& file, DesignSettings* d) {
  using Range = YamlMap::Range;
  YamlMap map(node, file, "design.");
  d->enabled = true;
  d->duration = map.Number("duration", d->duration, Range::kFinitePositive);
  if (!(d->duration >= 0.5 && d->duration <= 60.0)) {
    ThrowConfigError(file, map.Optional("duration"), "design.duration",
                     "a record length in [0.5, 60] s", NumberText(d->duration));
  }
  d->max_voltage = map.Number("max_voltage", d->max_voltage, Range::kFinitePositive);
  if (!(d->max_voltage <= 10.0)) {
    ThrowConfigError(file, map.Optional("max_voltage"), "design.max_voltage",
                     "a voltage in (0, 10] V (the drive's range)", NumberText(d->max_voltage));
  }
  const YAML::Node travel = map.Required("travel");
  if (!travel.IsSequence() || travel.size() != 2) {
    ThrowConfigError(file, travel, "design.travel", "[low, high] in m", Describe(travel));
  }
  d->travel_low = map.NumberFrom(travel[0], "design.travel", Range::kAny);
  d->travel_high = map.NumberFrom(travel[1], "design.travel", Range::kAny);
  if (!(std::isfinite(d->travel_low) && std::isfinite(d->travel_high) &&
        d->travel_low < d->travel_high)) {
    ThrowConfigError(file, travel, "design.travel", "finite low < high",
                     NumberText(d->travel_low) + " and " + NumberText(d->travel_high));
  }
  d->rel_se = map.Number("rel_se", d->rel_se, Range::kNonNegative);
  map.Finish();
}

}  // namespace axis
