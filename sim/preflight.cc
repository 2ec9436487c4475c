#include "sim/preflight.h"

#include <cmath>
#include <complex>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

#include <ceres/jet.h>

#include "sim/dense_decompositions.h"

namespace axis {
namespace {

using J7 = ceres::Jet<double, kNumStates>;

// ∂f/∂y of the model at state y (input 0), by Jet.
Eigen::Matrix<double, kNumStates, kNumStates> StateJacobian(
    const AxisStructure& structure, const AxisParams<double>& params,
    const AxisState<double>& y) {
  AxisState<J7> yj;
  for (int k = 0; k < kNumStates; ++k) yj[k] = J7(y[k], k);
  AxisState<J7> dy;
  AxisDerivative(structure, params.cast<J7>(), yj, J7(0.0), &dy);
  Eigen::Matrix<double, kNumStates, kNumStates> jac;
  for (int r = 0; r < kNumStates; ++r) jac.row(r) = dy[r].v.transpose();
  return jac;
}

double Amplification(std::complex<double> z) {
  return std::abs(1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0))));
}

}  // namespace

Rk4StabilityLimit Rk4StabilityLimitOf(const AxisStructure& structure,
                                      const AxisParams<double>& params) {
  Rk4StabilityLimit limit;
  limit.max_step = std::numeric_limits<double>::infinity();
  AxisState<double> rest = AxisState<double>::Zero();
  AxisState<double> contact = rest;
  contact[2] = 2.0 * params.H / params.r_g;  // pinion ahead: X = r_g·y2 − y0 = 2H
  for (const AxisState<double>& y : {rest, contact}) {
    const Eigen::Matrix<double, kNumStates, kNumStates> jac = StateJacobian(structure, params, y);
    if (!jac.allFinite()) {
      limit.max_step = std::numeric_limits<double>::quiet_NaN();
      return limit;
    }
    const StateEigenvalueVector eigenvalues = StateEigenvalues(jac);
    for (int k = 0; k < kNumStates; ++k) {
      std::complex<double> lambda = eigenvalues[k];
      if (std::abs(lambda) < 1e-6) continue;  // rigid-body modes: |R| = 1
      // A growing mode (negative friction at rest, e.g. a learned force
      // map's f(0) + F_c below zero) grows in the exact solution too. A
      // real one needs no step limit (RK4 follows the growth); an
      // oscillating one still limits the step as its undamped twin i·Im λ
      // does (RK4 is stable on the imaginary axis up to |hλ| = 2√2).
      if (lambda.real() > 0.0) {
        if (std::abs(lambda.imag()) < 1e-6 * std::abs(lambda)) continue;
        lambda = std::complex<double>(0.0, lambda.imag());
      }
      double lo = 0.0, hi = 10.0 / std::abs(lambda);
      if (Amplification(hi * lambda) <= 1.0) continue;
      for (int it = 0; it < 100; ++it) {
        const double mid = 0.5 * (lo + hi);
        (Amplification(mid * lambda) <= 1.0 ? lo : hi) = mid;
      }
      if (lo < limit.max_step) {
        limit.max_step = lo;
        limit.eigenvalue = lambda;
      }
    }
  }
  return limit;
}

void CheckRk4Step(const AxisStructure& structure, const AxisParams<double>& params,
                  double step, const std::string& where, const std::string& key) {
  const Rk4StabilityLimit limit = Rk4StabilityLimitOf(structure, params);
  if (!(step > limit.max_step)) return;
  std::ostringstream msg;
  msg << where << ": key '" << key << "': expected a step of at most " << limit.max_step
      << " s (the RK4 stability limit of the linearised model, fastest eigenvalue "
      << limit.eigenvalue.real();
  if (limit.eigenvalue.imag() != 0.0) {
    msg << (limit.eigenvalue.imag() > 0 ? " + " : " - ") << std::abs(limit.eigenvalue.imag())
        << "i";
  }
  msg << " 1/s), got " << step << " s";
  throw std::invalid_argument(msg.str());
}

double PhysicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return 0.0;
  return static_cast<double>(pages) * static_cast<double>(page_size);
}

void CheckMemory(double bytes, const std::string& where, const std::string& what,
                 const std::string& advice) {
  const double physical = PhysicalMemoryBytes();
  if (!(physical > 0.0) || bytes <= 0.5 * physical) return;
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  std::ostringstream msg;
  msg.precision(3);
  msg << where << ": expected " << what << " to fit in memory (at most half of this machine's "
      << physical / kGiB << " GiB), got an estimated " << bytes / kGiB << " GiB: " << advice;
  throw std::invalid_argument(msg.str());
}

}  // namespace axis
