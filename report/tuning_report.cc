#include "report/tuning_report.h"

#include <cmath>
#include <sstream>

#include "common/format.h"
#include "sim/config.h"
#include "sim/csv.h"

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

Json SettingJson(const TunedSetting& s) {
  Json spread = Json::array();
  for (const FigureSpread& f : s.spread) {
    spread.push_back({{"figure", f.figure},
                      {"at_estimate", JsonNumber<Json>(f.at_estimate)},
                      {"low", JsonNumber<Json>(f.low)},
                      {"high", JsonNumber<Json>(f.high)},
                      {"limiting", f.limiting}});
  }
  return {{"K1", JsonNumber<Json>(s.K1)},
          {"T_p", JsonNumber<Json>(s.T_p)},
          {"metrics", MetricsJson(s.metrics)},
          {"violations", s.violations},
          {"spread", spread},
          {"robust", s.robust},
          {"robust_violations", s.robust_violations}};
}

// The table of both settings' figures.
std::string FiguresTable(const AnalogLoopTuning& t) {
  TextTable table;
  table.headers = {"figure", "unit", "current", "over the intervals", "proposed",
                   "over the intervals", "limited by", "spec"};
  table.right = {false, false, true, true, true, true, false, false};
  for (size_t f = 0; f < t.proposed.spread.size() && f < t.current.spread.size(); ++f) {
    const FigureSpread& c = t.current.spread[f];
    const FigureSpread& p = t.proposed.spread[f];
    table.rows.push_back({p.figure, Unit(p.figure), Cell(c.at_estimate),
                          Cell(c.low) + " .. " + Cell(c.high), Cell(p.at_estimate),
                          Cell(p.low) + " .. " + Cell(p.high), p.limiting.empty() ? "-" : p.limiting,
                          Bound(t.spec, p.figure)});
  }
  return RenderText(table);
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
    const char* name = setting == &t.current ? "current" : "proposed";
    if (setting->robust) {
      out << "  " << name << ": meets the spec at the estimate and at every interval end\n";
    } else {
      out << "  " << name << ": does not meet the spec"
          << (setting->violations.empty() ? " at every interval end" : "") << ":";
      for (const std::string& v : setting->violations) out << " " << v << ";";
      for (const std::string& v : setting->robust_violations) out << " " << v << ";";
      out << "\n";
    }
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
  const StepResponse& c = t.current.response;
  const StepResponse& p = t.proposed.response;
  const StepResponse& lo = t.proposed.band_low;
  const StepResponse& hi = t.proposed.band_high;
  const size_t n = c.t.size();
  if (c.finite && p.finite && n > 0 && p.t.size() == n && lo.t.size() == n && hi.t.size() == n) {
    WriteCsvAtomic(dir + "/tune_step.csv",
                   {"t", "x_current", "v_current", "i_current", "vm_current", "fg_current",
                    "x_proposed", "v_proposed", "i_proposed", "vm_proposed", "fg_proposed",
                    "x_proposed_low", "x_proposed_high", "v_proposed_low", "v_proposed_high",
                    "i_proposed_low", "i_proposed_high", "fg_proposed_low", "fg_proposed_high"},
                   {c.t, c.x, c.v, c.i, c.vm, c.fg, p.x, p.v, p.i, p.vm, p.fg, lo.x, hi.x, lo.v,
                    hi.v, lo.i, hi.i, lo.fg, hi.fg});
    files->push_back("tune_step.csv");
  }
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

}  // namespace axis
