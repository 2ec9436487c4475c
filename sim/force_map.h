// The force map of MODEL.md §7 (issue 15): a smooth load force learned where
// the effect library has no term for it, f(x), f(v) or f(x)·sgn_ε(v), as a
// natural cubic spline through (knot, value) pairs. The values, forces in N
// at the knots, are model parameters (AxisParams::f_map, names "f_map.<k>"),
// so that a fit estimates them with the rest; the knots and the variable are
// structure (not differentiated), like N_cog.
//
// The spline is the cubic spline basis in its cardinal form: f is linear in
// the values, f(t_k) = value_k, f'' continuous and zero at both ends
// (natural end conditions; de Boor, "A Practical Guide to Splines", 2001,
// ch. IV), and held at the end value outside [t_0, t_{K−1}] (no
// extrapolation past the range the data visited). The fit's roughness
// penalty acts on the second differences of the values (discovery/force_map.h;
// Eilers & Marx 1996, "Flexible smoothing with B-splines and penalties").
#ifndef SIM_FORCE_MAP_H_
#define SIM_FORCE_MAP_H_

#include <array>
#include <string>
#include <vector>

#include "sim/scalar.h"

namespace axis {

// At most this many knots (the size of AxisParams::f_map).
inline constexpr int kMaxForceMapKnots = 40;
// At least this many: a natural spline through 3 points is one curve.
inline constexpr int kMinForceMapKnots = 4;

// What the map's force depends on.
enum class ForceMapVariable {
  kX,  // load position x = y0 (m)
  kV,  // load velocity v = y1 (m/s)
};

// The structure of a force map (MODEL.md §7 `force_map`).
struct ForceMap {
  bool enabled = false;
  ForceMapVariable variable = ForceMapVariable::kX;
  // F_eff += f(x)·sgn_ε(v) (Coulomb friction that varies along the travel)
  // instead of f(x); only with variable x.
  bool friction = false;
  // Knots t_k, strictly increasing, kMinForceMapKnots..kMaxForceMapKnots of
  // them; unit of the variable (m or m/s).
  std::vector<double> knots;
};

// "x", "v" or "x_friction": the map's kind, as the discovery loop names it
// ("force_map.x_friction"). Never throws.
std::string ForceMapKind(const ForceMap& map);

// What is wrong with `knots` for a map, in the parts of a config error
// "expected …, got …"; both empty if they can carry one (count within
// kMinForceMapKnots..kMaxForceMapKnots, finite, strictly increasing).
// Never throws.
struct KnotsProblem {
  std::string expected, got;
  bool ok() const { return expected.empty(); }
};
KnotsProblem ForceMapKnotsProblem(const std::vector<double>& knots);

// The second derivatives m_k of the natural cubic spline through
// (knots[k], values[k]), k < K = knots.size() (m_0 = m_{K−1} = 0): the
// tridiagonal system of de Boor ch. IV solved by elimination (the matrix
// depends on the knots only, so it is double; the values may be Jets).
// `knots` must satisfy ForceMapKnotsProblem; never throws.
template <typename T>
void ForceMapSecondDerivatives(const std::vector<double>& knots,
                               const std::array<T, kMaxForceMapKnots>& values,
                               std::array<T, kMaxForceMapKnots>* m) {
  const int K = static_cast<int>(knots.size());
  for (int k = 0; k < kMaxForceMapKnots; ++k) (*m)[k] = T(0.0);
  if (K < 3) return;
  // Rows j = 1..K−2: h_{j−1}/6·m_{j−1} + (h_{j−1} + h_j)/3·m_j + h_j/6·m_{j+1}
  //   = (y_{j+1} − y_j)/h_j − (y_j − y_{j−1})/h_{j−1}.
  std::array<double, kMaxForceMapKnots> diag{}, upper{};
  std::array<T, kMaxForceMapKnots> rhs;
  for (int j = 1; j < K - 1; ++j) {
    const double h0 = knots[j] - knots[j - 1];
    const double h1 = knots[j + 1] - knots[j];
    diag[j] = (h0 + h1) / 3.0;
    upper[j] = h1 / 6.0;
    rhs[j] = (values[j + 1] - values[j]) * (1.0 / h1) - (values[j] - values[j - 1]) * (1.0 / h0);
  }
  // Forward elimination (the matrix is diagonally dominant: no pivoting).
  for (int j = 2; j < K - 1; ++j) {
    const double lower = (knots[j] - knots[j - 1]) / 6.0;
    const double factor = lower / diag[j - 1];
    diag[j] -= factor * upper[j - 1];
    rhs[j] = rhs[j] - rhs[j - 1] * factor;
  }
  for (int j = K - 2; j >= 1; --j) {
    T next = j + 1 < K - 1 ? T((*m)[j + 1] * upper[j]) : T(0.0);
    (*m)[j] = (rhs[j] - next) * (1.0 / diag[j]);
  }
}

// f(z): the spline through (knots, values) with second derivatives `m`
// (ForceMapSecondDerivatives) at z (unit of the variable), the end value
// outside the knots. Never throws.
template <typename T>
T ForceMapValue(const std::vector<double>& knots, const std::array<T, kMaxForceMapKnots>& values,
                const std::array<T, kMaxForceMapKnots>& m, const T& z) {
  const int K = static_cast<int>(knots.size());
  const double zv = ScalarValue(z);
  if (!(zv > knots[0])) return values[0];
  if (!(zv < knots[K - 1])) return values[K - 1];
  int i = 0;
  while (i + 2 < K && zv >= knots[i + 1]) ++i;
  const double h = knots[i + 1] - knots[i];
  const T b = (z - knots[i]) * (1.0 / h);
  const T a = T(1.0) - b;
  return a * values[i] + b * values[i + 1] +
         ((a * a * a - a) * m[i] + (b * b * b - b) * m[i + 1]) * (h * h / 6.0);
}

}  // namespace axis

#endif  // SIM_FORCE_MAP_H_
