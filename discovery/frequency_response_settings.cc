#include "discovery/frequency_response_settings.h"

#include "io/settings_reader.h"
#include "io/yaml_util.h"

namespace axis {

void ReadFrequencyResponseSettings(const YAML::Node& node, const std::string& file,
                                   FrequencyResponseSettings* s) {
  if (node.IsNull()) return;
  YamlMap map(node, file, "frequency_response.");
  ReadSettings(&map, s);
  map.Finish();
}

}  // namespace axis
