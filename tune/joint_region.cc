#include "tune/joint_region.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <boost/math/distributions/chi_squared.hpp>

#include "estimation/parameter_tie.h"
#include "sim/dense_decompositions.h"
#include "sim/random.h"

namespace axis {
namespace {

// The normal quantile of a two-sided 95 % interval: z_i = ±kZ95 is the end.
constexpr double kZ95 = 1.959963984540054;

// A parameter the samples move: its estimate, its interval and its bounds.
struct Moved {
  std::string name;
  int index = 0;  // in FitResult::free_names
  double value = 0.0, low = 0.0, high = 0.0;
  double lower = -HUGE_VAL, upper = HUGE_VAL;
};

std::vector<Moved> MovedParameters(const FitResult& result, const AxisConfig& model,
                                   const std::vector<std::string>& skip,
                                   const std::vector<FreeParameter>& free) {
  std::vector<Moved> out;
  AxisConfig probe = model;
  for (const ParameterEstimate& e : result.parameters) {
    if (!e.free || std::find(skip.begin(), skip.end(), e.name) != skip.end()) continue;
    if (!(std::isfinite(e.std_error) && e.std_error > 0.0) || !std::isfinite(e.ci95_low) ||
        !std::isfinite(e.ci95_high) || FindParam(&probe.params, e.name) == nullptr) {
      continue;
    }
    const auto it = std::find(result.free_names.begin(), result.free_names.end(), e.name);
    if (it == result.free_names.end() ||
        it - result.free_names.begin() >= result.correlation.rows()) {
      continue;
    }
    Moved m{e.name, static_cast<int>(it - result.free_names.begin()), e.value, e.ci95_low,
            e.ci95_high};
    for (const FreeParameter& f : free) {
      if (f.name == e.name) m.lower = f.lower, m.upper = f.upper;
    }
    out.push_back(m);
  }
  return out;
}

// A factor L with L·Lᵀ = R (Cholesky; else the eigen-decomposition with
// negative eigenvalues set to 0).
Eigen::MatrixXd Factor(const Eigen::MatrixXd& r) {
  const Eigen::LLT<Eigen::MatrixXd> llt(r);
  if (llt.info() == Eigen::Success) return llt.matrixL();
  const SymmetricEigen eig = SymmetricEigenOf(r);
  const Eigen::VectorXd root = eig.values.cwiseMax(0.0).cwiseSqrt();
  return eig.vectors * root.asDiagonal();
}

}  // namespace

std::vector<RegionSample> JointRegionSamples(const FitResult& result, const AxisConfig& model,
                                             const std::vector<std::string>& skip,
                                             const std::vector<FreeParameter>& free, int count) {
  const std::vector<Moved> moved = MovedParameters(result, model, skip, free);
  std::vector<RegionSample> out;
  if (moved.empty() || count <= 0) return out;
  const int p = static_cast<int>(moved.size());
  Eigen::MatrixXd r(p, p);
  for (int i = 0; i < p; ++i) {
    for (int j = 0; j < p; ++j) {
      const double c = result.correlation(moved[i].index, moved[j].index);
      r(i, j) = std::isfinite(c) ? c : (i == j ? 1.0 : 0.0);
    }
  }
  const Eigen::MatrixXd factor = Factor(r);
  const double radius2 = boost::math::quantile(boost::math::chi_squared(p), 0.95);
  RandomEngine rng(kJointRegionSeed);
  while (static_cast<int>(out.size()) < count) {
    Eigen::VectorXd u(p);
    for (int i = 0; i < p; ++i) u(i) = StandardNormal(rng);
    if (u.squaredNorm() > radius2) continue;  // outside the 95 % region
    const Eigen::VectorXd z = factor * u;
    RegionSample s{"joint sample " + std::to_string(out.size() + 1), model};
    for (int i = 0; i < p; ++i) {
      const Moved& m = moved[i];
      const double half = z(i) >= 0.0 ? m.high - m.value : m.value - m.low;
      *FindParam(&s.model.params, m.name) =
          std::clamp(m.value + z(i) * half / kZ95, m.lower, m.upper);
    }
    ApplyResultTies(result, &s.model.params);
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace axis
