#include "discovery/frequency_response.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "common/format.h"
#include "estimation/evaluate_experiment.h"
#include "io/atomic_file.h"
#include "sim/linearisation.h"

namespace axis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kZ95 = 1.959963984540054;
constexpr double kPi = 3.14159265358979323846;
// Below this median coherence of the noise-free model the record drives it
// beyond its linear range (a limit, friction near zero velocity, backlash).
constexpr double kSmallSignalCoherence = 0.9;
// The longest segment (samples): a longer record gives more averages, not
// finer bins (2048 bins keep report.json and the plots small).
constexpr int kMaxSegment = 4096;

// The linear model's modes at the steady state under u: the resonances
// first, then each channel's anti-resonances, as LinearMode lists.
struct ModeSet {
  std::string blocker;
  OperatingPoint point;
  std::vector<LinearMode> resonances;
  std::vector<std::vector<LinearMode>> anti;
};

ModeSet ModesAt(const AxisStructure& structure, const AxisParams<double>& p,
                const AxisState<double>& start, double u, const std::vector<Channel>& channels) {
  ModeSet m;
  m.point = FindOperatingPoint(structure, p, start, u);
  m.blocker = LinearModelBlocker(structure, p, m.point);
  if (!m.blocker.empty()) return m;
  const LinearisedAxis system = Linearise(structure, p, m.point.state, u, channels);
  m.resonances = Resonances(system);
  for (size_t j = 0; j < channels.size(); ++j) m.anti.push_back(AntiResonances(system, j));
  return m;
}

// The mode of `list` nearest to `root`, or nullptr.
const LinearMode* Nearest(const std::vector<LinearMode>& list, std::complex<double> root) {
  const LinearMode* best = nullptr;
  for (const LinearMode& m : list) {
    if (best == nullptr || std::abs(m.root - root) < std::abs(best->root - root)) best = &m;
  }
  return best;
}

// Applies `visit(set, k)` to every mode of a ModeSet in a fixed order:
// set −1 the resonances, set j ≥ 0 channel j's anti-resonances.
template <typename F>
void ForEachMode(const ModeSet& m, F visit) {
  for (size_t k = 0; k < m.resonances.size(); ++k) visit(-1, k, m.resonances[k]);
  for (size_t j = 0; j < m.anti.size(); ++j) {
    for (size_t k = 0; k < m.anti[j].size(); ++k) visit(static_cast<int>(j), k, m.anti[j][k]);
  }
}

const std::vector<LinearMode>& ModeList(const ModeSet& m, int set) {
  return set < 0 ? m.resonances : m.anti[set];
}

double Median(std::vector<double> x) {
  if (x.empty()) return kNaN;
  std::nth_element(x.begin(), x.begin() + x.size() / 2, x.end());
  return x[x.size() / 2];
}

// "29.453 ± 0.00043 Hz (zeta 0.031)": the frequency, the half-width of its
// 95 % interval, the damping.
std::string ModeText(const ModeEstimate& m) {
  std::string s = FormatNumber(m.frequency, 5);
  if (std::isfinite(m.std_error)) s += " ± " + FormatNumber(m.ci95_high - m.frequency, 2);
  return s + " Hz (zeta " + FormatNumber(m.damping, 2) + ")";
}

nlohmann::json ModesJson(const std::vector<ModeEstimate>& modes) {
  nlohmann::json out = nlohmann::json::array();
  for (const ModeEstimate& m : modes) {
    out.push_back({{"frequency_hz", JsonNumber<nlohmann::json>(m.frequency)},
                   {"damping", JsonNumber<nlohmann::json>(m.damping)},
                   {"std_error_hz", JsonNumber<nlohmann::json>(m.std_error)},
                   {"ci95_low_hz", JsonNumber<nlohmann::json>(m.ci95_low)},
                   {"ci95_high_hz", JsonNumber<nlohmann::json>(m.ci95_high)}});
  }
  return out;
}

nlohmann::json ComplexJson(const std::vector<std::complex<double>>& h, bool phase) {
  nlohmann::json out = nlohmann::json::array();
  for (const std::complex<double>& x : h) {
    out.push_back(JsonNumber<nlohmann::json>(phase ? std::arg(x) * 180.0 / kPi : std::abs(x)));
  }
  return out;
}

}  // namespace

