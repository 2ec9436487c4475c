// Helpers that let templated code treat double and ceres::Jet alike.
#ifndef SIM_SCALAR_H_
#define SIM_SCALAR_H_

#include <cmath>

#include <ceres/jet.h>

// GCC and Clang: inline every call inside the function. Jet arithmetic is
// Eigen expression code over 5-element vectors that GCC otherwise leaves out
// of line in large translation units (bench/: the difference between 650 and
// ~350 ns per Jet RK4 step).
#if defined(__GNUC__)
#define AXIS_FLATTEN __attribute__((flatten))
#else
#define AXIS_FLATTEN
#endif

namespace axis {

// The value part of a scalar: x itself for double, x.a for a Jet.
inline double ScalarValue(double x) { return x; }
template <typename T, int N>
double ScalarValue(const ceres::Jet<T, N>& x) {
  return ScalarValue(x.a);
}

// True if the value and every derivative part are finite. (ceres::isfinite
// looks at the value only; a simulation whose sensitivities overflow has
// finite values and a non-finite Jacobian.)
inline bool AllFinite(double x) { return std::isfinite(x); }
template <typename T, int N>
bool AllFinite(const ceres::Jet<T, N>& x) {
  return AllFinite(x.a) && x.v.allFinite();
}

// Largest |derivative part| (0 for double).
inline double MaxAbsDerivative(double) { return 0.0; }
template <typename T, int N>
double MaxAbsDerivative(const ceres::Jet<T, N>& x) {
  return x.v.cwiseAbs().maxCoeff();
}

// out = y + alpha·x, with alpha a plain double. For Jets this runs one pass
// over the value and derivative parts without temporaries (the RK4 stages
// are a third of the cost of a Jet step otherwise; bench/).
inline void MultiplyAdd(double y, double alpha, double x, double* out) {
  *out = y + alpha * x;
}
template <typename T, int N>
void MultiplyAdd(const ceres::Jet<T, N>& y, double alpha,
                 const ceres::Jet<T, N>& x, ceres::Jet<T, N>* out) {
  out->a = y.a + alpha * x.a;
  out->v.noalias() = y.v + alpha * x.v;
}

// Adds alpha times the derivative part of g to the derivative part of *x,
// leaving its value alone (the saltation jump of sensitivities at an event,
// sim/switched_rk4.h). A no-op for double, which has no derivative part.
inline void AddScaledDerivative(double, double, double*) {}
template <typename T, int N>
void AddScaledDerivative(double alpha, const ceres::Jet<T, N>& g,
                         ceres::Jet<T, N>* x) {
  x->v.noalias() += alpha * g.v;
}

// Rounds x down to a multiple of `quantum` (> 0) in value while keeping the
// derivative of x: the encoder quantisation of MODEL.md §5. Passing the
// derivative straight through makes closed-loop sensitivities those of the
// unquantised loop, which is what the quantiser does on average; a literal
// floor() would cut every feedback sensitivity to zero.
template <typename T>
T Quantize(const T& x, double quantum) {
  const double value = ScalarValue(x);
  return x + T(quantum * std::floor(value / quantum) - value);
}

}  // namespace axis

#endif  // SIM_SCALAR_H_
