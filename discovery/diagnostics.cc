#include "discovery/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "common/concurrency.h"
#include "common/gnuplot.h"
#include "common/statistics.h"
#include "estimation/evaluate_experiment.h"
#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"
#include "io/csv.h"

namespace axis {
namespace {

constexpr int kBins = 12;
constexpr int kMinCount = 10;
constexpr double kTwoPi = 6.283185307179586476925;

BinnedResidual Bin(const std::string& variable, const std::string& unit,
                   const std::vector<double>& x, const std::vector<double>& r) {
  BinnedResidual b;
  b.variable = variable;
  b.unit = unit;
  const auto [lo_it, hi_it] = std::minmax_element(x.begin(), x.end());
  const double lo = *lo_it, hi = *hi_it;
  double mean = 0.0, var = 0.0;
  for (double e : r) mean += e / r.size();
  for (double e : r) var += (e - mean) * (e - mean) / std::max<size_t>(1, r.size() - 1);
  const double s = std::sqrt(var);
  b.width = (hi - lo) / kBins;
  if (!(hi > lo) || !(s > 0.0)) return b;
  std::vector<double> sum(kBins, 0.0);
  std::vector<int> count(kBins, 0);
  for (size_t k = 0; k < x.size(); ++k) {
    int j = static_cast<int>((x[k] - lo) / (hi - lo) * kBins);
    j = std::clamp(j, 0, kBins - 1);
    sum[j] += r[k];
    ++count[j];
  }
  for (int j = 0; j < kBins; ++j) {
    if (count[j] < kMinCount) continue;
    const double m = sum[j] / count[j];
    const double se = s / std::sqrt(static_cast<double>(count[j]));
    b.center.push_back(lo + (j + 0.5) * (hi - lo) / kBins);
    b.mean.push_back(m);
    b.std_error.push_back(se);
    b.count.push_back(count[j]);
    b.chi2 += (m / se) * (m / se);
    ++b.dof;
  }
  if (b.dof > 0) b.p_value = ChiSquaredSurvival(b.chi2, b.dof);
  return b;
}

// "x in [0.12, 0.31] m" style ranges of the bins of `b` whose own χ²₁ has
// p below `threshold`; empty if none.
std::string SignificantRanges(const BinnedResidual& b, double threshold) {
  std::ostringstream out;
  out << std::setprecision(3);
  int runs = 0;
  for (size_t j = 0; j < b.center.size();) {
    const auto significant = [&](size_t k) {
      const double z = b.mean[k] / b.std_error[k];
      return ChiSquaredSurvival(z * z, 1) < threshold;
    };
    if (!significant(j)) {
      ++j;
      continue;
    }
    size_t end = j;
    // A run: consecutive significant bins (adjacent centres one width apart).
    while (end + 1 < b.center.size() && significant(end + 1) &&
           b.center[end + 1] - b.center[end] < 1.5 * b.width) {
      ++end;
    }
    out << (runs++ ? ", " : "") << "[" << b.center[j] - 0.5 * b.width << ", "
        << b.center[end] + 0.5 * b.width << "]";
    j = end + 1;
  }
  return out.str();
}

}  // namespace

std::vector<ChannelDiagnostics> DiagnoseResiduals(const EstimationProblem& job) {
  std::vector<ChannelDiagnostics> out;
  for (const FitExperiment& e : job.experiments) {
    const ExperimentFit fit = EvaluateExperiment(job.model.structure, job.model.params, e);
    SimulationOptions options = e.options;
    options.channels = {Channel::kV, Channel::kX, Channel::kA, Channel::kTheta};
    const SimulationGrid grid = MakeGrid(options, e.drive);
    const Trace<double> trace = Simulate(job.model.structure, job.model.params,
                                         e.initial_state, e.drive, options, grid);
    if (!trace.finite) {
      throw std::runtime_error("experiment '" + e.name +
                               "': simulation failed at the fitted parameters");
    }
    std::vector<double> angle = trace[Channel::kTheta];
    for (double& a : angle) a -= kTwoPi * std::floor(a / kTwoPi);
    for (const ChannelFit& c : fit.channels) {
      if (!c.fitted) continue;
      ChannelDiagnostics d;
      d.experiment = e.name;
      d.channel = c.channel;
      d.unit = c.unit;
      d.rms = c.rms;
      d.sigma = c.sigma;
      d.ljung_box_p = c.ljung_box_p;
      d.xcorr_peak = c.input_xcorr_peak;
      d.xcorr_lag = c.input_xcorr_lag;
      std::vector<double> r(c.measured.size());
      for (size_t k = 0; k < r.size(); ++k) r[k] = c.simulated[k] - c.measured[k];
      // Over the fitted samples (a record simulated past them: a tail
      // left unfitted, estimation/record_prefix.h).
      const auto head = [&r](std::vector<double> values) {
        values.resize(std::min(values.size(), r.size()));
        return values;
      };
      const bool rotary = job.model.structure.motion == Motion::kRotary;
      d.bins.push_back(Bin("v", ChannelUnit(Channel::kV, rotary), head(trace[Channel::kV]), r));
      d.bins.push_back(Bin("x", ChannelUnit(Channel::kX, rotary), head(trace[Channel::kX]), r));
      d.bins.push_back(Bin("a", ChannelUnit(Channel::kA, rotary), head(trace[Channel::kA]), r));
      d.bins.push_back(Bin("theta mod rev", "rad", head(angle), r));
      out.push_back(d);
    }
  }
  return out;
}

std::string FormatDiagnostics(const std::vector<ChannelDiagnostics>& diags) {
  std::ostringstream out;
  out << "Residual diagnostics (binned mean residual: chi2 p-value, largest |mean|)\n";
  out << "  experiment  channel  LB p       xcorr u (lag)   ";
  if (!diags.empty()) {
    for (const BinnedResidual& b : diags[0].bins) out << std::setw(24) << ("vs " + b.variable);
  }
  out << "\n";
  for (const ChannelDiagnostics& d : diags) {
    out << "  " << std::left << std::setw(12) << d.experiment << std::setw(9)
        << d.channel << std::right << std::setw(9) << std::setprecision(3)
        << d.ljung_box_p << std::setw(10) << d.xcorr_peak << " (" << std::setw(3)
        << d.xcorr_lag << ")   ";
    for (const BinnedResidual& b : d.bins) {
      double peak = 0.0;
      for (double m : b.mean) peak = std::max(peak, std::abs(m));
      std::ostringstream cell;
      cell << std::setprecision(2) << b.p_value << ", " << std::setprecision(3) << peak;
      out << std::setw(24) << cell.str();
    }
    out << "\n";
  }
  return out.str();
}

void WriteDiagnosticsCsv(const std::string& path, const ChannelDiagnostics& d) {
  std::ostringstream csv;
  csv << "variable,center,mean,std_error,count\n" << std::setprecision(12);
  for (const BinnedResidual& b : d.bins) {
    for (size_t j = 0; j < b.center.size(); ++j) {
      csv << '"' << b.variable << "\"," << b.center[j] << "," << b.mean[j] << ","
          << b.std_error[j] << "," << b.count[j] << "\n";
    }
  }
  WriteFileAtomic(path, csv.str());
}

std::string DiagnosticsPlotScript(const ChannelDiagnostics& d, const std::string& csv_path,
                                  const std::string& output, bool svg) {
  std::ostringstream s;
  if (svg) {
    s << "set terminal svg size 1000,640 dynamic noenhanced font 'sans,12' background rgb "
         "'white'; ";
  } else {
    s << "set terminal pngcairo size 1200,800 noenhanced; ";
  }
  s << "set output '" << output
    << "'; set datafile separator ','; set grid; " << (svg ? "set key below; " : "")
    << "set multiplot layout 2,2 title 'mean "
    << d.channel << " residual (" << d.unit << "), " << d.experiment << "';";
  for (const BinnedResidual& b : d.bins) {
    s << "set title 'vs " << b.variable << "'; set xlabel '" << b.variable << " ("
      << b.unit << ")'; set ylabel 'residual (" << d.unit << ")';"
      << "plot '" << csv_path << "' using (strcol(1) eq '" << b.variable
      << "' ? $2 : 1/0):3:4 with yerrorbars " << (svg ? "title 'bin mean, ±1 std error'" : "notitle")
      << ", 0 with lines lc rgb 'gray' notitle;";
  }
  s << "unset multiplot";
  return s.str();
}

void WriteDiagnostics(const std::string& dir,
                      const std::vector<ChannelDiagnostics>& diags,
                      std::vector<std::string>* warnings) {
  // Several gnuplot runs at once (ProcessThreads), the warnings in order.
  std::vector<std::string> failed(diags.size());
  ForEachConcurrently(diags.size(), ProcessThreads(), [&](size_t k) {
    const ChannelDiagnostics& d = diags[k];
    const std::string stem = dir + "/diag_" + d.experiment + "_" + d.channel;
    WriteDiagnosticsCsv(stem + ".csv", d);
    const auto script = [&](const std::string& png) {
      return DiagnosticsPlotScript(d, stem + ".csv", png, false);
    };
    std::string warning;
    if (!RenderGnuplotPng(stem + ".png", script, d.experiment + " " + d.channel, &warning)) {
      failed[k] = warning;
    }
  });
  for (const std::string& warning : failed) {
    if (warnings != nullptr && !warning.empty()) warnings->push_back(warning);
  }
}

ResidualVerdict JudgeResiduals(const std::vector<ChannelDiagnostics>& diagnostics,
                               const FitResult& fit, double alpha) {
  if (!(alpha > 0.0)) {
    throw std::invalid_argument("JudgeResiduals: expected a level alpha > 0, got " +
                                std::to_string(alpha));
  }
  ResidualVerdict v;
  v.tests = 1;
  for (const ChannelDiagnostics& d : diagnostics) {
    v.tests += 1;
    for (const BinnedResidual& b : d.bins) v.tests += b.dof > 0 ? 1 : 0;
  }
  v.threshold = alpha / v.tests;
  // The fit's own s² and degrees of freedom (m − edf after a kept force
  // map: not an integer; the χ² tail at the nearest one).
  const double dof = fit.residual_dof;
  const bool has_dof = dof >= 0.5;
  v.s2 = has_dof ? fit.residual_variance : std::numeric_limits<double>::quiet_NaN();
  v.s2_p_value = has_dof ? ChiSquaredSurvival(fit.residual_variance * dof,
                                              static_cast<int>(std::lround(dof)))
                         : std::numeric_limits<double>::quiet_NaN();
  std::ostringstream head;
  head << std::setprecision(3);
  if (!(v.s2_p_value >= v.threshold)) {
    head << "s^2 = " << v.s2 << " (p " << v.s2_p_value
         << "): the residual is larger than the declared noise";
    v.remains.push_back(head.str());
  }
  for (const ChannelDiagnostics& d : diagnostics) {
    std::ostringstream line;
    line << std::setprecision(3) << d.experiment << "/" << d.channel << ": RMS " << d.rms
         << " " << d.unit << " = " << (d.sigma > 0.0 ? d.rms / d.sigma : 0.0) << " sigma";
    std::vector<std::string> found;
    if (!(d.ljung_box_p >= v.threshold)) {
      std::ostringstream f;
      f << std::setprecision(3) << "not white (Ljung-Box p " << d.ljung_box_p << ")";
      found.push_back(f.str());
    }
    for (const BinnedResidual& b : d.bins) {
      if (b.dof == 0 || b.p_value >= v.threshold) continue;
      double largest = 0.0;
      for (double m : b.mean) largest = std::max(largest, std::abs(m));
      const std::string ranges = SignificantRanges(b, v.threshold / b.dof);
      std::ostringstream f;
      f << std::setprecision(3) << "mean residual depends on " << b.variable << " (chi2 p "
        << b.p_value << "): "
        << (ranges.empty() ? "spread over its range"
                           : "significant for " + b.variable + " in " + ranges + " " + b.unit)
        << " (largest |mean| " << largest << " " << d.unit << ")";
      found.push_back(f.str());
    }
    for (const std::string& f : found) v.remains.push_back(d.experiment + "/" + d.channel + ": " + f);
    if (found.empty()) line << "; white, no structure";
    v.channels.push_back(line.str());
  }
  v.verdict = v.remains.empty() ? "explained" : "incomplete";
  return v;
}

std::string FormatVerdict(const ResidualVerdict& v) {
  std::ostringstream out;
  out << std::setprecision(4);
  out << "Verdict: " << v.verdict << " (s^2 = " << v.s2 << ", p " << v.s2_p_value << "; "
      << v.tests << " tests at " << v.threshold << " each)\n";
  for (const std::string& c : v.channels) out << "  " << c << "\n";
  if (!v.remains.empty()) {
    out << "What remains:\n";
    for (const std::string& r : v.remains) out << "  - " << r << "\n";
  }
  return out.str();
}

}  // namespace axis