Eigen::MatrixXd ParameterCovariance(const FitResult& result) {
  const Eigen::Index n = static_cast<Eigen::Index>(result.free_names.size());
  if (result.correlation.rows() != n || result.correlation.cols() != n) return {};
  Eigen::VectorXd se(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    se(i) = kNaN;
    for (const ParameterEstimate& p : result.parameters) {
      if (p.free && p.name == result.free_names[i]) se(i) = p.std_error;
    }
  }
  if (!se.allFinite() || !result.correlation.allFinite()) return {};
  return se.asDiagonal() * result.correlation * se.asDiagonal();
}

LinearModelModes LinearModelWithIntervals(const AxisConfig& model,
                                          const AxisState<double>& start, double u,
                                          const std::vector<Channel>& channels,
                                          const std::vector<std::string>& free,
                                          const Eigen::MatrixXd& covariance,
                                          const std::vector<ParameterTie>& ties) {
  const Eigen::Index n = static_cast<Eigen::Index>(free.size());
  const bool intervals = covariance.size() > 0;
  if (intervals && (covariance.rows() != n || covariance.cols() != n)) {
    throw std::invalid_argument("LinearModelWithIntervals: expected a covariance of " +
                                std::to_string(n) + "x" + std::to_string(n) + ", got " +
                                std::to_string(covariance.rows()) + "x" +
                                std::to_string(covariance.cols()));
  }
  const AxisStructure structure = AveragedStructure(model.structure);
  const ModeSet at = ModesAt(structure, model.params, start, u, channels);
  LinearModelModes out;
  out.blocker = at.blocker;
  out.point = at.point;
  out.anti_resonances.resize(at.anti.size());
  if (!at.blocker.empty()) return out;
  // The derivatives of every mode's frequency in each free parameter.
  std::vector<Eigen::VectorXd> gradient;
  ForEachMode(at, [&](int, size_t, const LinearMode&) {
    gradient.push_back(Eigen::VectorXd::Zero(n));
  });
  const std::vector<std::pair<int, int>> tie_indices = TieIndices(ties);
  for (Eigen::Index j = 0; intervals && j < n; ++j) {
    AxisParams<double> p = model.params;
    double* value = FindParam(&p, free[j]);
    if (value == nullptr) {
      throw std::invalid_argument("LinearModelWithIntervals: expected a parameter name of the "
                                  "model, got '" + free[j] + "'");
    }
    const double x = *value;
    const double sd = std::sqrt(std::max(covariance(j, j), 0.0));
    const double h = x != 0.0 ? 1e-5 * std::abs(x) : (sd > 0.0 ? 1e-3 * sd : 1e-8);
    *value = x + h;
    ApplyTies(tie_indices, &p);
    const ModeSet up = ModesAt(structure, p, start, u, channels);
    *value = x - h;
    ApplyTies(tie_indices, &p);
    const ModeSet down = ModesAt(structure, p, start, u, channels);
    size_t i = 0;
    ForEachMode(at, [&](int set, size_t, const LinearMode& m) {
      const bool ok = up.blocker.empty() && down.blocker.empty();
      const LinearMode* a = ok ? Nearest(ModeList(up, set), m.root) : nullptr;
      const LinearMode* b = ok ? Nearest(ModeList(down, set), m.root) : nullptr;
      gradient[i++](j) = a != nullptr && b != nullptr ? (a->frequency - b->frequency) / (2 * h)
                                                      : kNaN;
    });
  }
  size_t i = 0;
  ForEachMode(at, [&](int set, size_t, const LinearMode& m) {
    ModeEstimate e;
    e.frequency = m.frequency;
    e.damping = m.damping;
    const Eigen::VectorXd& g = gradient[i++];
    e.std_error = intervals ? std::sqrt(std::max(g.dot(covariance * g), 0.0)) : kNaN;
    e.ci95_low = e.frequency - kZ95 * e.std_error;
    e.ci95_high = e.frequency + kZ95 * e.std_error;
    (set < 0 ? out.resonances : out.anti_resonances[set]).push_back(e);
  });
  return out;
}

std::vector<double> ExperimentInput(const FitExperiment& e, bool rotary, std::string* name,
                                    std::string* unit) {
  const Drive& d = e.drive;
  std::vector<double> u(e.t.size());
  for (size_t k = 0; k < e.t.size(); ++k) {
    const double t = e.t[k];
    if (!d.closed_loop) {
      u[k] = d.input.Evaluate(t);
    } else if (d.has_injection) {
      u[k] = d.injection.Evaluate(t);
    } else if (d.reference.kind == Reference::Kind::kTable) {
      u[k] = d.reference.table.Evaluate(t);
    } else {
      u[k] = d.reference.Profile(t);
    }
  }
  if (!d.closed_loop) {
    *name = "U";
    *unit = "V";
  } else if (d.has_injection) {
    *name = "injection";
    *unit = d.has_supply ? "duty" : "V";
  } else {
    *name = "x_ref";
    *unit = ChannelUnit(Channel::kXRef, rotary);
  }
  return u;
}

