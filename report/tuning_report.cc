#include "report/tuning_report.h"

#include <cmath>
#include <functional>
#include <limits>
#include <sstream>

#include "common/format.h"
#include "sim/config.h"
#include "io/csv.h"

namespace axis {
namespace {

using Json = nlohmann::json;

// A figure's value in its unit, "-" for NaN.
std::string Cell(double x) { return std::isnan(x) ? "-" : FormatNumber(x, 4); }

// The spec's bound on figure `name` ("<= 0.8 s"), "" if unset.
std::string Bound(const TuneSpec& s, const std::string& name) {
  const auto text = [](double b, const char* side, const char* unit) {
    return std::isnan(b) ? std::string() : std::string(side) + " " + FormatNumber(b, 4) + unit;
  };
  if (name == "settling_time") return text(s.max_settling_time, "<=", " s");
  if (name == "overshoot") return text(s.max_overshoot, "<=", "");
  if (name == "peak_current") return text(s.max_current, "<=", " A");
  if (name == "voltage_headroom") return text(s.min_voltage_headroom, ">=", " V");
  if (name == "ringing") return text(s.max_ringing, "<=", " m/s");
  if (name == "ringing_decay") return text(s.max_ringing_decay, "<=", " s");
  return "";
}

const char* Unit(const std::string& name) {
  if (name == "settling_time") return "s";
  if (name == "peak_current") return "A";
  if (name == "voltage_headroom") return "V";
  if (name == "ringing") return "m/s";
  if (name == "ringing_decay") return "s";
  return "1";
}

Json MetricsJson(const StepMetrics& m) {
  return {{"final_velocity", JsonNumber<Json>(m.final_velocity)},
          {"settling_time", JsonNumber<Json>(m.settling_time)},
          {"settled", m.settled},
          {"overshoot", JsonNumber<Json>(m.overshoot)},
          {"peak_current", JsonNumber<Json>(m.peak_current)},
          {"voltage_headroom", JsonNumber<Json>(m.voltage_headroom)},
          {"ringing", JsonNumber<Json>(m.ringing)},
          {"ringing_decay", JsonNumber<Json>(m.ringing_decay)}};
}

Json SpreadJson(const std::vector<FigureSpread>& spreads) {
  Json spread = Json::array();
  for (const FigureSpread& f : spreads) {
    spread.push_back({{"figure", f.figure},
                      {"at_estimate", JsonNumber<Json>(f.at_estimate)},
                      {"low", JsonNumber<Json>(f.low)},
                      {"high", JsonNumber<Json>(f.high)},
                      {"limiting", f.limiting}});
  }
  return spread;
}

Json SettingJson(const TunedSetting& s) {
  const Json spread = SpreadJson(s.spread);
  return {{"K1", JsonNumber<Json>(s.K1)},
          {"T_p", JsonNumber<Json>(s.T_p)},
          {"metrics", MetricsJson(s.metrics)},
          {"violations", s.violations},
          {"spread", spread},
          {"robust", s.robust},
          {"robust_violations", s.robust_violations},
          {"samples", s.samples},
          {"samples_met", s.samples_met}};
}

// "k of n samples of the joint 95 % region" (tune/joint_region.h).
std::string SamplesPhrase(int samples, int met) {
  return std::to_string(met) + " of " + std::to_string(samples) +
         " samples of the fit's joint 95 % region";
}

// Whether a setting meets the spec over the uncertainty, in one line;
// `checks` names what it was judged on besides the estimate and the
// `samples` of the joint region (`met` of them meeting it).
std::string RobustLine(const char* name, bool robust, const std::vector<std::string>& violations,
                       const std::vector<std::string>& robust_violations, int samples, int met,
                       const std::string& checks = "every interval end") {
  std::string out = std::string("  ") + name;
  const std::string joint = samples > 0 ? ", and at " + SamplesPhrase(samples, met) : "";
  if (robust) return out + ": meets the spec at the estimate and at " + checks + joint + "\n";
  out += ": does not meet the spec";
  out += violations.empty() ? " at " + checks + ":" : ":";
  for (const std::string& v : violations) out += " " + v + ";";
  for (const std::string& v : robust_violations) out += " " + v + ";";
  if (samples > 0) out += " met at " + SamplesPhrase(samples, met);
  return out + "\n";
}

// The table of two settings' figures over the intervals, with each
// figure's unit and the spec's bound on it.
std::string SpreadTable(const std::vector<FigureSpread>& current,
                        const std::vector<FigureSpread>& proposed,
                        const std::function<std::string(const std::string&)>& unit,
                        const std::function<std::string(const std::string&)>& bound) {
  TextTable table;
  table.headers = {"figure", "unit", "current", "over the intervals", "proposed",
                   "over the intervals", "limited by", "spec"};
  table.right = {false, false, true, true, true, true, false, false};
  for (size_t f = 0; f < proposed.size() && f < current.size(); ++f) {
    const FigureSpread& c = current[f];
    const FigureSpread& p = proposed[f];
    table.rows.push_back({p.figure, unit(p.figure), Cell(c.at_estimate),
                          Cell(c.low) + " .. " + Cell(c.high), Cell(p.at_estimate),
                          Cell(p.low) + " .. " + Cell(p.high), p.limiting.empty() ? "-" : p.limiting,
                          bound(p.figure)});
  }
  return RenderText(table);
}

// The table of both settings' figures.
std::string FiguresTable(const AnalogLoopTuning& t) {
  return SpreadTable(
      t.current.spread, t.proposed.spread, [](const std::string& f) { return Unit(f); },
      [&t](const std::string& f) { return Bound(t.spec, f); });
}

std::string CurveTable(const AnalogLoopTuning& t) {
  TextTable table;
  table.headers = {"T_p (s)", "settling (s)", "overshoot", "peak i (A)", "headroom (V)",
                   "ringing (m/s)", "decay (s)", "meets spec"};
  table.right = {true, true, true, true, true, true, true, false};
  for (const TuningPoint& p : t.curve) {
    table.rows.push_back({FormatNumber(p.T_p, 4),
                          p.metrics.settled ? Cell(p.metrics.settling_time) : "not settled",
                          Cell(p.metrics.overshoot), Cell(p.metrics.peak_current),
                          Cell(p.metrics.voltage_headroom), Cell(p.metrics.ringing),
                          Cell(p.metrics.ringing_decay), p.violations.empty() ? "yes" : "no"});
  }
  return RenderText(table);
}

}  // namespace

std::string FormatTuning(const AnalogLoopTuning& t) {
  if (!t.ran) return t.note.empty() ? "" : "Tuning: " + t.note + "\n";
  std::ostringstream out;
  const TuneSpec& s = t.spec;
  out << "Tuning the analog loop (K_2 = " << FormatNumber(t.K2, 4) << " kept): a "
      << FormatNumber(s.step_voltage, 3) << " V set-velocity step, " << FormatNumber(s.duration, 3)
      << " s, settling band " << FormatNumber(100.0 * s.settling_band, 3)
      << " % of the final velocity, residual vibration from " << FormatNumber(s.ringing_after, 3)
      << " s after the velocity enters the band\n";
  out << "  current:  K1 " << FormatNumber(t.current.K1, 5) << ", T_p "
      << FormatNumber(t.current.T_p, 4) << " s\n";
  out << "  proposed: K1 " << FormatNumber(t.proposed.K1, 5) << ", T_p "
      << FormatNumber(t.proposed.T_p, 4) << " s\n";
  out << FiguresTable(t);
  for (const auto* setting : {&t.current, &t.proposed}) {
    out << RobustLine(setting == &t.current ? "current" : "proposed", setting->robust,
                      setting->violations, setting->robust_violations, setting->samples,
                      setting->samples_met);
  }
  out << "Trade-off curve (the paper's series of steps in T_p):\n" << CurveTable(t);
  out << "  " << t.simulations << " simulations, " << FormatNumber(t.seconds, 3) << " s\n";
  return out.str();
}

Json TuningToJson(const AnalogLoopTuning& t) {
  Json curve = Json::array();
  for (const TuningPoint& p : t.curve) {
    Json row = MetricsJson(p.metrics);
    row["T_p"] = JsonNumber<Json>(p.T_p);
    row["violations"] = p.violations;
    curve.push_back(row);
  }
  const TuneSpec& s = t.spec;
  return {{"ran", t.ran},
          {"note", t.note},
          {"spec",
           {{"step_voltage", JsonNumber<Json>(s.step_voltage)},
            {"duration", JsonNumber<Json>(s.duration)},
            {"settling_band", JsonNumber<Json>(s.settling_band)},
            {"ringing_after", JsonNumber<Json>(s.ringing_after)},
            {"settling_time", JsonNumber<Json>(s.max_settling_time)},
            {"overshoot", JsonNumber<Json>(s.max_overshoot)},
            {"current", JsonNumber<Json>(s.max_current)},
            {"voltage_headroom", JsonNumber<Json>(s.min_voltage_headroom)},
            {"ringing", JsonNumber<Json>(s.max_ringing)},
            {"ringing_decay", JsonNumber<Json>(s.max_ringing_decay)},
            {"velocity_gain", JsonNumber<Json>(s.velocity_gain)}}},
          {"K2", JsonNumber<Json>(t.K2)},
          {"current", SettingJson(t.current)},
          {"proposed", SettingJson(t.proposed)},
          {"curve", curve},
          {"simulations", t.simulations},
          {"seconds", JsonNumber<Json>(t.seconds)}};
}

void WriteTuning(const std::string& dir, const AxisConfig& model, const AnalogLoopTuning& t,
                 std::vector<std::string>* files) {
  if (!t.ran) return;
  std::vector<std::vector<double>> curve(7);
  for (const TuningPoint& p : t.curve) {
    const StepMetrics& m = p.metrics;
    const double values[] = {p.T_p, m.settling_time, m.overshoot, m.peak_current,
                             m.voltage_headroom, m.ringing, m.ringing_decay};
    bool finite = true;
    for (double v : values) finite = finite && std::isfinite(v);
    if (!finite) continue;  // a point that did not settle or ring: in report.json
    for (size_t k = 0; k < curve.size(); ++k) curve[k].push_back(values[k]);
  }
  if (!curve[0].empty()) {
    WriteCsvAtomic(dir + "/tune_curve.csv",
                   {"T_p", "settling_time", "overshoot", "peak_current", "voltage_headroom",
                    "ringing", "ringing_decay"},
                   curve);
    files->push_back("tune_curve.csv");
  }
  if (WriteTuneStepCsv(dir + "/tune_step.csv", t)) files->push_back("tune_step.csv");
  AxisConfig tuned = model;
  tuned.name = model.name + "_tuned";
  tuned.source = "fit-params (tune:): the fitted model with the proposed K1 and T_p";
  tuned.params.K1 = t.proposed.K1;
  tuned.params.T_p = t.proposed.T_p;
  WriteFileAtomic(dir + "/model_tuned.yaml",
                  "# Written by fit-params (tune:): the fitted model with the proposed\n"
                  "# K1 and T_p. Loadable by simulate-axis and fit-params.\n" +
                      AxisConfigToYaml(tuned));
  std::ostringstream y;
  y << "# Written by fit-params (tune:): the step the proposal was tuned on.\n"
    << "# Set K1 = " << FormatNumber(t.proposed.K1, 6) << " and T_p = "
    << FormatNumber(t.proposed.T_p, 6) << " s on the machine, run this step,\n"
    << "# record u, a, tach and i, and fit it (or simulate it:\n"
    << "# simulate-axis tune_verify.yaml --out tune_verify.csv).\n"
    << "description: \"verify the tuning: a " << FormatNumber(t.spec.step_voltage, 4)
    << " V set-velocity step\"\n"
    << "model: model_tuned.yaml\n"
    << "duration: " << FormatNumber(t.spec.duration, 6) << "\n"
    << "step: 1.0e-5\n"
    << "output_rate: 1000\n"
    << "channels: [u, v, a, i, tach, vm, fg]\n"
    << "input: {type: step, amplitude: " << FormatNumber(t.spec.step_voltage, 6)
    << ", start: 0.0}\n";
  WriteFileAtomic(dir + "/tune_verify.yaml", y.str());
  files->push_back("model_tuned.yaml");
  files->push_back("tune_verify.yaml");
}

namespace {

const char* MoveUnit(const std::string& figure) {
  if (figure == "move_time" || figure == "settling_time") return "s";
  if (figure == "peak_current") return "A";
  return "m";
}

std::string MoveBound(const MoveSpec& s, const std::string& figure) {
  const auto text = [](double b, const char* unit) {
    return std::isnan(b) ? std::string() : "<= " + FormatNumber(b, 4) + " " + unit;
  };
  if (figure == "settling_time") return text(s.max_settling_time, "s");
  if (figure == "following_error") return text(s.max_following_error, "m");
  if (figure == "overshoot") return text(s.max_overshoot, "m");
  if (figure == "peak_current") return text(s.max_current, "A");
  if (figure == "ringing") return text(s.max_ringing, "m");
  return "";
}

std::string Gains(const MoveSetting& s, const std::vector<TunedGain>& gains) {
  std::string out;
  ControllerConfig c = s.controller;
  for (const TunedGain& g : gains) {
    const double* v = ControllerGain(&c, g.name);
    out += (out.empty() ? "" : ", ") + g.name + " " + (v ? FormatNumber(*v, 4) : "?");
  }
  return out;
}

// "none", or "ZV 12.3 Hz, zeta 0.05".
std::string Shaper(const InputShaper& s) {
  if (s.type == ShaperType::kNone) return "none";
  return ShaperName(s.type) + " " + FormatNumber(s.frequency, 4) + " Hz, zeta " +
         FormatNumber(s.damping, 3);
}

// The largest residual vibration over the checks (after the estimate), and
// where.
const CheckFigure* WorstVibration(const MoveSetting& s) {
  const CheckFigure* worst = nullptr;
  for (size_t k = 1; k < s.residual_vibration.size(); ++k) {
    const CheckFigure& c = s.residual_vibration[k];
    if (std::isnan(c.value)) continue;
    if (worst == nullptr || c.value > worst->value) worst = &c;
  }
  return worst;
}

std::string MoveSettingsTable(const MoveTuning& t) {
  TextTable table;
  const bool shaped = !t.shapers.empty();
  table.headers = {"setting", "profile", "speed", "gains", "move (s)", "settled at (s)",
                   "following (m)", "overshoot (m)", "peak i (A)", "ringing (m)", "meets spec"};
  table.right = {false, false, true, false, true, true, true, true, true, true, false};
  if (shaped) {
    table.headers.insert(table.headers.begin() + 3, {"shaper", "smoothing (m)"});
    table.right.insert(table.right.begin() + 3, {false, true});
  }
  const auto row = [&](const std::string& name, const MoveSetting& s) {
    const MoveMetrics& m = s.metrics;
    std::vector<std::string> cells = {name, s.profile, FormatNumber(s.speed, 3), Gains(s, t.gains),
                          FormatNumber(s.reference.MoveDuration(), 4),
                          m.settled ? Cell(m.move_time) : "not settled",
                          Cell(m.following_error), Cell(m.overshoot), Cell(m.peak_current),
                          Cell(m.ringing), s.violations.empty() ? "yes" : "no"};
    if (shaped) {
      cells.insert(cells.begin() + 3, {Shaper(s.reference.shaper), Cell(s.smoothing)});
    }
    table.rows.push_back(std::move(cells));
  };
  row("current", t.current);
  for (const MoveSetting& s : t.tuned) row("tuned", s);
  return RenderText(table);
}

std::string MoveFiguresTable(const MoveTuning& t) {
  return SpreadTable(
      t.current.spread, t.proposed.spread, [](const std::string& f) { return MoveUnit(f); },
      [&t](const std::string& f) { return MoveBound(t.spec, f); });
}

Json ShaperJson(const InputShaper& s) {
  Json amplitudes = Json::array(), times = Json::array();
  for (double a : s.amplitudes) amplitudes.push_back(JsonNumber<Json>(a));
  for (double x : s.times) times.push_back(JsonNumber<Json>(x));
  return {{"type", ShaperName(s.type)},
          {"frequency", JsonNumber<Json>(s.frequency)},
          {"damping", JsonNumber<Json>(s.damping)},
          {"amplitudes", amplitudes},
          {"times", times},
          {"duration", JsonNumber<Json>(s.Duration())}};
}

Json MoveSettingJson(const MoveSetting& s) {
  Json vibration = Json::array();
  for (const CheckFigure& c : s.residual_vibration) {
    vibration.push_back({{"check", c.check}, {"ringing", JsonNumber<Json>(c.value)}});
  }
  const ControllerConfig& c = s.controller;
  const MoveMetrics& m = s.metrics;
  return {{"profile", s.profile},
          {"speed", JsonNumber<Json>(s.speed)},
          {"K1", JsonNumber<Json>(s.K1)},
          {"T_p", JsonNumber<Json>(s.T_p)},
          {"controller",
           {{"G_p", JsonNumber<Json>(c.G_p)},
            {"G_i", JsonNumber<Json>(c.G_i)},
            {"G_v", JsonNumber<Json>(c.G_v)},
            {"G_ff", JsonNumber<Json>(c.G_ff)},
            {"alpha", JsonNumber<Json>(c.alpha)}}},
          {"move",
           {{"velocity", JsonNumber<Json>(s.reference.velocity)},
            {"acceleration", JsonNumber<Json>(s.reference.acceleration)},
            {"jerk", JsonNumber<Json>(s.reference.jerk)},
            {"duration", JsonNumber<Json>(s.reference.MoveDuration())}}},
          {"shaper", ShaperJson(s.reference.shaper)},
          {"smoothing", JsonNumber<Json>(s.smoothing)},
          {"residual_vibration", vibration},
          {"metrics",
           {{"move_time", JsonNumber<Json>(m.move_time)},
            {"settled", m.settled},
            {"settling_time", JsonNumber<Json>(m.settling_time)},
            {"following_error", JsonNumber<Json>(m.following_error)},
            {"overshoot", JsonNumber<Json>(m.overshoot)},
            {"peak_current", JsonNumber<Json>(m.peak_current)},
            {"ringing", JsonNumber<Json>(m.ringing)}}},
          {"violations", s.violations},
          {"objective", JsonNumber<Json>(s.objective)},
          {"scenarios", s.scenarios},
          {"evaluations", s.evaluations},
          {"spread", SpreadJson(s.spread)},
          {"robust", s.robust},
          {"robust_violations", s.robust_violations},
          {"samples", s.samples},
          {"samples_met", s.samples_met},
          {"checks_met", s.checks_met}};
}

// Klipper's rule beside the proposal: its fits, its choice, and how that
// choice fares on the identified axis with the profile's tuned gains.
std::string KlipperText(const MoveTuning& t) {
  std::ostringstream out;
  out << "  Klipper's rule (tune.move.klipper; its resonance test simulated on the identified "
         "model, "
      << FormatNumber(t.resonance.seconds, 4) << " s, "
      << FormatNumber(t.resonance.frequency.front(), 4) << "-"
      << FormatNumber(t.resonance.frequency.back(), 4) << " Hz):\n";
  TextTable table;
  table.headers = {"shaper", "frequency (Hz)", "vibration (%)", "smoothing (m)", "score"};
  table.right = {false, true, true, true, true};
  for (const KlipperShaperFit& f : t.klipper_choice.fitted) {
    table.rows.push_back({ShaperName(f.type), FormatNumber(f.frequency, 4),
                          FormatNumber(100.0 * f.vibration, 3), Cell(f.smoothing),
                          Cell(f.score)});
  }
  out << RenderText(table);
  const MoveSetting& k = t.klipper;
  out << "  Klipper's rule recommends " << Shaper(k.reference.shaper) << "; on the "
      << k.profile << "'s tuned gains it " << (k.violations.empty() ? "meets" : "breaks")
      << " the spec at the estimate and meets it at " << k.checks_met << " of "
      << k.residual_vibration.size() - 1 << " checks (the proposal: " << t.proposed.checks_met
      << ")\n";
  return out.str();
}

}  // namespace

std::string FormatMoveTuning(const MoveTuning& t) {
  if (!t.ran) return t.note.empty() ? "" : "Move tuning: " + t.note + "\n";
  std::ostringstream out;
  const MoveSpec& s = t.spec;
  out << "Tuning the position controller and the move: " << FormatNumber(s.distance, 4)
      << " m, limits " << FormatNumber(s.max_velocity, 4) << " m/s, "
      << FormatNumber(s.max_acceleration, 4) << " m/s^2"
      << (std::isfinite(s.max_jerk) ? ", " + FormatNumber(s.max_jerk, 4) + " m/s^3" : "")
      << "; position band " << FormatNumber(s.position_band, 3) << " m; "
      << (t.slow_down ? "the move may be slowed (speed < 1)" : "the move at the limits")
      << "; searched with every bound " << FormatNumber(100.0 * t.margin, 3) << " % inside\n";
  if (t.on_proposed_analog_loop) {
    out << "  on the analog loop as proposed above (K1 " << FormatNumber(t.proposed.K1, 5)
        << ", T_p " << FormatNumber(t.proposed.T_p, 4) << " s)\n";
  }
  for (const std::string& note : t.shaper_notes) out << "  shapers on " << note << "\n";
  out << MoveSettingsTable(t);
  out << "  proposed: " << t.proposed.profile << " at speed " << FormatNumber(t.proposed.speed, 3)
      << ", " << Gains(t.proposed, t.gains);
  if (!t.shapers.empty()) {
    out << ", shaper " << Shaper(t.proposed.reference.shaper) << " (smoothing "
        << FormatNumber(t.proposed.smoothing, 3) << " m)";
  }
  out << "\n";
  if (const CheckFigure* worst = WorstVibration(t.proposed)) {
    out << "  proposed: residual vibration " << FormatNumber(t.proposed.metrics.ringing, 3)
        << " m at the estimate, at most " << FormatNumber(worst->value, 3) << " m over the "
        << t.proposed.residual_vibration.size() - 1 << " checks (" << worst->check << ")\n";
  }
  if (!t.proposed.scenarios.empty()) {
    out << "  searched to meet the spec also at: " << Join(t.proposed.scenarios, ", ")
        << " (where the estimate's best broke it)\n";
  }
  if (t.klipper_ran) out << KlipperText(t);
  if (!t.klipper_note.empty()) out << "  " << t.klipper_note << "\n";
  out << MoveFiguresTable(t);
  for (const auto* setting : {&t.current, &t.proposed}) {
    out << RobustLine(setting == &t.current ? "current" : "proposed", setting->robust,
                      setting->violations, setting->robust_violations, setting->samples,
                      setting->samples_met, "every interval end and the full current loop where the job fits the "
                      "quasi-steady one");
  }
  out << "  " << t.simulations << " simulations, " << FormatNumber(t.seconds, 3) << " s\n";
  return out.str();
}

namespace {

Json KlipperJson(const MoveTuning& t) {
  if (!t.klipper_ran) return {{"ran", false}, {"note", t.klipper_note}};
  Json fitted = Json::array();
  for (const KlipperShaperFit& f : t.klipper_choice.fitted) {
    fitted.push_back({{"shaper", ShaperName(f.type)},
                      {"frequency", JsonNumber<Json>(f.frequency)},
                      {"vibration", JsonNumber<Json>(f.vibration)},
                      {"smoothing", JsonNumber<Json>(f.smoothing)},
                      {"score", JsonNumber<Json>(f.score)}});
  }
  Json frequency = Json::array(), psd = Json::array();
  for (size_t k = 0; k < t.resonance.frequency.size(); ++k) {
    frequency.push_back(JsonNumber<Json>(t.resonance.frequency[k]));
    psd.push_back(JsonNumber<Json>(t.resonance.psd[k]));
  }
  return {{"ran", true},
          {"resonance_test",
           {{"seconds", JsonNumber<Json>(t.resonance.seconds)},
            {"averages", t.resonance.averages},
            {"frequency", frequency},
            {"psd", psd}}},
          {"fitted", fitted},
          {"recommended", ShaperName(t.klipper_choice.fitted[t.klipper_choice.recommended].type)},
          {"setting", MoveSettingJson(t.klipper)}};
}

}  // namespace

Json MoveTuningToJson(const MoveTuning& t) {
  Json gains = Json::array();
  for (const TunedGain& g : t.gains) {
    gains.push_back({{"name", g.name},
                     {"low", JsonNumber<Json>(g.low)},
                     {"high", JsonNumber<Json>(g.high)}});
  }
  Json tuned = Json::array();
  for (const MoveSetting& s : t.tuned) tuned.push_back(MoveSettingJson(s));
  Json shapers = Json::array();
  for (ShaperType type : t.shapers) shapers.push_back(ShaperName(type));
  const MoveSpec& s = t.spec;
  return {{"ran", t.ran},
          {"note", t.note},
          {"spec",
           {{"distance", JsonNumber<Json>(s.distance)},
            {"max_velocity", JsonNumber<Json>(s.max_velocity)},
            {"max_acceleration", JsonNumber<Json>(s.max_acceleration)},
            {"max_jerk", JsonNumber<Json>(s.max_jerk)},
            {"profiles", s.profiles},
            {"settle", JsonNumber<Json>(s.settle)},
            {"position_band", JsonNumber<Json>(s.position_band)},
            {"ringing_after", JsonNumber<Json>(s.ringing_after)},
            {"settling_time", JsonNumber<Json>(s.max_settling_time)},
            {"following_error", JsonNumber<Json>(s.max_following_error)},
            {"overshoot", JsonNumber<Json>(s.max_overshoot)},
            {"current", JsonNumber<Json>(s.max_current)},
            {"ringing", JsonNumber<Json>(s.max_ringing)}}},
          {"gains", gains},
          {"shapers", shapers},
          {"shaper_notes", t.shaper_notes},
          {"slow_down", t.slow_down},
          {"margin", JsonNumber<Json>(t.margin)},
          {"on_proposed_analog_loop", t.on_proposed_analog_loop},
          {"current", MoveSettingJson(t.current)},
          {"proposed", MoveSettingJson(t.proposed)},
          {"tuned", tuned},
          {"klipper", KlipperJson(t)},
          {"simulations", t.simulations},
          {"seconds", JsonNumber<Json>(t.seconds)}};
}

void WriteMoveTuning(const std::string& dir, const AxisConfig& model, const MoveTuning& t,
                     std::vector<std::string>* files) {
  if (!t.ran) return;
  if (WriteTuneMoveCsv(dir + "/tune_move.csv", t)) files->push_back("tune_move.csv");
  AxisConfig tuned = model;
  tuned.name = model.name + "_tuned_move";
  tuned.source = "fit-params (tune.move:): the fitted model with the proposed controller";
  tuned.params.K1 = t.proposed.K1;
  tuned.params.T_p = t.proposed.T_p;
  tuned.has_controller = true;
  tuned.controller = t.proposed.controller;
  WriteFileAtomic(dir + "/model_tuned_move.yaml",
                  "# Written by fit-params (tune.move:): the fitted model with the proposed\n"
                  "# K1, T_p and controller gains. Loadable by simulate-axis and fit-params.\n" +
                      AxisConfigToYaml(tuned));
  const Reference& r = t.proposed.reference;
  std::ostringstream y;
  y << "# Written by fit-params (tune.move:): the move the proposal was tuned on.\n"
    << "# Set the controller as in model_tuned_move.yaml, run this move, record\n"
    << "# x, x_ref, u and i (or simulate it:\n"
    << "# simulate-axis tune_move_verify.yaml --out tune_move_verify.csv).\n"
    << "description: \"verify the move tuning: a " << FormatNumber(r.distance, 4) << " m "
    << t.proposed.profile << " move\"\n"
    << "model: model_tuned_move.yaml\n"
    << "duration: " << FormatNumber(r.MoveDuration() + t.spec.settle, 6) << "\n"
    << "step: 1.0e-5\n"
    << "output_rate: 1000\n"
    << "channels: [u, x, x_ref, v, a, i, tach]\n"
    << "reference: {type: " << t.proposed.profile << ", distance: " << FormatNumber(r.distance, 8)
    << ", velocity: " << FormatNumber(r.velocity, 8)
    << ", acceleration: " << FormatNumber(r.acceleration, 8);
  if (r.kind == Reference::Kind::kMinJerk && std::isfinite(r.jerk)) {
    y << ", jerk: " << FormatNumber(r.jerk, 8);
  }
  if (r.shaper.type != ShaperType::kNone) {
    y << ",\n            shaper: {type: " << ShaperName(r.shaper.type)
      << ", frequency: " << FormatNumber(r.shaper.frequency, 10)
      << ", damping: " << FormatNumber(r.shaper.damping, 10) << "}";
  }
  y << "}\n";
  WriteFileAtomic(dir + "/tune_move_verify.yaml", y.str());
  files->push_back("model_tuned_move.yaml");
  files->push_back("tune_move_verify.yaml");
}

bool WriteTuneStepCsv(const std::string& path, const AnalogLoopTuning& t) {
  const StepResponse& c = t.current.response;
  const StepResponse& p = t.proposed.response;
  const StepResponse& lo = t.proposed.band_low;
  const StepResponse& hi = t.proposed.band_high;
  const size_t n = c.t.size();
  if (!(t.ran && c.finite && p.finite && n > 0 && p.t.size() == n && lo.t.size() == n &&
        hi.t.size() == n)) {
    return false;
  }
  WriteCsvAtomic(path,
                 {"t", "x_current", "v_current", "i_current", "vm_current", "fg_current",
                  "x_proposed", "v_proposed", "i_proposed", "vm_proposed", "fg_proposed",
                  "x_proposed_low", "x_proposed_high", "v_proposed_low", "v_proposed_high",
                  "i_proposed_low", "i_proposed_high", "fg_proposed_low", "fg_proposed_high"},
                 {c.t, c.x, c.v, c.i, c.vm, c.fg, p.x, p.v, p.i, p.vm, p.fg, lo.x, hi.x, lo.v,
                  hi.v, lo.i, hi.i, lo.fg, hi.fg});
  return true;
}

bool WriteTuneMoveCsv(const std::string& path, const MoveTuning& t) {
  const MoveResponse& c = t.current.response;
  const MoveResponse& p = t.proposed.response;
  const MoveResponse& lo = t.proposed.band_low;
  const MoveResponse& hi = t.proposed.band_high;
  if (!(t.ran && c.finite && p.finite && !c.t.empty() && !p.t.empty() &&
        lo.t.size() == p.t.size() && hi.t.size() == p.t.size())) {
    return false;
  }
  // TuneMove runs both to the same end; a run that is shorter still (a
  // tuning made otherwise) is held at its last sample.
  const size_t n = std::max(c.t.size(), p.t.size());
  const auto held = [n](const std::vector<double>& v) {
    std::vector<double> out = v;
    if (!out.empty()) out.resize(n, out.back());
    return out;
  };
  const MoveResponse& longer = c.t.size() >= p.t.size() ? c : p;
  WriteCsvAtomic(path,
                 {"t", "x_ref_current", "x_current", "v_current", "i_current", "u_current",
                  "fg_current", "x_ref_proposed", "x_proposed", "v_proposed", "i_proposed",
                  "u_proposed", "fg_proposed", "x_proposed_low", "x_proposed_high",
                  "v_proposed_low", "v_proposed_high", "i_proposed_low", "i_proposed_high",
                  "u_proposed_low", "u_proposed_high"},
                 {longer.t, held(c.x_ref), held(c.x), held(c.v), held(c.i), held(c.u),
                  held(c.fg), held(p.x_ref), held(p.x), held(p.v), held(p.i), held(p.u),
                  held(p.fg), held(lo.x), held(hi.x), held(lo.v), held(hi.v), held(lo.i),
                  held(hi.i), held(lo.u), held(hi.u)});
  return true;
}

namespace {

// Two panels side by side from `csv`: each a band (columns lo:hi) and the
// current and proposed lines, with its label.
struct Panel {
  const char* ylabel;
  int current, proposed, low, high;
  int reference;  // a dashed line (0: none)
};

std::string TwoPanelScript(const std::string& csv, const std::string& output,
                           const std::string& title, const Panel (&panels)[2]) {
  std::ostringstream s;
  s << "set terminal svg size 1000,420 dynamic noenhanced font 'sans,12' background rgb "
       "'white'; set output '"
    << output << "'; set datafile separator ','; set grid; set key top right; "
    << "set multiplot layout 1,2 title '" << title << "'; set xlabel 't (s)'; ";
  for (const Panel& p : panels) {
    s << "set ylabel '" << p.ylabel << "'; plot '" << csv << "' every ::1 using 1:" << p.low
      << ":" << p.high << " with filledcurves lc rgb '#c6dbef' title 'proposed, over the "
      << "intervals', '" << csv << "' every ::1 using 1:" << p.current
      << " with lines lw 1.5 lc rgb '#969696' title 'current', '" << csv
      << "' every ::1 using 1:" << p.proposed
      << " with lines lw 2 lc rgb '#08519c' title 'proposed'";
    if (p.reference > 0) {
      s << ", '" << csv << "' every ::1 using 1:" << p.reference
        << " with lines dt 2 lc rgb '#d94801' title 'reference (proposed)'";
    }
    s << "; ";
  }
  s << "unset multiplot";
  return s.str();
}

}  // namespace

std::string TuneStepPlotScript(const std::string& csv, const std::string& output) {
  return TwoPanelScript(csv, output, "the step: current and proposed setting",
                        {{"velocity (m/s)", 3, 8, 14, 15, 0}, {"current (A)", 4, 9, 16, 17, 0}});
}

std::string TuneMovePlotScript(const std::string& csv, const std::string& output) {
  return TwoPanelScript(csv, output, "the move: current and proposed setting",
                        {{"position (m)", 3, 9, 14, 15, 8}, {"current (A)", 5, 11, 18, 19, 0}});
}

}  // namespace axis
