#include "discovery/significance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <vector>

#include "common/statistics.h"
#include "sim/channels.h"
#include "discovery/candidates.h"
#include "discovery/internal/find_estimate.h"

namespace axis {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

EffectSignificance EffectWald(const std::string& effect, const FitResult& fit) {
  const Candidate candidate = CandidateNamed(effect);
  const std::string& base = candidate.effect;
  const std::vector<CandidateColumn>& columns = candidate.columns;
  EffectSignificance w;
  w.effect = effect;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Free parameter k of the fit: its index in the correlation matrix.
  const auto index = [&](const std::string& name) -> int {
    for (size_t k = 0; k < fit.free_names.size(); ++k) {
      if (fit.free_names[k] == name) return static_cast<int>(k);
    }
    return -1;
  };
  const auto estimate = [&](const std::string& name) { return FindEstimate(fit, name); };
  const auto covariance = [&](const std::string& a, const std::string& b) {
    const int i = index(a), j = index(b);
    if (i < 0 || j < 0) return 0.0;
    const double rho = fit.correlation.rows() > std::max(i, j) ? fit.correlation(i, j)
                                                               : (i == j ? 1.0 : 0.0);
    return estimate(a)->std_error * estimate(b)->std_error * rho;
  };
  const std::string p = columns[0].param;
  const ParameterEstimate* e = estimate(p);
  double chi2 = nan;
  if (e != nullptr && index(p) >= 0) {
    if (base == "stribeck") {
      const ParameterEstimate* fc = estimate("F_c");
      const double d = e->value - (fc ? fc->value : 0.0);
      const double var = covariance("F_st", "F_st") + covariance("F_c", "F_c") -
                         2.0 * covariance("F_st", "F_c");
      chi2 = d * d / var;
    } else if (base == "stribeck_shape") {
      // The exponent against the Gaussian shape the term had without it.
      const double d = e->value - kGaussianStribeckShape;
      chi2 = d * d / covariance(p, p);
    } else if (base == "cogging") {
      w.dof = 2;
      double var = covariance("A_cog", "A_cog");
      const double var_phi = covariance("phi_cog", "phi_cog");
      if (var_phi > 0.0) var -= covariance("A_cog", "phi_cog") * covariance("A_cog", "phi_cog") / var_phi;
      chi2 = e->value * e->value / var;
    } else if (base == "load_friction") {
      // Both directions' coefficients against 0 jointly: xᵀ·Σ⁻¹·x, dof 2.
      w.dof = 2;
      const ParameterEstimate* back = estimate("mu_b");
      const double x = e->value, y = back != nullptr ? back->value : 0.0;
      const double a = covariance("mu_d", "mu_d"), d = covariance("mu_b", "mu_b");
      const double b = covariance("mu_d", "mu_b");
      const double det = a * d - b * b;
      if (det > 0.0) {
        chi2 = (d * x * x - 2.0 * b * x * y + a * y * y) / det;
      } else {  // one coefficient fixed or on its bound (no variance): the other alone
        w.dof = 1;
        chi2 = a > 0.0 ? x * x / a : d > 0.0 ? y * y / d : nan;
      }
    } else {
      chi2 = e->value * e->value / covariance(p, p);
    }
  }
  w.chi2 = std::isfinite(chi2) ? chi2 : nan;
  w.p_value = std::isfinite(chi2) ? ChiSquaredSurvival(chi2, w.dof) : nan;
  return w;
}

std::string ImplausibleValue(const std::string& effect, const FitResult& fit,
                             const EstimationProblem& job) {
  const auto value = [&](const std::string& name) {
    const ParameterEstimate* e = FindEstimate(fit, name);
    return e ? e->value : std::numeric_limits<double>::quiet_NaN();
  };
  std::ostringstream why;
  if (effect == "payload") {
    const double dm = value("Delta_M");
    if (dm < 0.0) {
      why << "payload Delta_M = " << dm << " " << ParamUnit("Delta_M", job.model.structure.motion)
          << " is below zero: the declared mass M is too "
          << "large (free M instead)";
    }
  } else if (effect == "coulomb" || effect == "motor_coulomb" || effect == "stribeck") {
    // Friction opposes the motion: a negative Coulomb (or static) level
    // pushes the axis along, which no friction does — a stand-in for
    // something else (a misfit of the sensor front end, a drive offset).
    const char* name = effect == "coulomb" ? "F_c" : effect == "stribeck" ? "F_st" : "T_c";
    const std::string unit = " " + ParamUnit(name, job.model.structure.motion);
    const double level = value(name);
    if (level < 0.0) {
      why << effect << " " << name << " = " << level << unit
          << " is below zero: friction opposes the motion, a negative level does not";
    }
  }
  // A Stribeck exponent at its search bound (discovery/candidates.h
  // kStribeckShapeBounds) is a shape pushed as far as it goes — a step at
  // v_st or a spike at rest — a stand-in for something else.
  if (effect == "stribeck_shape") {
    const double delta = value("delta_st");
    const double lo = kStribeckShapeBounds[0], hi = kStribeckShapeBounds[1];
    if (delta <= lo * 1.01 || delta >= hi * 0.99) {
      why << "stribeck_shape delta_st = " << delta << " is at its search bound [" << lo << ", "
          << hi << "]: a shape no friction curve has";
    }
  }
  // The sensor's filters (MODEL.md §6) must be filters of this record: a
  // cut-off above the record's Nyquist frequency cannot be told from none
  // (at f_N = 1/(2T) a first-order filter with f_c above it lags by less
  // than T/π, a fraction of a sample the delay and the sampling convention
  // already cover; seen: τ_lp.a = 6.9 µs kept on a 1 kHz record, a stand-in
  // beside a delay), and a second-order filter at its damping bound is a
  // resonance the fit pushed as far as it could, a stand-in for something
  // else (seen: ζ = 0.05 near 1 kHz standing in for part of a 3 ms delay).
  // Delays have no such rule: any length, sub-sample included, is a
  // recorder's skew.
  const size_t dot = effect.find('.');
  const std::string base = effect.substr(0, dot);
  if ((base == "sensor_lowpass" || base == "sensor_lowpass2") && dot != std::string::npos) {
    const std::string channel = effect.substr(dot + 1);
    const std::optional<Channel> c = ParseChannel(channel);
    double period = 0.0;  // the longest output period of the experiments fitting it
    for (const FitExperiment& e : job.experiments) {
      for (const FittedChannel& f : e.fitted) {
        if (c && f.channel == *c) period = std::max(period, e.options.output_period);
      }
    }
    const std::string tau_name = (base == "sensor_lowpass" ? "tau_lp." : "tau_lp2.") + channel;
    const double tau = value(tau_name);
    // On `a` under a convention nobody declared the filter is seen through
    // a convention that may be the wrong one (a period mean is itself a box
    // filter): a 250 Hz anti-alias filter on instant samples read as period
    // means fits at 574 Hz, and the convention is judged again after the
    // loop with the filter kept (discovery/discovery_session.h). There the
    // bound is the sample rate (τ < T/(2π)).
    const bool unsettled = c && *c == Channel::kA && job.model.declared.count("accelerometer") == 0;
    const double cutoff_limit = unsettled ? 1.0 / period : 0.5 / period;
    if (period > 0.0 && 1.0 / (2.0 * kPi * tau) > cutoff_limit) {
      why << effect << " " << tau_name << " = " << tau << " s puts the cut-off at "
          << 1.0 / (2.0 * kPi * tau) << " Hz, above the record's "
          << (unsettled ? "sample rate " : "Nyquist frequency ") << cutoff_limit
          << " Hz: such a filter cannot be told from none";
    } else if (base == "sensor_lowpass2") {
      const double zeta = value("zeta_lp2." + channel);
      if (zeta <= kLowpass2DampingBounds[0] * 1.01 || zeta >= kLowpass2DampingBounds[1] / 1.01) {
        why << effect << " zeta_lp2." << channel << " = " << zeta
            << " is at its bound: a resonance the fit pushed as far as it could, a "
               "stand-in for something else";
      }
    }
  }
  return why.str();
}

}  // namespace axis
