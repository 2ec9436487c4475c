#include "run/campaign_settings.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "common/format.h"
#include "sim/config.h"
#include "io/yaml_util.h"

namespace axis {
namespace {

using Range = YamlMap::Range;

// A campaign file's keys as a sequence of named steps, one per key group,
// in the order their checks run, then the checks against the job file and
// the generating configs.
class CampaignSettingsParser {
 public:
  // `path` must outlive the parser. Throws as LoadYamlFile and YamlMap.
  explicit CampaignSettingsParser(const std::string& path)
      : path_(path), root_(LoadYamlFile(path)), dir_(DirectoryOf(path)), map_(root_, path, "") {
    c_.path = path;
  }
  CampaignSettingsParser(const CampaignSettingsParser&) = delete;
  CampaignSettingsParser& operator=(const CampaignSettingsParser&) = delete;

  CampaignConfig Parse(std::vector<YAML::Node>* truth_value_keys);

 private:
  void ParseGenerate();
  void ParseSeeds();
  void ParseDiscover();
  void ParseTruth();
  void ParseTruthEffects(YamlMap& t);
  void ParseTruthValues(YamlMap& t);
  void ParseOutsideLibrary(YamlMap& t);
  void ParseOutput();
  // The job: no `benchmark:`, its experiments those of `generate:`.
  void CheckJob();
  void CheckOutsideSwitchedOn();

