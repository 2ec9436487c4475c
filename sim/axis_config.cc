#include "sim/axis_config.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/channels.h"
#include "sim/drive_config.h"
#include "sim/effect_table.h"
#include "sim/force_map.h"
#include "sim/preflight.h"

namespace axis {

namespace {

using Range = YamlMap::Range;

const std::vector<std::string> kAmplifiers = {
    "analog_velocity_loop", "current_source", "force_source", "voltage_drive"};
const std::vector<std::string> kMotions = {"linear", "rotary"};
const std::vector<std::string> kLoads = {"none", "gravity", "pendulum"};
const std::vector<std::string> kCouplings = {"gear", "rigid"};
const std::vector<std::string> kAccelerometer = {"period_mean", "instant"};
const std::vector<std::string> kCurrentLoops = {"full", "quasi_steady"};

Amplifier ParseAmplifier(const std::string& s) {
  if (s == "current_source") return Amplifier::kCurrentSource;
  if (s == "force_source") return Amplifier::kForceSource;
  if (s == "voltage_drive") return Amplifier::kVoltageDrive;
  return Amplifier::kAnalogVelocityLoop;
}

Motion ParseMotion(const std::string& s) {
  return s == "rotary" ? Motion::kRotary : Motion::kLinear;
}

LoadTerm ParseLoad(const std::string& s) {
  if (s == "gravity") return LoadTerm::kGravity;
  if (s == "pendulum") return LoadTerm::kPendulum;
  return LoadTerm::kNone;
}

Coupling ParseCoupling(const std::string& s) {
  return s == "rigid" ? Coupling::kRigid : Coupling::kGear;
}

CurrentLoop ParseCurrentLoop(const std::string& s) {
  return s == "quasi_steady" ? CurrentLoop::kQuasiSteady : CurrentLoop::kFull;
}

AccelerometerSampling ParseAccelerometer(const std::string& s) {
  return s == "instant" ? AccelerometerSampling::kInstant
                        : AccelerometerSampling::kPeriodMean;
}

// Parameters a configuration needs (MODEL.md §2–4): the ones the equations
// of that configuration read.
std::vector<std::string> RequiredParams(const AxisStructure& s) {
  std::vector<std::string> out = {"M", "B_a"};
  const bool force = s.amplifier == Amplifier::kForceSource;
  if (force) {
    out.push_back("g_F");
  } else if (s.amplifier == Amplifier::kVoltageDrive) {
    for (const char* n : {"r_g", "J_m", "B_m", "K_tau", "K_e", "R"}) out.push_back(n);
    if (s.inductance) out.push_back("L");
  } else {
    for (const char* n : {"r_g", "J_m", "B_m", "K_tau", "K_t", "T_z", "T_p",
                          "T_r", "K1", "K2", "K_i", "V_L"}) {
      out.push_back(n);
    }
    if (s.amplifier == Amplifier::kAnalogVelocityLoop) {
      for (const char* n : {"R", "L", "K_e", "V_M", "K_a"}) out.push_back(n);
    }
  }
  if (s.coupling == Coupling::kGear) {
    for (const char* n : {"H", "k_g", "b_g"}) out.push_back(n);
  }
  if (s.load == LoadTerm::kGravity) out.push_back("m_g");
  if (s.load == LoadTerm::kPendulum) {
    out.push_back("m_p");
    out.push_back("l_p");
  }
  return out;
}



void ParseParameters(YamlMap& map, AxisConfig* config) {
  std::set<std::string> given;
  for (const auto& entry : map.node()) given.insert(entry.first.Scalar());
  VisitParams([&](const char* name, const char*, double& field) {
    if (!given.count(name)) return;
    field = map.Number(name, ParamRange(name));
  }, config->params);
  for (const std::string& name : RequiredParams(config->structure)) {
    if (!given.count(name)) {
      ThrowConfigError(map.file(), map.node(), map.KeyPath(name),
                       "a value (required by this amplifier and coupling)",
                       "nothing");
    }
  }
  map.Finish();
}

// A list of numbers under `key` of `map` (at least one).
std::vector<double> NumberList(YamlMap& map, const std::string& key) {
  const YAML::Node list = map.Required(key);
  if (!list.IsSequence() || list.size() == 0) {
    ThrowConfigError(map.file(), list, map.KeyPath(key), "a list of numbers", Describe(list));
  }
  std::vector<double> out;
  for (const YAML::Node& item : list) {
    out.push_back(map.NumberFrom(item, map.KeyPath(key), Range::kAny));
  }
  return out;
}

// `force_map: {variable: x|v, friction: bool, knots: [...], values: [...]}`
// (MODEL.md §7, sim/force_map.h).
void ParseForceMap(YamlMap& map, AxisConfig* config) {
  ForceMap& f = config->structure.force_map;
  f.enabled = true;
  f.variable = map.Choice("variable", {"x", "v"}) == "v" ? ForceMapVariable::kV
                                                          : ForceMapVariable::kX;
  f.friction = map.Choice("friction", {"false", "true"}, "false") == "true";
  if (f.friction && f.variable == ForceMapVariable::kV) {
    ThrowConfigError(map.file(), map.Optional("friction"), map.KeyPath("friction"),
                     "false with variable v (f(v) is already a friction law)", "true");
  }
  f.knots = NumberList(map, "knots");
  const KnotsProblem problem = ForceMapKnotsProblem(f.knots);
  if (!problem.ok()) {
    ThrowConfigError(map.file(), map.Optional("knots"), map.KeyPath("knots"), problem.expected,
                     problem.got);
  }
  const std::vector<double> values = NumberList(map, "values");
  if (values.size() != f.knots.size()) {
    ThrowConfigError(map.file(), map.Optional("values"), map.KeyPath("values"),
                     "one value (N) per knot (" + std::to_string(f.knots.size()) + ")",
                     std::to_string(values.size()) + " values");
  }
  config->params.f_map.fill(0.0);
  for (size_t k = 0; k < values.size(); ++k) config->params.f_map[k] = values[k];
  map.Finish();
}

// `sensor_<kind>: {<channel>: value, ...}` (MODEL.md §7): the effect's
// parameter on each named channel; sensor_lowpass2 takes τ alone (ζ = 1/√2)
// or `{tau: τ, zeta: ζ}`.
void ParseSensorEffect(YamlMap& map, const SensorEffectInfo& effect, AxisConfig* config) {
  for (const auto& entry : map.node()) {
    const std::string channel_name = entry.first.Scalar();
    const auto channel = ParseChannel(channel_name);
    if (!channel || *channel == Channel::kT) {
      ThrowConfigError(map.file(), entry.first, map.KeyPath(channel_name),
                       "a channel name (" + ChannelNameList() + ", not t)",
                       "'" + channel_name + "'");
    }
    (config->structure.sensors.*(effect.flag))[static_cast<int>(*channel)] = true;
    config->declared.insert(std::string(effect.name) + "." + channel_name);
    const std::string suffix = "." + channel_name;
    if (effect.params.size() == 1) {
      const std::string name = effect.params[0] + suffix;
      *FindParam(&config->params, name) = map.Number(channel_name, ParamRange(name));
      continue;
    }
    // sensor_lowpass2: τ, or {tau, zeta}.
    const std::string tau = effect.params[0] + suffix;
    const std::string zeta = effect.params[1] + suffix;
    if (!map.node()[channel_name].IsMap()) {
      *FindParam(&config->params, tau) = map.Number(channel_name, ParamRange(tau));
      continue;
    }
    YamlMap body(map.Optional(channel_name), map.file(), map.KeyPath(channel_name) + ".");
    *FindParam(&config->params, tau) = body.Number("tau", ParamRange(tau));
    *FindParam(&config->params, zeta) =
        body.Number("zeta", *FindParam(&config->params, zeta), ParamRange(zeta));
    body.Finish();
  }
  map.Finish();
}

}  // namespace

Channel ChannelOrThrow(const std::string& name, const YamlMap& map,
                       const YAML::Node& node, const std::string& key) {
  const auto c = ParseChannel(name);
  if (!c || *c == Channel::kT) {
    ThrowConfigError(map.file(), node, key,
                     "a channel name of MODEL.md section 6 (" +
                         ChannelNameList() + ", not t)",
                     "'" + name + "'");
  }
  return *c;
}

Range ParamRange(const std::string& name) {
  static const std::set<std::string> positive = {
      "L", "J_m", "r_g", "M", "T_p", "T_r", "K_i", "V_M", "K_a",
      "w", "v_eps", "omega_eps", "v_st", "delta_st"};
  static const std::set<std::string> non_negative = {
      "R", "B_m", "H", "T_z", "B_a", "b_g", "k_g", "F_s", "Delta_M", "m_g", "m_p", "l_p", "mu_d", "mu_b"};
  if (name == "w_pt" || name == "lambda_rp" || name == "w_vb") return Range::kFinitePositive;
  if (name == "v_vb") return Range::kNonNegative;
  if (name == "V_L") return Range::kPositiveOrInfinite;  // .inf: no preamp limit
  if (positive.count(name)) return Range::kPositive;
  if (non_negative.count(name)) return Range::kNonNegative;
  // tau_d: either sign (a skew between channels); the filters' time
  // constants ≥ 0 (0: off); their damping > 0.
  if (name.rfind("tau_lp.", 0) == 0 || name.rfind("tau_lp2.", 0) == 0) {
    return Range::kNonNegative;
  }
  if (name.rfind("zeta_lp2.", 0) == 0) return Range::kFinitePositive;
  return Range::kAny;
}

void ParseEffects(YamlMap& effects, AxisConfig* config) {
  for (const auto& entry : effects.node()) {
    const std::string name = entry.first.Scalar();
    YamlMap body(effects.Optional(name), effects.file(),
                 effects.KeyPath(name) + ".");
    const SensorEffectInfo* sensor = nullptr;
    for (const SensorEffectInfo& e : SensorEffectTable()) {
      if (name == e.name) sensor = &e;
    }
    if (sensor != nullptr) {
      ParseSensorEffect(body, *sensor, config);
      continue;
    }
    if (name == "force_map") {
      ParseForceMap(body, config);
      continue;
    }
    const EffectInfo* spec = nullptr;
    for (const auto* table : {&DynamicEffectTable(), &GeneratorOnlyEffectTable()}) {
      for (const EffectInfo& e : *table) {
        if (name == e.name) spec = &e;
      }
    }
    if (spec == nullptr) {
      std::string known;
      for (const EffectInfo& e : DynamicEffectTable()) known += std::string(e.name) + ", ";
      for (const SensorEffectInfo& e : SensorEffectTable()) known += std::string(e.name) + ", ";
      known += "force_map; or, to generate data, " +
               GeneratorOnlyEffectNameList();
      ThrowConfigError(effects.file(), entry.first, effects.KeyPath(name),
                       "an effect of MODEL.md section 7 (" + known + ")",
                       "'" + name + "'");
    }
    config->structure.effects.*(spec->flag) = true;
    for (const char* p : spec->params) {
      *FindParam(&config->params, p) = body.Number(p, ParamRange(p));
    }
    if (name == "friction_patch" && !(config->params.x_pt1 > config->params.x_pt0)) {
      std::ostringstream got;
      got << config->params.x_pt1 << " (x_pt0 " << config->params.x_pt0 << ")";
      ThrowConfigError(effects.file(), body.Optional("x_pt1"), body.KeyPath("x_pt1"),
                       "a patch end above x_pt0", got.str());
    }
    // `stribeck: {…, delta_st}` declares the shape exponent as
    // `stribeck_shape: {delta_st}` does.
    if (name == "stribeck" && body.Has("delta_st")) {
      config->params.delta_st = body.Number("delta_st", ParamRange("delta_st"));
      config->structure.effects.stribeck_shape = true;
    }
    if (name == "cogging") {
      config->structure.N_cog =
          static_cast<int>(body.Integer("N_cog", config->structure.N_cog, 1, 10000));
    }
    body.Finish();
  }
}

void ValidateAxisConfig(const AxisConfig& config, const std::string& where) {
  AxisParams<double> p = config.params;
  VisitParams([&](const char* name, const char*, double& value) {
    const Range r = ParamRange(name);
    if (!InRange(value, r)) {
      throw std::invalid_argument(where + ": parameter '" + name +
                                  "': expected " + RangeText(r) + ", got " +
                                  NumberText(value));
    }
  }, p);
  if (config.structure.amplifier == Amplifier::kForceSource &&
      config.structure.coupling != Coupling::kRigid) {
    throw std::invalid_argument(
        where + ": key 'coupling': expected rigid with amplifier "
                "force_source (there is no motor to couple), got gear");
  }
  if (!(config.structure.instant_window > 0.0 && config.structure.instant_window <= 1.0)) {
    throw std::invalid_argument(where + ": key 'instant_window': expected a half-window in s, "
                                        "> 0 and at most 1, got " +
                                NumberText(config.structure.instant_window));
  }
  const AxisStructure& s = config.structure;
  if (s.amplifier == Amplifier::kVoltageDrive && !(config.params.R > 0.0)) {
    throw std::invalid_argument(where + ": parameter 'R': expected a winding resistance > 0 "
                                        "with amplifier voltage_drive (i = (U - K_e*omega)/R), "
                                        "got " + NumberText(config.params.R));
  }
  if (s.effects.load_friction && s.amplifier == Amplifier::kForceSource) {
    throw std::invalid_argument(where + ": key 'effects.load_friction': expected a drive with a "
                                        "motor (its current makes the force the gearbox "
                                        "transmits), got amplifier force_source");
  }
  if (s.effects.stribeck_shape && !s.effects.stribeck) {
    throw std::invalid_argument(where + ": key 'effects.stribeck_shape': expected the Stribeck "
                                        "term it shapes (effects.stribeck), got none");
  }
  if (s.load == LoadTerm::kPendulum && s.motion != Motion::kRotary) {
    throw std::invalid_argument(where + ": key 'load': expected motion: rotary with a pendulum "
                                        "(its angle is the load's position), got motion: linear");
  }
  if (s.load == LoadTerm::kGravity && s.motion != Motion::kLinear) {
    throw std::invalid_argument(where + ": key 'load': expected motion: linear with gravity (a "
                                        "vertical axis lifting m_g; a rotary joint under gravity "
                                        "is load: pendulum), got motion: rotary");
  }
  if (s.inductance && s.amplifier != Amplifier::kVoltageDrive) {
    throw std::invalid_argument(
        where + ": key 'inductance': expected false with an amplifier other than voltage_drive "
                "(the analog velocity loop's current is its own state y6, a current or force "
                "source has none), got true");
  }
  if (config.structure.current_loop == CurrentLoop::kQuasiSteady &&
      config.structure.amplifier != Amplifier::kAnalogVelocityLoop) {
    throw std::invalid_argument(
        where + ": key 'current_loop': expected full with an amplifier other than "
                "analog_velocity_loop (only that one has a current loop), got quasi_steady");
  }
}

AxisConfig LoadAxisConfig(const std::string& path) {
  return ParseAxisConfig(LoadYamlFile(path), path);
}

AxisConfig ParseAxisConfig(const YAML::Node& document, const std::string& path) {
  AxisConfig config;
  config.path = path;
  YamlMap root(document, path, "");
  config.name = root.String("name");
  config.source = root.String("source", "");
  root.String("description", "");
  config.structure.amplifier = ParseAmplifier(root.Choice("amplifier", kAmplifiers));
  config.structure.coupling = ParseCoupling(root.Choice("coupling", kCouplings));
  config.structure.current_loop =
      ParseCurrentLoop(root.Choice("current_loop", kCurrentLoops, "full"));
  config.structure.inductance = root.Choice("inductance", {"true", "false"}, "false") == "true";
  if (root.Has("accelerometer")) config.declared.insert("accelerometer");
  config.structure.accelerometer =
      ParseAccelerometer(root.Choice("accelerometer", kAccelerometer, "period_mean"));
  config.structure.instant_window =
      root.Number("instant_window", config.structure.instant_window, YamlMap::Range::kPositive);
  config.structure.motion = ParseMotion(root.Choice("motion", kMotions, "linear"));
  config.structure.load = ParseLoad(root.Choice("load", kLoads, "none"));
  YamlMap params(root.Required("parameters"), path, "parameters.");
  ParseParameters(params, &config);
  if (const YAML::Node effects = root.Optional("effects")) {
    YamlMap map(effects, path, "effects.");
    ParseEffects(map, &config);
  }
  if (const YAML::Node controller = root.Optional("controller")) {
    YamlMap map(controller, path, "controller.");
    config.controller = ParseController(map, ControllerConfig{});
    config.has_controller = true;
  }
  root.Finish();
  ValidateAxisConfig(config, path);
  return config;
}

void SetParam(AxisConfig* config, const std::string& name, double value,
              const std::string& where) {
  double* field = FindParam(&config->params, name);
  if (field == nullptr) {
    std::string names;
    for (const ParamInfo& info : ListParams()) {
      if (info.name.find('.') != std::string::npos) continue;
      names += (names.empty() ? "" : ", ") + info.name;
    }
    throw std::invalid_argument(where + ": expected a parameter name of the "
                                "model (" + names + ", tau_d.<channel>, "
                                "b.<channel>, f_map.<k>), got '" + name + "'");
  }
  *field = value;
}

void ApplySetArgument(AxisConfig* config, const std::string& assignment) {
  const size_t eq = assignment.find('=');
  const std::string where = "--set " + assignment;
  if (eq == std::string::npos || eq == 0) {
    throw std::invalid_argument(where + ": expected NAME=VALUE, got '" +
                                assignment + "'");
  }
  const std::string name = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end == nullptr || *end != '\0' || std::isnan(value)) {
    throw std::invalid_argument(where + ": expected a number after '=', got '" +
                                text + "'");
  }
  SetParam(config, name, value, where);
  ValidateAxisConfig(*config, where);
}

