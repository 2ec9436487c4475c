// Classical fixed-step fourth-order Runge–Kutta, the integrator of
// Nelson & Chang (1984) and MODEL.md (mission 1).
#ifndef SIM_RK4_H_
#define SIM_RK4_H_

#include "sim/scalar.h"

namespace axis {

// Advances *y from t to t + h with the classical RK4 scheme, Butcher tableau
//
//     0   |
//     1/2 | 1/2
//     1/2 | 0    1/2
//     1   | 0    0    1
//     ----+-------------------
//         | 1/6  1/3  1/3  1/6
//
// Global error O(h⁴): halving h divides the error by about 16 on smooth
// problems. Real-axis stability: |h·λ| ≤ 2.785 (Hairer & Wanner, Solving ODEs
// II, §IV.2).
//   f: callable f(double t, const State& y, State* dy) writing dy/dt.
//   State: a fixed-size Eigen vector of double or ceres::Jet (anything with
//   size(), operator[] and a MultiplyAdd for its scalar, sim/scalar.h).
//   Time and step are double: they are never differentiated.
// Never throws unless f does.
template <typename State, typename F>
AXIS_FLATTEN void Rk4Step(const F& f, double t, double h, State* y) {
  // Element loops with double weights through MultiplyAdd: for Jet states
  // this scales the derivative parts in place instead of evaluating Eigen
  // expressions over non-native scalars (bench/: 632 → under 300 ns a step).
  const int n = static_cast<int>(y->size());
  const double half_h = 0.5 * h;
  State k, stage, sum;
  f(t, *y, &k);
  for (int i = 0; i < n; ++i) {
    sum[i] = k[i];
    MultiplyAdd((*y)[i], half_h, k[i], &stage[i]);
  }
  f(t + half_h, stage, &k);
  for (int i = 0; i < n; ++i) {
    MultiplyAdd(sum[i], 2.0, k[i], &sum[i]);
    MultiplyAdd((*y)[i], half_h, k[i], &stage[i]);
  }
  f(t + half_h, stage, &k);
  for (int i = 0; i < n; ++i) {
    MultiplyAdd(sum[i], 2.0, k[i], &sum[i]);
    MultiplyAdd((*y)[i], h, k[i], &stage[i]);
  }
  f(t + h, stage, &k);
  for (int i = 0; i < n; ++i) {
    sum[i] += k[i];
    MultiplyAdd((*y)[i], h / 6.0, sum[i], &(*y)[i]);
  }
}

// As Rk4Step with a step length `h` of the state's scalar type (a
// ceres::Jet whose derivative part is how the step's length moves with the
// parameters: the rest of a step after an event located inside it,
// sim/switched_rk4.h). The increments are computed with h itself, so their
// derivative carries ∂y(t + h)/∂h·∂h/∂p; the stage times passed to f are
// t + c·value(h), never differentiated (f's explicit time dependence, a
// smooth input's, is left out of ∂/∂h). Slower than Rk4Step (scalar
// products of two scalars); with a double h the two agree.
// Never throws unless f does.
template <typename State, typename Scalar, typename F>
void Rk4StepOfLength(const F& f, double t, const Scalar& h, State* y) {
  const int n = static_cast<int>(y->size());
  const double hv = ScalarValue(h);
  const Scalar half_h = 0.5 * h;
  State k1, k2, k3, k4, stage;
  f(t, *y, &k1);
  for (int i = 0; i < n; ++i) stage[i] = (*y)[i] + half_h * k1[i];
  f(t + 0.5 * hv, stage, &k2);
  for (int i = 0; i < n; ++i) stage[i] = (*y)[i] + half_h * k2[i];
  f(t + 0.5 * hv, stage, &k3);
  for (int i = 0; i < n; ++i) stage[i] = (*y)[i] + h * k3[i];
  f(t + hv, stage, &k4);
  for (int i = 0; i < n; ++i) {
    (*y)[i] += (h / 6.0) * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  }
}

}  // namespace axis

#endif  // SIM_RK4_H_
