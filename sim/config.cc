#include "sim/config.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "sim/csv.h"
#include "sim/data_table.h"
#include "sim/preflight.h"

namespace axis {
namespace {

using Range = YamlMap::Range;

const std::vector<std::string> kAmplifiers = {
    "analog_velocity_loop", "current_source", "force_source"};
const std::vector<std::string> kCouplings = {"gear", "rigid"};
const std::vector<std::string> kAccelerometer = {"period_mean", "instant"};
const std::vector<std::string> kCurrentLoops = {"full", "quasi_steady"};

Amplifier ParseAmplifier(const std::string& s) {
  if (s == "current_source") return Amplifier::kCurrentSource;
  if (s == "force_source") return Amplifier::kForceSource;
  return Amplifier::kAnalogVelocityLoop;
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
  return out;
}


std::string FormatNumber(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
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

Range ParamRange(const std::string& name) {
  static const std::set<std::string> positive = {
      "L", "J_m", "r_g", "M", "T_p", "T_r", "K_i", "V_M", "K_a",
      "w", "v_eps", "omega_eps", "v_st"};
  static const std::set<std::string> non_negative = {
      "R", "B_m", "H", "T_z", "B_a", "b_g", "k_g", "F_s", "Delta_M"};
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

const std::vector<EffectInfo>& DynamicEffectTable() {
  static const std::vector<EffectInfo> effects = {
      {"coulomb", {"F_c"}, &EffectSwitches::coulomb},
      {"stribeck", {"F_st", "v_st"}, &EffectSwitches::stribeck},
      {"viscous_asymmetry", {"Delta_B"}, &EffectSwitches::viscous_asymmetry},
      {"load_offset", {"F_0"}, &EffectSwitches::load_offset},
      {"spring", {"k_x", "x_0"}, &EffectSwitches::spring},
      {"payload", {"Delta_M"}, &EffectSwitches::payload},
      {"motor_coulomb", {"T_c"}, &EffectSwitches::motor_coulomb},
      {"cogging", {"A_cog", "phi_cog"}, &EffectSwitches::cogging},
  };
  return effects;
}

const std::vector<EffectInfo>& GeneratorOnlyEffectTable() {
  static const std::vector<EffectInfo> effects = {
      {"friction_patch", {"F_pt", "x_pt0", "x_pt1", "w_pt"}, &EffectSwitches::friction_patch},
      {"quadratic_drag", {"C_d"}, &EffectSwitches::quadratic_drag},
      {"position_ripple", {"F_rp", "lambda_rp", "phi_rp"}, &EffectSwitches::position_ripple},
      {"velocity_bump", {"F_vb", "v_vb", "w_vb"}, &EffectSwitches::velocity_bump},
  };
  return effects;
}

bool IsEffectName(const std::string& name, bool allow_bare_sensor) {
  const size_t dot = name.find('.');
  const std::string effect = name.substr(0, dot);
  for (const SensorEffectInfo& e : SensorEffectTable()) {
    if (effect != e.name) continue;
    if (dot == std::string::npos) return allow_bare_sensor;
    return ParseChannel(name.substr(dot + 1)).has_value();
  }
  if (dot != std::string::npos) return false;
  for (const EffectInfo& e : DynamicEffectTable()) {
    if (effect == e.name) return true;
  }
  return false;
}

bool IsFrontEndEffect(const std::string& name) {
  const std::string effect = name.substr(0, name.find('.'));
  if (effect == "accelerometer") return true;
  for (const SensorEffectInfo& e : SensorEffectTable()) {
    if (effect == e.name) return true;
  }
  return false;
}

std::string GeneratorOnlyEffectNameList() {
  std::string list;
  for (const EffectInfo& e : GeneratorOnlyEffectTable()) {
    list += (list.empty() ? "" : ", ") + std::string(e.name);
  }
  return list;
}

std::vector<std::string> EnabledEffectNames(const AxisStructure& s) {
  std::vector<std::string> out;
  for (const EffectInfo& e : DynamicEffectTable()) {
    if (s.effects.*(e.flag)) out.push_back(e.name);
  }
  for (int c = 0; c < kNumChannels; ++c) {
    const std::string channel = ChannelName(static_cast<Channel>(c));
    for (const SensorEffectInfo& e : SensorEffectTable()) {
      if ((s.sensors.*(e.flag))[static_cast<size_t>(c)]) out.push_back(e.name + ("." + channel));
    }
  }
  if (s.force_map.enabled) out.push_back("force_map." + ForceMapKind(s.force_map));
  return out;
}

std::string EffectNameList() {
  std::string list;
  for (const EffectInfo& e : DynamicEffectTable()) list += std::string(e.name) + ", ";
  for (const SensorEffectInfo& e : SensorEffectTable()) {
    list += e.name + std::string("[.channel]") + (&e == &SensorEffectTable().back() ? "" : ", ");
  }
  return list;
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
    if (name == "cogging") {
      config->structure.N_cog =
          static_cast<int>(body.Integer("N_cog", config->structure.N_cog, 1, 10000));
    }
    body.Finish();
  }
}

namespace {

// The `effects:` block of AxisConfigToYaml (none if nothing is switched
// on): each switched effect with its parameters, the force map, the sensor
// delays and biases. `params`: a copy of config.params (FindParam reads
// through a mutable pointer).
void EmitEffects(const AxisConfig& config, AxisParams<double>& params, YAML::Emitter& out) {
  const EffectSwitches& sw = config.structure.effects;
  const SensorSwitches& sensors = config.structure.sensors;
  bool any_sensor = false;
  for (const SensorEffectInfo& e : SensorEffectTable()) {
    for (bool on : sensors.*(e.flag)) any_sensor = any_sensor || on;
  }
  bool any = any_sensor || config.structure.force_map.enabled;
  std::vector<const EffectInfo*> switched;
  for (const auto* table : {&DynamicEffectTable(), &GeneratorOnlyEffectTable()}) {
    for (const EffectInfo& e : *table) {
      if (sw.*(e.flag)) switched.push_back(&e);
    }
  }
  any = any || !switched.empty();
  if (!any) return;
  out << YAML::Key << "effects" << YAML::Value << YAML::BeginMap;
  for (const EffectInfo* effect : switched) {
    const EffectInfo& e = *effect;
    out << YAML::Key << e.name << YAML::Value << YAML::BeginMap;
    for (const char* p : e.params) {
      out << YAML::Key << p << YAML::Value << *FindParam(&params, p);
    }
    if (std::string(e.name) == "cogging") {
      out << YAML::Key << "N_cog" << YAML::Value << config.structure.N_cog;
    }
    out << YAML::EndMap;
  }
  if (config.structure.force_map.enabled) {
    const ForceMap& f = config.structure.force_map;
    out << YAML::Key << "force_map" << YAML::Value << YAML::BeginMap << YAML::Key
        << "variable" << YAML::Value << (f.variable == ForceMapVariable::kV ? "v" : "x")
        << YAML::Key << "friction" << YAML::Value << (f.friction ? "true" : "false")
        << YAML::Key << "knots" << YAML::Value << YAML::Flow << f.knots << YAML::Key
        << "values" << YAML::Value << YAML::Flow
        << std::vector<double>(params.f_map.begin(), params.f_map.begin() + f.knots.size())
        << YAML::EndMap;
  }
  for (const SensorEffectInfo& e : SensorEffectTable()) {
    const std::array<bool, kNumChannels>& on = sensors.*(e.flag);
    if (std::find(on.begin(), on.end(), true) == on.end()) continue;
    out << YAML::Key << e.name << YAML::Value << YAML::BeginMap;
    for (int c = 0; c < kNumChannels; ++c) {
      if (!on[c]) continue;
      const std::string suffix = std::string(".") + ChannelName(static_cast<Channel>(c));
      out << YAML::Key << ChannelName(static_cast<Channel>(c)) << YAML::Value;
      if (e.params.size() == 1) {
        out << *FindParam(&params, e.params[0] + suffix);
      } else {
        out << YAML::Flow << YAML::BeginMap << YAML::Key << "tau" << YAML::Value
            << *FindParam(&params, e.params[0] + suffix) << YAML::Key << "zeta" << YAML::Value
            << *FindParam(&params, e.params[1] + suffix) << YAML::EndMap;
      }
    }
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

// The `controller:` block of AxisConfigToYaml.
void EmitController(const ControllerConfig& c, YAML::Emitter& out) {
  out << YAML::Key << "controller" << YAML::Value << YAML::BeginMap
      << YAML::Key << "T_s" << YAML::Value << c.T_s
      << YAML::Key << "T_track" << YAML::Value << c.T_track
      << YAML::Key << "G_ff" << YAML::Value << c.G_ff
      << YAML::Key << "G_p" << YAML::Value << c.G_p
      << YAML::Key << "G_i" << YAML::Value << c.G_i
      << YAML::Key << "G_v" << YAML::Value << c.G_v
      << YAML::Key << "alpha" << YAML::Value << c.alpha
      << YAML::Key << "U_max" << YAML::Value << c.U_max
      << YAML::Key << "delay_samples" << YAML::Value << c.delay_samples
      << YAML::Key << "counts_per_rev" << YAML::Value << c.counts_per_rev
      << YAML::Key << "load_quantum" << YAML::Value << c.load_quantum
      << YAML::EndMap;
}

}  // namespace

std::string AxisConfigToYaml(const AxisConfig& config) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << config.name;
  out << YAML::Key << "source" << YAML::Value << config.source;
  const char* amplifiers[] = {"analog_velocity_loop", "current_source", "force_source"};
  out << YAML::Key << "amplifier" << YAML::Value
      << amplifiers[static_cast<int>(config.structure.amplifier)];
  out << YAML::Key << "coupling" << YAML::Value
      << (config.structure.coupling == Coupling::kRigid ? "rigid" : "gear");
  out << YAML::Key << "current_loop" << YAML::Value
      << kCurrentLoops[static_cast<int>(config.structure.current_loop)];
  out << YAML::Key << "accelerometer" << YAML::Value
      << (config.structure.accelerometer == AccelerometerSampling::kInstant
              ? "instant"
              : "period_mean");
  out << YAML::Key << "instant_window" << YAML::Value << config.structure.instant_window;
  // Parameters of MODEL.md §2 and §4, and the sgn_ε widths v_eps and
  // omega_eps of §7 (effect parameters go with their effect).
  std::set<std::string> effect_params;
  for (const auto* table : {&DynamicEffectTable(), &GeneratorOnlyEffectTable()}) {
    for (const EffectInfo& e : *table) {
      for (const char* p : e.params) effect_params.insert(p);
    }
  }
  out << YAML::Key << "parameters" << YAML::Value << YAML::BeginMap;
  AxisParams<double> params = config.params;
  VisitParams([&](const char* name, const char*, double& value) {
    const std::string n = name;
    if (n.find('.') != std::string::npos || effect_params.count(n)) return;
    out << YAML::Key << n << YAML::Value << value;
  }, params);
  out << YAML::EndMap;
  EmitEffects(config, params, out);
  if (config.has_controller) EmitController(config.controller, out);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

void ValidateAxisConfig(const AxisConfig& config, const std::string& where) {
  AxisParams<double> p = config.params;
  VisitParams([&](const char* name, const char*, double& value) {
    const Range r = ParamRange(name);
    if (!InRange(value, r)) {
      throw std::invalid_argument(where + ": parameter '" + name +
                                  "': expected " + RangeText(r) + ", got " +
                                  FormatNumber(value));
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
                                FormatNumber(config.structure.instant_window));
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
  config.structure.accelerometer =
      ParseAccelerometer(root.Choice("accelerometer", kAccelerometer, "period_mean"));
  config.structure.instant_window =
      root.Number("instant_window", config.structure.instant_window, YamlMap::Range::kPositive);
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

void RequireColumn(const YamlMap& map, const YAML::Node& node,
                   const std::string& key, const CsvTable& table,
                   const std::string& column) {
  if (table.HasColumn(column)) return;
  ThrowConfigError(map.file(), node, key, table.ColumnExpectation(),
                   table.DescribeName(column));
}

void MakeCubicOrThrow(YamlMap& map, InputSignal* s) {
  try {
    MakeCubic(s);
  } catch (const std::invalid_argument& e) {
    ThrowConfigError(map.file(), map.Optional("interpolation"), map.KeyPath("interpolation"),
                     "samples a cubic can pass through (" + std::string(e.what()) + ")",
                     "cubic");
  }
}

InputSignal ParseColumnSignal(YamlMap& map, const std::string& base_dir) {
  InputSignal s;
  s.kind = InputSignal::Kind::kTable;
  const std::string file = ResolvePath(base_dir, map.String("file"));
  const std::string time_col = map.String("time", "t");
  const std::string value_col = map.String("column");
  const double scale = map.Number("scale", 1.0);
  s.offset = map.Number("offset", 0.0);
  const std::string mode = map.Choice("interpolation", {"linear", "hold", "cubic"}, "linear");
  s.hold = mode == "hold";
  const DataTable table = ReadDataTable(file, time_col);
  RequireColumn(map, map.node(), map.KeyPath("time"), table, time_col);
  RequireColumn(map, map.node(), map.KeyPath("column"), table, value_col);
  CheckStrictlyIncreasing(table, time_col);
  s.times = table.Column(time_col);
  s.values = table.Column(value_col);
  for (double& v : s.values) v *= scale;
  if (mode == "cubic") MakeCubicOrThrow(map, &s);
  return s;
}

InputSignal ParseInputSignal(YamlMap& map, const std::string& base_dir,
                             double duration) {
  const std::string type = map.Choice(
      "type", {"zero", "step", "ramp", "sine", "chirp", "prbs", "table", "column"});
  InputSignal s;
  s.offset = map.Number("offset", 0.0);
  if (type == "zero") {
    s.kind = InputSignal::Kind::kZero;
  } else if (type == "step") {
    s.kind = InputSignal::Kind::kStep;
    s.amplitude = map.Number("amplitude");
    s.start = map.Number("start", 0.0, Range::kNonNegative);
  } else if (type == "ramp") {
    s.kind = InputSignal::Kind::kRamp;
    s.slope = map.Number("slope");
    s.start = map.Number("start", 0.0, Range::kNonNegative);
  } else if (type == "sine") {
    s.kind = InputSignal::Kind::kSine;
    s.amplitude = map.Number("amplitude");
    s.frequency = map.Number("frequency", Range::kFinitePositive);
    s.phase = map.Number("phase", 0.0);
    s.start = map.Number("start", 0.0, Range::kNonNegative);
  } else if (type == "chirp") {
    s.kind = InputSignal::Kind::kChirp;
    s.amplitude = map.Number("amplitude");
    s.f0 = map.Number("f0", Range::kNonNegative);
    s.f1 = map.Number("f1", Range::kNonNegative);
    s.sweep_time = map.Number("sweep_time", Range::kFinitePositive);
    s.start = map.Number("start", 0.0, Range::kNonNegative);
  } else if (type == "prbs") {
    const double amplitude = map.Number("amplitude");
    const double bit_time = map.Number("bit_time", Range::kFinitePositive);
    const int order = static_cast<int>(map.Integer("order", 10, 2, 20));
    const long seed = map.Integer("seed", 1, 1, 1L << 30);
    const double bits = PrbsTableBits(duration, bit_time);
    if (!(bits <= kMaxPrbsBits)) {
      std::ostringstream got;
      got << std::setprecision(3) << bits << " bits (duration " << duration << " s / bit_time "
          << bit_time << " s): lengthen bit_time or shorten the duration";
      ThrowConfigError(map.file(), map.Optional("bit_time"), map.KeyPath("bit_time"),
                       "a PRBS of at most 1e+08 bits", got.str());
    }
    s = MakePrbs(amplitude, s.offset, bit_time, order,
                 static_cast<std::uint32_t>(seed), duration);
  } else if (type == "table") {
    s.kind = InputSignal::Kind::kTable;
    const YAML::Node points = map.Required("points");
    const std::string key = map.KeyPath("points");
    if (!points.IsSequence() || points.size() < 1) {
      ThrowConfigError(map.file(), points, key,
                       "a list of [time, value] pairs", Describe(points));
    }
    for (const YAML::Node& point : points) {
      if (!point.IsSequence() || point.size() != 2) {
        ThrowConfigError(map.file(), point, key, "a [time, value] pair",
                         Describe(point));
      }
      const double t = map.NumberFrom(point[0], key, Range::kAny);
      if (!s.times.empty() && !(t > s.times.back())) {
        ThrowConfigError(map.file(), point, key,
                         "strictly increasing times",
                         FormatNumber(t) + " after " + FormatNumber(s.times.back()));
      }
      s.times.push_back(t);
      s.values.push_back(map.NumberFrom(point[1], key, Range::kAny));
    }
    const std::string mode = map.Choice("interpolation", {"linear", "hold", "cubic"}, "linear");
    s.hold = mode == "hold";
    if (mode == "cubic") MakeCubicOrThrow(map, &s);
  } else {  // column
    s = ParseColumnSignal(map, base_dir);
  }
  map.Finish();
  return s;
}

Reference ParseReference(YamlMap& map, const std::string& base_dir,
                         double origin) {
  Reference r;
  const std::string type = map.Choice("type", {"trapezoid", "min_jerk", "column"});
  if (type != "column") {
    r.kind = type == "min_jerk" ? Reference::Kind::kMinJerk : Reference::Kind::kTrapezoid;
    r.distance = map.Number("distance");
    r.velocity = map.Number("velocity", Range::kFinitePositive);
    r.acceleration = map.Number("acceleration", Range::kFinitePositive);
    if (r.kind == Reference::Kind::kMinJerk) {
      r.jerk = map.Number("jerk", HUGE_VAL, Range::kPositiveOrInfinite);
    }
    r.start = map.Number("start", 0.0, Range::kNonNegative);
    r.origin = map.Number("origin", origin);
  } else {
    r.kind = Reference::Kind::kTable;
    r.table = ParseColumnSignal(map, base_dir);
  }
  map.Finish();
  return r;
}

ControllerConfig ParseController(YamlMap& map, const ControllerConfig& d) {
  ControllerConfig c;
  c.T_s = map.Number("T_s", d.T_s, Range::kFinitePositive);
  c.T_track = map.Number("T_track", d.T_track, Range::kFinitePositive);
  c.G_ff = map.Number("G_ff", d.G_ff);
  c.G_p = map.Number("G_p", d.G_p);
  c.G_i = map.Number("G_i", d.G_i);
  c.G_v = map.Number("G_v", d.G_v);
  c.alpha = map.Number("alpha", d.alpha, Range::kNonNegative);
  if (c.alpha > 1.0) {
    ThrowConfigError(map.file(), map.Optional("alpha"), map.KeyPath("alpha"),
                     "a number in [0, 1]", FormatNumber(c.alpha));
  }
  c.U_max = map.Number("U_max", d.U_max, Range::kPositive);
  c.delay_samples = static_cast<int>(
      map.Integer("delay_samples", d.delay_samples, 0, 1000));
  c.counts_per_rev = map.Number("counts_per_rev", d.counts_per_rev,
                                Range::kNonNegative);
  c.load_quantum = map.Number("load_quantum", d.load_quantum,
                              Range::kNonNegative);
  map.Finish();
  return c;
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
  if (const YAML::Node node = root.Optional("configuration")) {
    YamlMap map(node, path, "configuration.");
    if (map.Has("amplifier")) {
      model->structure.amplifier = ParseAmplifier(map.Choice("amplifier", kAmplifiers));
    }
    if (map.Has("coupling")) {
      model->structure.coupling = ParseCoupling(map.Choice("coupling", kCouplings));
    }
    if (map.Has("current_loop")) {
      model->structure.current_loop = ParseCurrentLoop(map.Choice("current_loop", kCurrentLoops));
    }
    if (map.Has("accelerometer")) {
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
  ValidateAxisConfig(*model, path);
}

namespace {

// The experiment's `channels:` (required): the trace's columns, each once;
// t is always recorded.
void ParseTraceChannels(YamlMap& root, const std::string& path, ExperimentConfig* e) {
  const YAML::Node channels = root.Required("channels");
  if (!channels.IsSequence() || channels.size() == 0) {
    ThrowConfigError(path, channels, "channels",
                     "a list of channel names (" + ChannelNameList() + ")",
                     Describe(channels));
  }
  std::set<Channel> listed;
  for (const YAML::Node& c : channels) {
    const auto channel = c.IsScalar() ? ParseChannel(c.Scalar()) : std::nullopt;
    if (!channel) {
      ThrowConfigError(path, c, "channels",
                       "a channel name (" + ChannelNameList() + ")", Describe(c));
    }
    // Each names a column of the trace; a CSV reader refuses a repeated one.
    if (!listed.insert(*channel).second) {
      ThrowConfigError(path, c, "channels", "each channel once (each names a column)",
                       Describe(c) + " again");
    }
    if (*channel != Channel::kT) e->options.channels.push_back(*channel);
  }
}

// The experiment's `noise:` (optional): σ per channel name, not t.
void ParseNoise(YamlMap& root, const std::string& path, ExperimentConfig* e) {
  const YAML::Node node = root.Optional("noise");
  if (!node) return;
  YamlMap map(node, path, "noise.");
  for (const auto& entry : node) {
    const std::string name = entry.first.Scalar();
    const auto channel = ParseChannel(name);
    if (!channel || *channel == Channel::kT) {
      ThrowConfigError(path, entry.first, "noise." + name,
                       "a channel name (" + ChannelNameList() + ", not t)",
                       "'" + name + "'");
    }
    e->noise_sigma[static_cast<int>(*channel)] =
        map.Number(name, Range::kNonNegative);
  }
  map.Finish();
}

// CheckMemory on the trace of `e`, sampled at `rate` Hz.
void CheckTraceMemory(const ExperimentConfig& e, double rate, const std::string& path) {
  // The trace: one double per output sample and channel (and time); a
  // delayed channel also keeps one value per RK4 step.
  const double outputs = std::floor(e.options.duration / e.options.output_period) + 1.0;
  const double steps = e.options.duration / e.options.step;
  double delayed = 0.0;
  for (int c = 0; c < kNumChannels; ++c) {
    delayed += HasGridFrontEnd(e.model.structure, static_cast<Channel>(c)) ? 1.0 : 0.0;
  }
  const double bytes =
      8.0 * (outputs * (e.options.channels.size() + 1.0) * 2.0 + steps * delayed);
  std::ostringstream advice;
  advice << "shorten 'duration' (" << e.options.duration << " s) or lower 'output_rate' ("
         << rate << " Hz)";
  CheckMemory(bytes, path, "the simulation", advice.str());
}

// The experiment's drive: `input:` (open loop) or `reference:` with the
// controller and an optional `injection:` (closed loop).
void ParseExperimentDrive(YamlMap& root, const std::string& path, const std::string& dir,
                          ExperimentConfig* e) {
  const bool has_input = root.Has("input");
  const bool has_reference = root.Has("reference");
  if (has_input == has_reference) {
    ThrowConfigError(path, root.node(), has_input ? "reference" : "input",
                     "exactly one of 'input' (open loop) or 'reference' "
                     "(closed loop through the controller)",
                     has_input ? "both" : "neither");
  }
  if (has_input) {
    for (const char* key : {"controller", "injection"}) {
      if (root.Has(key)) {
        ThrowConfigError(path, root.node()[key], key,
                         std::string(key) + " only with a 'reference' (closed loop)",
                         "an open-loop experiment with 'input'");
      }
    }
    YamlMap map(root.Required("input"), path, "input.");
    e->drive.input = ParseInputSignal(map, dir, e->options.duration);
    return;
  }
  e->drive.closed_loop = true;
  ControllerConfig base = e->model.controller;
  if (const YAML::Node node = root.Optional("controller")) {
    YamlMap map(node, path, "controller.");
    base = ParseController(map, base);
  } else if (!e->model.has_controller) {
    ThrowConfigError(path, root.node(), "controller",
                     "a controller section here or in the model config " +
                         e->model.path,
                     "none");
  }
  e->drive.controller = base;
  YamlMap map(root.Required("reference"), path, "reference.");
  e->drive.reference = ParseReference(map, dir, e->initial_state[0]);
  if (const YAML::Node node = root.Optional("injection")) {
    YamlMap inj(node, path, "injection.");
    e->drive.injection = ParseInputSignal(inj, dir, e->options.duration);
    e->drive.has_injection = true;
  }
}

}  // namespace

ExperimentConfig LoadExperiment(const std::string& path) {
  return ParseExperiment(LoadYamlFile(path), path, DirectoryOf(path));
}

ExperimentConfig ParseExperiment(const YAML::Node& document, const std::string& path,
                                 const std::string& dir) {
  ExperimentConfig e;
  e.path = path;
  YamlMap root(document, path, "");
  e.description = root.String("description", "");
  e.model = LoadAxisConfig(ResolvePath(dir, root.String("model")));
  ParseModelOverrides(root, &e.model);

  e.options.duration = root.Number("duration", Range::kFinitePositive);
  e.options.step = root.Number("step", 1e-5, Range::kFinitePositive);
  {
    const YAML::Node node = root.node()["step"];
    CheckRk4Step(e.model.structure, e.model.params, e.options.step,
                 node ? path + ":" + std::to_string(node.Mark().line + 1) : path, "step");
  }
  const double rate = root.Number("output_rate", 1000.0, Range::kFinitePositive);
  e.options.output_period = 1.0 / rate;
  ParseTraceChannels(root, path, &e);
  ParseNoise(root, path, &e);
  CheckTraceMemory(e, rate, path);
  e.seed = static_cast<std::uint64_t>(root.Integer("seed", 0, 0, kMaxExperimentSeed));
  if (const YAML::Node node = root.Optional("initial_state")) {
    YamlMap map(node, path, "initial_state.");
    for (int k = 0; k < kNumStates; ++k) {
      e.initial_state[k] = map.Number("y" + std::to_string(k), 0.0);
    }
    map.Finish();
  }
  e.initial_state = ConsistentInitialState(e.model, e.initial_state);
  ParseExperimentDrive(root, path, dir, &e);
  root.Finish();
  try {
    MakeGrid(e.options, e.drive);
  } catch (const std::invalid_argument& err) {
    throw std::invalid_argument(path + ": " + err.what());
  }
  return e;
}

}  // namespace axis