namespace {

// The H1 of `u` to `y` on the bins of `band`, appended to `freq`, `h`, `coh`.
void BandResponse(const std::vector<double>& u, const std::vector<double>& y, double dt,
                  int segment_length, const BandExcitation& band, std::vector<double>* freq,
                  std::vector<std::complex<double>>* h, std::vector<double>* coh) {
  WelchOptions options;
  options.segment_length = segment_length;
  const FrequencyResponseEstimate e = EstimateH1(ComputeWelchSpectra(u, y, dt, options));
  for (size_t k = 1; k < e.frequency.size(); ++k) {
    if (e.frequency[k] < band.f_low || e.frequency[k] > band.f_high) continue;
    if (freq != nullptr) freq->push_back(e.frequency[k]);
    h->push_back(e.h1[k]);
    coh->push_back(e.coherence[k]);
  }
}

// The analysis of one experiment whose input excites a band.
void AnalyseChannels(const EstimationProblem& job, const FitExperiment& e,
                     const std::vector<double>& u, const FitResult& result,
                     ExperimentFrequencyResponse* r) {
  const ExperimentFit fit = EvaluateExperiment(job.model.structure, job.model.params, e);
  const bool rotary = job.model.structure.motion == Motion::kRotary;
  std::vector<Channel> linear_channels;
  for (const FittedChannel& f : e.fitted) {
    if (IsStateChannel(f.channel)) linear_channels.push_back(f.channel);
  }
  if (e.drive.closed_loop) {
    r->linear.blocker = "a closed loop (the sampled controller is not linearised)";
  } else {
    r->linear = LinearModelWithIntervals(job.model, e.initial_state, r->mean_input,
                                         linear_channels, result.free_names,
                                         ParameterCovariance(result), job.ties);
  }
  LinearisedAxis system;
  if (r->linear.blocker.empty()) {
    system = Linearise(AveragedStructure(job.model.structure), job.model.params,
                       r->linear.point.state, r->mean_input, linear_channels);
  }
  for (const FittedChannel& f : e.fitted) {
    const ChannelFit* cf = nullptr;
    for (const ChannelFit& c : fit.channels) {
      if (c.channel == ChannelName(f.channel)) cf = &c;
    }
    if (cf == nullptr) continue;
    for (double y : cf->simulated) {
      if (!std::isfinite(y)) {
        throw std::runtime_error("experiment '" + e.name +
                                 "': simulation failed at the fitted parameters");
      }
    }
    const size_t n = std::min({u.size(), cf->measured.size(), cf->simulated.size()});
    const std::vector<double> un(u.begin(), u.begin() + n);
    ChannelFrequencyResponse c;
    c.channel = ChannelName(f.channel);
    c.unit = ChannelUnit(f.channel, rotary);
    BandResponse(un, std::vector<double>(cf->measured.begin(), cf->measured.begin() + n),
                 r->sample_period, r->segment_length, r->band, &c.frequency, &c.data,
                 &c.data_coherence);
    BandResponse(un, std::vector<double>(cf->simulated.begin(), cf->simulated.begin() + n),
                 r->sample_period, r->segment_length, r->band, nullptr, &c.model,
                 &c.model_coherence);
    const auto row = std::find(linear_channels.begin(), linear_channels.end(), f.channel);
    if (r->linear.blocker.empty() && row != linear_channels.end()) {
      const size_t j = static_cast<size_t>(row - linear_channels.begin());
      for (double fr : c.frequency) c.linear.push_back(LinearResponse(system, j, fr));
      c.anti_resonances = r->linear.anti_resonances[j];
    }
    r->channels.push_back(std::move(c));
  }
}

}  // namespace

