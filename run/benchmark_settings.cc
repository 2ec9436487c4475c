#include "run/benchmark_settings.h"

#include <algorithm>
#include <set>
#include <stdexcept>

#include "common/format.h"
#include "io/output_staging.h"
#include "estimation/estimation_problem.h"
#include "sim/channels.h"
#include "sim/config.h"
#include "io/yaml_util.h"

namespace axis {
namespace {

// Entry k of `benchmark.columns` (`columns`, from `map`): its experiment
// among the job's, the channel that experiment measures.
BenchmarkColumn ParseColumn(const YamlMap& map, const YAML::Node& columns, size_t k,
                            const std::string& path,
                            const std::vector<FitExperiment>& experiments,
                            const std::vector<FitExperiment>& validate, bool rotary) {
  const std::string prefix = map.KeyPath("columns[" + std::to_string(k) + "]");
  YamlMap entry(columns[k], path, prefix + ".");
  BenchmarkColumn c;
  c.experiment = entry.String("experiment");
  const FitExperiment* fitted = FindExperiment(experiments, c.experiment);
  const FitExperiment* validated = FindExperiment(validate, c.experiment);
  if (fitted == nullptr && validated == nullptr) {
    ThrowConfigError(path, entry.Optional("experiment"), entry.KeyPath("experiment"),
                     "the name of an experiment of this job", "'" + c.experiment + "'");
  }
  if (k == 0 && (validated == nullptr || fitted != nullptr)) {
    ThrowConfigError(path, entry.Optional("experiment"), entry.KeyPath("experiment"),
                     "the score (the first column) on a 'validate:' experiment, which "
                     "no criterion fits",
                     "'" + c.experiment + "', a fitted experiment");
  }
  const FitExperiment& e = fitted != nullptr ? *fitted : *validated;
  c.channel = entry.String("channel");
  const auto channel = ParseChannel(c.channel);
  bool measured = false;
  for (Channel m : e.measured_channels) measured = measured || (channel && m == *channel);
  if (!measured) {
    std::vector<std::string> names;
    for (Channel m : e.measured_channels) names.push_back(ChannelName(m));
    ThrowConfigError(path, entry.Optional("channel"), entry.KeyPath("channel"),
                     "a channel that experiment '" + c.experiment + "' measures (" +
                         Join(names, ", ") + ")",
                     "'" + c.channel + "'");
  }
  c.measure = entry.Choice("measure", {"rms", "mae", "relative_error_percent"}, "rms");
  c.scale = entry.Number("scale", 1.0, YamlMap::Range::kFinitePositive);
  if (c.scale != 1.0 && !entry.Has("unit")) {
    ThrowConfigError(path, entry.Optional("scale"), entry.KeyPath("unit"),
                     "the unit of the scaled figure (e.g. 'mm' with scale 1000) whenever "
                     "scale is not 1",
                     "none");
  }
  c.unit = entry.String("unit", c.measure == "relative_error_percent"
                                    ? "%"
                                    : ChannelUnit(*channel, rotary));
  entry.Finish();
  return c;
}

// `benchmark.columns` (required, a non-empty list).
void ParseColumns(YamlMap& map, const std::string& path,
                  const std::vector<FitExperiment>& experiments,
                  const std::vector<FitExperiment>& validate, bool rotary,
                  BenchmarkSettings* out) {
  const YAML::Node columns = map.Required("columns");
  if (!columns.IsSequence() || columns.size() == 0) {
    ThrowConfigError(path, columns, map.KeyPath("columns"),
                     "a non-empty list of {experiment, channel, measure, scale, unit}",
                     Describe(columns));
  }
  for (size_t k = 0; k < columns.size(); ++k) {
    out->columns.push_back(ParseColumn(map, columns, k, path, experiments, validate, rotary));
  }
}

// The criterion of `criteria_map` whose key is `name_key` (name: list).
BenchmarkCriterion ParseCriterion(YamlMap& criteria_map, const YAML::Node& name_key,
                                  const std::string& path,
                                  const std::vector<FitExperiment>& experiments) {
  BenchmarkCriterion c;
  c.name = name_key.Scalar();
  const std::string key = criteria_map.KeyPath(c.name);
  if (!IsOutputName(c.name) || c.name == "." || c.name == ".." || c.name == "benchmark.md" ||
      c.name == "benchmark.json" || c.name == kOutputList) {
    ThrowConfigError(path, name_key, key,
                     "a criterion name of letters, digits, '_', '-', '.' (it names the "
                     "output folder; not benchmark.md, benchmark.json or " +
                         std::string(kOutputList) + ")",
                     "'" + c.name + "'");
  }
  const YAML::Node list = criteria_map.Required(c.name);
  if (!list.IsSequence() || list.size() == 0) {
    ThrowConfigError(path, list, key, "a non-empty list of names of 'experiments:' entries",
                     Describe(list));
  }
  std::set<std::string> seen;
  for (const YAML::Node& name_node : list) {
    const std::string name = name_node.IsScalar() ? name_node.Scalar() : Describe(name_node);
    if (!name_node.IsScalar() || FindExperiment(experiments, name) == nullptr) {
      ThrowConfigError(path, name_node, key,
                       "names of 'experiments:' entries (the fitted ones; 'validate:' "
                       "entries are never fitted)",
                       "'" + name + "'");
    }
    if (!seen.insert(name).second) {
      ThrowConfigError(path, name_node, key, "each experiment once", "'" + name + "' again");
    }
    c.experiments.push_back(name);
  }
  for (const FitExperiment& e : experiments) {
    if (e.estimate_initial_state && seen.count(e.name) == 0) {
      ThrowConfigError(path, list, key,
                       "every experiment with 'initial_state: estimate' (its state is "
                       "fitted, it cannot only be simulated)",
                       "a list without '" + e.name + "'");
    }
  }
  return c;
}

// `benchmark.criteria` (required, a non-empty mapping).
void ParseCriteria(YamlMap& map, const std::string& path,
                   const std::vector<FitExperiment>& experiments, BenchmarkSettings* out) {
  const YAML::Node criteria = map.Required("criteria");
  if (!criteria.IsMap() || criteria.size() == 0) {
    ThrowConfigError(path, criteria, map.KeyPath("criteria"),
                     "a non-empty mapping of criterion name -> list of fitted experiments",
                     Describe(criteria));
  }
  YamlMap criteria_map(criteria, path, map.KeyPath("criteria."));
  for (const auto& item : criteria) {
    out->criteria.push_back(ParseCriterion(criteria_map, item.first, path, experiments));
  }
}

// `benchmark.quoted` (optional): each `experiment` one of out->columns'.
void ParseQuoted(YamlMap& map, const std::string& path, BenchmarkSettings* out) {
  const YAML::Node quoted = map.Optional("quoted");
  if (!quoted) return;
  if (!quoted.IsSequence()) {
    ThrowConfigError(path, quoted, map.KeyPath("quoted"),
                     "a list of {model, value, source, experiment?}", Describe(quoted));
  }
  for (size_t k = 0; k < quoted.size(); ++k) {
    YamlMap entry(quoted[k], path, map.KeyPath("quoted[" + std::to_string(k) + "]."));
    QuotedScore q;
    q.model = entry.String("model");
    q.value = entry.Number("value", YamlMap::Range::kNonNegative);
    q.source = entry.String("source");
    if (entry.Has("experiment")) {
      q.experiment = entry.String("experiment");
      const bool named =
          std::any_of(out->columns.begin(), out->columns.end(),
                      [&](const BenchmarkColumn& c) { return c.experiment == q.experiment; });
      if (!named) {
        ThrowConfigError(path, quoted[k]["experiment"], entry.KeyPath("experiment"),
                         "the experiment of one of 'benchmark.columns'",
                         "'" + q.experiment + "'");
      }
    }
    entry.Finish();
    out->quoted.push_back(q);
  }
}

}  // namespace

void ParseBenchmark(const YAML::Node& node, const std::string& path,
                    const std::vector<FitExperiment>& experiments,
                    const std::vector<FitExperiment>& validate, BenchmarkSettings* out,
                    bool rotary) {
  YamlMap map(node, path, "benchmark.");
  out->present = true;
  out->title = map.String("title");
  ParseColumns(map, path, experiments, validate, rotary, out);
  ParseCriteria(map, path, experiments, out);
  ParseQuoted(map, path, out);
  map.Finish();
}


}  // namespace axis