AxisState<double> ConsistentInitialState(const AxisConfig& config,
                                         const AxisState<double>& y) {
  AxisState<double> out = y;
  if (config.structure.coupling == Coupling::kRigid) {
    out[2] = y[0] / config.params.r_g;
    out[3] = y[1] / config.params.r_g;
  }
  return out;
}

void ParseModelOverrides(YamlMap& root, AxisConfig* model) {
  const std::string& path = root.file();
  const bool inductive_before = model->structure.inductance;
  YAML::Node inductance_node;  // where `configuration: {inductance: …}` is, if given
  bool sets_inductance_value = false;
  if (const YAML::Node node = root.Optional("configuration")) {
    YamlMap map(node, path, "configuration.");
    if (map.Has("amplifier")) {
      model->structure.amplifier = ParseAmplifier(map.Choice("amplifier", kAmplifiers));
    }
    if (map.Has("coupling")) {
      model->structure.coupling = ParseCoupling(map.Choice("coupling", kCouplings));
    }
    if (map.Has("motion")) model->structure.motion = ParseMotion(map.Choice("motion", kMotions));
    if (map.Has("load")) model->structure.load = ParseLoad(map.Choice("load", kLoads));
    if (map.Has("current_loop")) {
      model->structure.current_loop = ParseCurrentLoop(map.Choice("current_loop", kCurrentLoops));
    }
    if (map.Has("inductance")) {
      inductance_node = node;
      model->structure.inductance = map.Choice("inductance", {"true", "false"}) == "true";
    }
    if (map.Has("accelerometer")) {
      model->declared.insert("accelerometer");
      model->structure.accelerometer =
          ParseAccelerometer(map.Choice("accelerometer", kAccelerometer));
    }
    if (map.Has("instant_window")) {
      model->structure.instant_window =
          map.Number("instant_window", YamlMap::Range::kPositive);
    }
    map.Finish();
  }
  if (const YAML::Node node = root.Optional("effects")) {
    YamlMap map(node, path, "effects.");
    ParseEffects(map, model);
  }
  if (const YAML::Node node = root.Optional("set")) {
    YamlMap map(node, path, "set.");
    for (const auto& entry : node) {
      const std::string name = entry.first.Scalar();
      if (name == "L") sets_inductance_value = true;
      if (FindParam(&model->params, name) == nullptr) {
        ThrowConfigError(path, entry.first, "set." + name,
                         "a parameter name of the model (MODEL.md sections 2 "
                         "and 7, e.g. V_L, B_a, k_g)",
                         "'" + name + "'");
      }
      // .inf only where the parameter's range has it (V_L: no limit); the
      // range itself is checked with the others by ValidateAxisConfig.
      const Range range = ParamRange(name);
      *FindParam(&model->params, name) =
          map.Number(name, range == Range::kPositiveOrInfinite ? range : Range::kAny);
    }
    map.Finish();
  }
  // Switched on here, the inductance needs its value here too: the model
  // config that left it off was not asked for L (RequiredParams), and L's
  // default is the X axis motor's.
  if (!inductive_before && model->structure.inductance && !sets_inductance_value) {
    ThrowConfigError(path, inductance_node, root.KeyPath("configuration.inductance"),
                     "set: {L: <armature inductance, H>} beside it (the model config "
                     "switches the inductance off and need not give L)",
                     "true without set.L");
  }
  ValidateAxisConfig(*model, path);
}

}  // namespace axis
