#include "discovery/significance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "common/statistics.h"
#include "discovery/candidates.h"
#include "discovery/internal/find_estimate.h"

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
                             const EstimationProblem& job) {
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
  } else if (effect == "coulomb" || effect == "motor_coulomb" || effect == "stribeck") {
    // Friction opposes the motion: a negative Coulomb (or static) level
    // pushes the axis along, which no friction does — a stand-in for
    // something else (a misfit of the sensor front end, a drive offset).
    const char* name = effect == "coulomb" ? "F_c" : effect == "stribeck" ? "F_st" : "T_c";
    const char* unit = effect == "motor_coulomb" ? " N*m" : " N";
    const double level = value(name);
    if (level < 0.0) {
      why << effect << " " << name << " = " << level << unit
          << " is below zero: friction opposes the motion, a negative level does not";
    }
  }
  // A front-end term is physical at any fitted value within its bounds: a
  // delay or a filter's time constant shorter than a sample is what an
  // anti-alias filter, a sensor's bandwidth or a skew between channels is.
  (void)job;
  return why.str();
}

}  // namespace axis