std::vector<ExperimentFrequencyResponse> AnalyseFrequencyResponse(
    const EstimationProblem& job, const FitResult& result,
    const FrequencyResponseSettings& settings) {
  std::vector<ExperimentFrequencyResponse> out;
  const bool rotary = job.model.structure.motion == Motion::kRotary;
  for (const FitExperiment& e : job.experiments) {
    ExperimentFrequencyResponse r;
    r.experiment = e.name;
    const std::vector<double> u = ExperimentInput(e, rotary, &r.input, &r.input_unit);
    r.sample_period = e.t.size() > 1 ? e.t[1] - e.t[0] : e.options.output_period;
    r.segment_length = std::min(WelchSegmentLength(u.size(), settings.min_averages), kMaxSegment);
    if (r.segment_length == 0 || !(r.sample_period > 0.0)) {
      r.note = r.input + ": a record of " + std::to_string(u.size()) + " samples, too short for " +
               std::to_string(settings.min_averages) + " averages of 16";
      out.push_back(std::move(r));
      continue;
    }
    WelchOptions options;
    options.segment_length = r.segment_length;
    const WelchSpectra s = ComputeWelchSpectra(u, u, r.sample_period, options);
    r.averages = s.averages;
    r.band = FindExcitedBand(s);
    r.mean_input = std::accumulate(u.begin(), u.end(), 0.0) / static_cast<double>(u.size());
    if (!r.band.band) {
      r.note = r.input + ": " + r.band.reason + "; no frequency response";
    } else {
      AnalyseChannels(job, e, u, result, &r);
    }
    out.push_back(std::move(r));
  }
  return out;
}

std::string FormatFrequencyResponse(const std::vector<ExperimentFrequencyResponse>& responses) {
  if (responses.empty()) return "";
  TextTable table;
  table.headers = {"experiment", "input", "channel", "band (Hz)", "averages",
                   "coherence data", "coherence model", "anti-resonances (± 95 %)"};
  table.right = {false, false, false, false, true, true, true, false};
  std::string notes;
  for (const ExperimentFrequencyResponse& r : responses) {
    if (!r.note.empty()) {
      notes += "  " + r.experiment + ": " + r.note + "\n";
      continue;
    }
    for (const ChannelFrequencyResponse& c : r.channels) {
      std::vector<std::string> anti;
      for (const ModeEstimate& m : c.anti_resonances) anti.push_back(ModeText(m));
      table.rows.push_back({r.experiment, r.input, c.channel,
                            FormatNumber(r.band.f_low, 3) + "-" + FormatNumber(r.band.f_high, 3),
                            std::to_string(r.averages), FormatNumber(Median(c.data_coherence), 3),
                            FormatNumber(Median(c.model_coherence), 3),
                            anti.empty() ? "-" : Join(anti, "; ")});
    }
    std::vector<std::string> res;
    for (const ModeEstimate& m : r.linear.resonances) res.push_back(ModeText(m));
    notes += "  " + r.experiment + ": linear model at u = " + FormatNumber(r.mean_input, 4) +
             " " + r.input_unit + ": " +
             (!r.linear.blocker.empty() ? "none, " + r.linear.blocker
              : res.empty()             ? "no resonance"
                                        : "resonances " + Join(res, "; ")) +
             "\n";
    double least = 1.0;
    for (const ChannelFrequencyResponse& c : r.channels) {
      least = std::min(least, Median(c.model_coherence));
    }
    if (least < kSmallSignalCoherence) {
      notes += "  " + r.experiment + ": the model's own coherence (median " +
               FormatNumber(least, 2) +
               ") says the record is not small-signal: compare the data with the model's H1\n";
    }
  }
  std::string out =
      "frequency response (H1 of the input to each fitted channel; Welch, Hann, 50 % overlap; "
      "coherence: median over the band)\n";
  if (!table.rows.empty()) out += RenderText(table);
  return out + notes;
}

