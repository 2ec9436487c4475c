#include "discovery/significance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "common/statistics.h"
#include "discovery/candidates.h"
#include "discovery/find_estimate.h"

namespace axis {

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
    } else if (base == "cogging") {
      w.dof = 2;
      double var = covariance("A_cog", "A_cog");
      const double var_phi = covariance("phi_cog", "phi_cog");
      if (var_phi > 0.0) var -= covariance("A_cog", "phi_cog") * covariance("A_cog", "phi_cog") / var_phi;
      chi2 = e->value * e->value / var;
    } else {
      chi2 = e->value * e->value / covariance(p, p);
    }
  }
  w.chi2 = std::isfinite(chi2) ? chi2 : nan;
  w.p_value = std::isfinite(chi2) ? ChiSquaredSurvival(chi2, w.dof) : nan;
  return w;
}

std::string ImplausibleValue(const std::string& effect, const FitResult& fit,
                             const FitJob& job) {
  const auto value = [&](const std::string& name) {
    const ParameterEstimate* e = FindEstimate(fit, name);
    return e ? e->value : std::numeric_limits<double>::quiet_NaN();
  };
  std::ostringstream why;
  if (effect == "payload") {
    const double dm = value("Delta_M");
    if (dm < 0.0) {
      why << "payload Delta_M = " << dm << " kg is below zero: the declared mass M is too "
          << "large (free M instead)";
    }
  } else if (effect.rfind("sensor_delay.", 0) == 0) {
    double period = std::numeric_limits<double>::infinity();
    for (const FitExperiment& e : job.experiments) {
      period = std::min(period, e.options.output_period);
    }
    const std::string name = "tau_d." + effect.substr(std::string("sensor_delay.").size());
    const double tau = value(name);
    if (tau < period) {
      why << name << " = " << tau << " s is shorter than the sample period " << period
          << " s: a sub-sample timing error (e.g. of an input read by linear interpolation "
          << "between samples), not a sensor delay";
    }
  }
  return why.str();
}

}  // namespace axis