  const std::string& path_;
  const YAML::Node root_;
  const std::string dir_;
  CampaignConfig c_;
  YamlMap map_;
  YAML::Node generate_;  // generate:
  // truth.outside_library: each force and its node, for messages.
  std::vector<std::pair<const EffectInfo*, YAML::Node>> outside_nodes_;
  std::vector<YAML::Node> truth_value_keys_;  // of c_.truth_values, for messages
};

CampaignConfig CampaignSettingsParser::Parse(std::vector<YAML::Node>* truth_value_keys) {
  c_.title = map_.String("title", path_);
  c_.job_path = ResolvePath(dir_, map_.String("job"));
  ParseGenerate();
  ParseSeeds();
  ParseDiscover();
  ParseTruth();
  ParseOutput();
  map_.Finish();
  // The job and the generating configs load now, so that a campaign cannot
  // fail on input after hours of fitting.
  CheckJob();
  CheckOutsideSwitchedOn();
  *truth_value_keys = std::move(truth_value_keys_);
  return std::move(c_);
}

void CampaignSettingsParser::ParseGenerate() {
  const YAML::Node generate = map_.Required("generate");
  if (!generate.IsMap() || generate.size() == 0) {
    ThrowConfigError(path_, generate, "generate",
                     "a mapping of experiment name to generating config", Describe(generate));
  }
  for (const auto& entry : generate) {
    const std::string name = entry.first.Scalar();
    if (!entry.second.IsScalar()) {
      ThrowConfigError(path_, entry.second, "generate." + name,
                       "the path of an experiment config", Describe(entry.second));
    }
    c_.generate.emplace_back(name, ResolvePath(dir_, entry.second.Scalar()));
  }
  generate_ = generate;
}

void CampaignSettingsParser::ParseSeeds() {
  YamlMap seeds(map_.Required("seeds"), path_, "seeds.");
  c_.first_seed = static_cast<int>(seeds.Integer("first", 1, 0, kMaxCampaignSeed));
  c_.last_seed = static_cast<int>(seeds.Integer("last", c_.first_seed, 0, kMaxCampaignSeed));
  if (c_.last_seed < c_.first_seed) {
    ThrowConfigError(path_, seeds.Optional("last"), "seeds.last",
                     "a seed at or above seeds.first = " + std::to_string(c_.first_seed),
                     std::to_string(c_.last_seed));
  }
  seeds.Finish();
}

void CampaignSettingsParser::ParseDiscover() {
  if (const YAML::Node d = map_.Optional("discover")) {
    if (!d.IsScalar() || (d.Scalar() != "true" && d.Scalar() != "false")) {
      ThrowConfigError(path_, d, "discover", "true or false", Describe(d));
    }
    c_.discover = d.Scalar() == "true";
  }
}

void CampaignSettingsParser::ParseTruth() {
  const YAML::Node truth = map_.Optional("truth");
  if (!truth) return;
  YamlMap t(truth, path_, "truth.");
  ParseTruthEffects(t);
  ParseTruthValues(t);
  if (t.Has("verdict")) c_.truth_verdict = t.Choice("verdict", {"explained", "incomplete"});
  ParseOutsideLibrary(t);
  t.Finish();
}

void CampaignSettingsParser::ParseTruthEffects(YamlMap& t) {
  const YAML::Node effects = t.Optional("effects");
  if (!effects) return;
  if (!effects.IsSequence()) {
    ThrowConfigError(path_, effects, "truth.effects", "a list of effect names",
                     Describe(effects));
  }
  for (const YAML::Node& e : effects) {
    const std::string name = e.IsScalar() ? e.Scalar() : "";
    if (!IsEffectName(name)) {
      ThrowConfigError(path_, e, "truth.effects",
                       "an effect of MODEL.md section 7 (" + EffectNameList() + ")",
                       Describe(e));
    }
    c_.truth_effects.push_back(name);
  }
  std::sort(c_.truth_effects.begin(), c_.truth_effects.end());
}

void CampaignSettingsParser::ParseTruthValues(YamlMap& t) {
  const YAML::Node values = t.Optional("values");
  if (!values) return;
  if (!values.IsMap()) {
    ThrowConfigError(path_, values, "truth.values",
                     "a mapping of parameter name to true value", Describe(values));
  }
  YamlMap v(values, path_, "truth.values.");
  for (const auto& entry : values) {
    const std::string name = entry.first.Scalar();
    c_.truth_values.emplace_back(name, v.Number(name, Range::kAny));
    truth_value_keys_.push_back(entry.first);
  }
  v.Finish();
}

void CampaignSettingsParser::ParseOutsideLibrary(YamlMap& t) {
  const YAML::Node outside = t.Optional("outside_library");
  if (!outside) return;
  const std::string names = GeneratorOnlyEffectNameList();
  if (!outside.IsSequence()) {
    ThrowConfigError(path_, outside, "truth.outside_library",
                     "a list of generator-only forces (" + names + ")", Describe(outside));
  }
  for (const YAML::Node& e : outside) {
    const std::string name = e.IsScalar() ? e.Scalar() : "";
    const auto known =
        std::find_if(GeneratorOnlyEffectTable().begin(), GeneratorOnlyEffectTable().end(),
                     [&](const EffectInfo& g) { return name == g.name; });
    if (known == GeneratorOnlyEffectTable().end()) {
      ThrowConfigError(path_, e, "truth.outside_library",
                       "a generator-only force (" + names + ")", Describe(e));
    }
    outside_nodes_.emplace_back(&*known, e);
    c_.truth_outside.push_back(name);
  }
  std::sort(c_.truth_outside.begin(), c_.truth_outside.end());
}

void CampaignSettingsParser::ParseOutput() {
  if (const YAML::Node output = map_.Optional("output")) {  // else fit-campaign --out
    YamlMap out(output, path_, "output.");
    c_.out_dir = OutputDirectory(&out, dir_);
    out.Finish();
  }
}

void CampaignSettingsParser::CheckJob() {
  const YAML::Node generate = generate_;
  YAML::Node job_root = LoadYamlFile(c_.job_path);
  if (const YAML::Node benchmark = job_root["benchmark"]) {
    ThrowConfigError(c_.job_path, benchmark, "benchmark",
                     "a job without 'benchmark:' (its criteria are run by fit-params, not by "
                     "a campaign)",
                     "one");
  }
  const auto experiments = JobExperiments(job_root);
  for (const auto& experiment : experiments) {
    const std::string& name = experiment.first;
    const bool has = std::any_of(c_.generate.begin(), c_.generate.end(),
                                 [&](const auto& g) { return g.first == name; });
    if (!has) {
      ThrowConfigError(path_, generate, "generate",
                       "a generating config for experiment '" + name + "' of " + c_.job_path,
                       "none");
    }
  }
  for (const auto& generating : c_.generate) {
    const std::string& name = generating.first;
    const bool in_job = std::any_of(experiments.begin(), experiments.end(),
                                    [&](const auto& e) { return e.first == name; });
    if (!in_job) {
      ThrowConfigError(path_, generate[name], "generate." + name,
                       "the name of an experiment of " + c_.job_path, "'" + name + "'");
    }
  }
}

// A force outside the library that no generating config switches on
// would make the campaign measure something else.
// Each generating config is read once here (CampaignSeedJob, run/campaign.cc,
// reads them again, as every seed does).
void CampaignSettingsParser::CheckOutsideSwitchedOn() {
  EffectSwitches switched_on;
  if (!outside_nodes_.empty()) {
    for (const auto& generating : c_.generate) {
      const EffectSwitches e = LoadExperiment(generating.second).model.structure.effects;
      for (const EffectInfo& g : GeneratorOnlyEffectTable()) {
        switched_on.*(g.flag) = switched_on.*(g.flag) || e.*(g.flag);
      }
    }
  }
  for (const auto& outside : outside_nodes_) {
    const std::string name = outside.first->name;
    const YAML::Node& node = outside.second;
    if (!(switched_on.*(outside.first->flag))) {
      ThrowConfigError(path_, node, "truth.outside_library",
                       "a force that a generating config switches on (effects." + name + ")",
                       "'" + name + "', in none of them");
    }
  }
}

}  // namespace

std::vector<std::pair<std::string, YAML::Node>> JobExperiments(YAML::Node root) {
  std::vector<std::pair<std::string, YAML::Node>> out;
  for (const char* key : {"experiments", "validate"}) {
    const YAML::Node list = root[key];
    if (!list || !list.IsSequence()) continue;
    for (YAML::Node e : list) {
      if (e.IsMap() && e["name"] && e["name"].IsScalar()) out.emplace_back(e["name"].Scalar(), e);
    }
  }
  return out;
}

CampaignConfig LoadCampaignSettings(const std::string& path,
                                    std::vector<YAML::Node>* truth_value_keys) {
  return CampaignSettingsParser(path).Parse(truth_value_keys);
}

void CheckTruthValues(const CampaignConfig& c, const std::vector<std::string>& free_names,
                      const std::vector<std::string>& effect_names,
                      const std::vector<YAML::Node>& truth_value_keys) {
  for (size_t k = 0; k < c.truth_values.size(); ++k) {
    const std::string& name = c.truth_values[k].first;
    const auto has = [&](const std::vector<std::string>& list) {
      return std::find(list.begin(), list.end(), name) != list.end();
    };
    if (has(free_names) || has(effect_names)) continue;
    std::string expected = "a free parameter of " + c.job_path + " (" + Join(free_names, ", ") + ")";
    if (!effect_names.empty()) {
      expected += " or of an effect of truth.effects (" + Join(effect_names, ", ") + ")";
    }
    ThrowConfigError(c.path, truth_value_keys[k], "truth.values." + name, expected,
                     "'" + name + "'");
  }
}

}  // namespace axis
