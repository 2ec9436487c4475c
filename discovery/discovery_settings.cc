#include "discovery/discovery_settings.h"

#include <string>

#include "io/settings_reader.h"
#include "io/yaml_util.h"
#include "sim/effect_table.h"

namespace axis {
namespace {

// `discover.candidates`: a list of effect names.
void ReadCandidates(YamlMap& map, DiscoverySettings* d) {
  const YAML::Node list = map.Optional("candidates");
  if (!list) return;
  if (!list.IsSequence()) {
    ThrowConfigError(map.file(), list, map.KeyPath("candidates"), "a list of effect names",
                     Describe(list));
  }
  for (const YAML::Node& c : list) {
    const std::string name = c.IsScalar() ? c.Scalar() : "";
    if (!IsEffectName(name, true)) {
      ThrowConfigError(map.file(), c, map.KeyPath("candidates"),
                       "an effect of MODEL.md section 7 (" + EffectNameList() + ")",
                       Describe(c));
    }
    d->candidates.push_back(name);
  }
}

}  // namespace

void ReadDiscoverySettings(const YAML::Node& node, const std::string& file,
                           DiscoverySettings* d) {
  d->enabled = true;
  if (node.IsNull()) return;
  YamlMap map(node, file, "discover.");
  ReadSettings(&map, d);
  if (d->alpha >= 1.0) {
    ThrowConfigError(file, map.Optional("alpha"), map.KeyPath("alpha"), "a level in (0, 1)",
                     Describe(map.Optional("alpha")));
  }
  ReadCandidates(map, d);
  map.Finish();
}

}  // namespace axis