nlohmann::json FrequencyResponseToJson(const std::vector<ExperimentFrequencyResponse>& responses) {
  nlohmann::json out = nlohmann::json::array();
  for (const ExperimentFrequencyResponse& r : responses) {
    nlohmann::json e = {{"experiment", r.experiment},
                        {"input", r.input},
                        {"input_unit", r.input_unit},
                        {"band", r.band.band},
                        {"note", r.note}};
    if (r.note.empty()) {
      e["band_low_hz"] = JsonNumber<nlohmann::json>(r.band.f_low);
      e["band_high_hz"] = JsonNumber<nlohmann::json>(r.band.f_high);
      e["averages"] = r.averages;
      e["segment_length"] = r.segment_length;
      e["sample_period"] = JsonNumber<nlohmann::json>(r.sample_period);
      e["linear_model"] = {{"input", JsonNumber<nlohmann::json>(r.mean_input)},
                           {"available", r.linear.blocker.empty()},
                           {"note", r.linear.blocker},
                           {"resonances", ModesJson(r.linear.resonances)}};
      nlohmann::json channels = nlohmann::json::array();
      for (const ChannelFrequencyResponse& c : r.channels) {
        channels.push_back({{"channel", c.channel},
                            {"unit", c.unit + "/" + r.input_unit},
                            {"frequency_hz", c.frequency},
                            {"data_magnitude", ComplexJson(c.data, false)},
                            {"data_phase_deg", ComplexJson(c.data, true)},
                            {"data_coherence", c.data_coherence},
                            {"model_magnitude", ComplexJson(c.model, false)},
                            {"model_phase_deg", ComplexJson(c.model, true)},
                            {"model_coherence", c.model_coherence},
                            {"linear_magnitude", ComplexJson(c.linear, false)},
                            {"linear_phase_deg", ComplexJson(c.linear, true)},
                            {"anti_resonances", ModesJson(c.anti_resonances)}});
      }
      e["channels"] = channels;
    }
    out.push_back(e);
  }
  return out;
}

void WriteFrequencyResponseCsv(const std::string& path, const ExperimentFrequencyResponse&,
                               const ChannelFrequencyResponse& c) {
  std::ostringstream s;
  s.precision(10);
  s << "f,data_db,data_deg,data_coherence,model_db,model_deg,model_coherence,linear_db,"
       "linear_deg\n";
  // Magnitude (dB) and phase (deg), empty cells where |H| is 0 or not finite.
  const auto bode = [](std::complex<double> h) {
    const double m = std::abs(h);
    if (!(m > 0.0) || !std::isfinite(m)) return std::string(",");
    return FormatNumber(20.0 * std::log10(m), 10) + "," +
           FormatNumber(std::arg(h) * 180.0 / kPi, 10);
  };
  for (size_t k = 0; k < c.frequency.size(); ++k) {
    s << c.frequency[k] << "," << bode(c.data[k]) << "," << c.data_coherence[k] << ","
      << bode(c.model[k]) << "," << c.model_coherence[k] << ","
      << (k < c.linear.size() ? bode(c.linear[k]) : std::string(",")) << "\n";
  }
  WriteFileAtomic(path, s.str());
}

std::string BodePlotScript(const ExperimentFrequencyResponse& r,
                           const ChannelFrequencyResponse& c, const std::string& csv_path,
                           const std::string& output, bool svg) {
  std::ostringstream s;
  if (svg) {
    s << "set terminal svg size 1000,760 dynamic noenhanced font 'sans,12' background rgb "
         "'white'; ";
  } else {
    s << "set terminal pngcairo size 1200,900 noenhanced; ";
  }
  const std::string file = "'" + csv_path + "'";
  const std::string lin = c.linear.empty() ? "" : ", " + file;
  s << "set output '" << output << "'; set datafile separator ','; set datafile missing ''; "
    << "set grid; set logscale x; set autoscale xfix; set key below; set multiplot layout 3,1 title '" << r.experiment
    << ": " << r.input << " to " << c.channel << "';"
    << "set ylabel '|H| (dB re 1 " << c.unit << "/" << r.input_unit << ")'; unset xlabel;"
    << "plot " << file << " using 1:2 skip 1 with points pt 7 ps 0.4 title 'data H1', " << file
    << " using 1:5 skip 1 with lines lw 2 title 'model at the estimate, H1'"
    << (lin.empty() ? "" : lin + " using 1:8 skip 1 with lines dt 2 lw 2 title 'linear model'")
    << ";"
    << "set ylabel 'phase (deg)'; set yrange [-180:180]; set ytics 90;"
    << "plot " << file << " using 1:3 skip 1 with points pt 7 ps 0.4 notitle, " << file
    << " using 1:6 skip 1 with points pt 6 ps 0.4 notitle"
    << (lin.empty() ? "" : lin + " using 1:9 skip 1 with points pt 1 ps 0.4 notitle") << ";"
    << "set ylabel 'coherence'; set yrange [0:1.05]; set ytics auto; set xlabel 'frequency (Hz)';"
    << "plot " << file << " using 1:4 skip 1 with lines title 'data', " << file
    << " using 1:7 skip 1 with lines title 'model';"
    << "unset multiplot";
  return s.str();
}

}  // namespace axis
