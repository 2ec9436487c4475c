#include "report/published_reference.h"

#include <string>
#include <vector>

#include "io/yaml_util.h"
#include "sim/axis_config.h"

namespace axis {

void ReadPublishedReference(const YAML::Node& node, const std::string& path,
                            const EstimationProblem& problem, PublishedReference* out) {
  using Range = YamlMap::Range;
  const AxisConfig& model = problem.model;
  const std::vector<FitExperiment>& experiments = problem.experiments;
  const std::vector<FitExperiment>& validate = problem.validate;
  YamlMap map(node, path, "published.");
  out->present = true;
  out->source = map.String("source");
  out->model = model;
  ParseModelOverrides(map, &out->model);
  if (const YAML::Node set = node["set"]) {
    for (const auto& entry : set) out->parameters.push_back(entry.first.Scalar());
  }
  if (const YAML::Node effects = node["effects"]) {
    for (const auto& effect : effects) {
      if (!effect.second.IsMap()) continue;
      for (const auto& param : effect.second) {
        out->parameters.push_back(param.first.Scalar());
      }
    }
  }
  if (const YAML::Node quoted = map.Optional("relative_error_percent")) {
    YamlMap experiments_map(quoted, path, "published.relative_error_percent.");
    for (const auto& entry : quoted) {
      const std::string name = entry.first.Scalar();
      bool known = false;
      for (const auto* list : {&experiments, &validate}) {
        for (const FitExperiment& e : *list) known = known || e.name == name;
      }
      if (!known) {
        ThrowConfigError(path, entry.first, experiments_map.KeyPath(name),
                         "the name of an experiment of this job", "'" + name + "'");
      }
      YamlMap channels(experiments_map.Optional(name), path,
                       experiments_map.KeyPath(name) + ".");
      for (const auto& ch : entry.second) {
        const std::string channel = ch.first.Scalar();
        ChannelOrThrow(channel, channels, ch.first, channels.KeyPath(channel));
        out->quoted.push_back(
            {name, channel, channels.Number(channel, Range::kNonNegative)});
      }
      channels.Finish();
    }
    experiments_map.Finish();
  }
  map.Finish();
}

}  // namespace axis
