// The sensor front end of MODEL.md §6: what happens to a simulated channel
// between the plant and the recorded sample — the sensor's and the
// anti-alias filter's low-pass (`sensor_lowpass`, `sensor_lowpass2`), a
// delay or a skew between channels (`sensor_delay`), the accelerometer's
// sampling convention (`accelerometer: instant | period_mean`) and an
// offset (`sensor_bias`, applied by Simulate). Every stage is linear and
// time-invariant, so their order does not matter; each works on the
// channel's values on the RK4 grid t_n = n·h (n = 0 … N), read as linear
// between grid points, and is templated on the scalar so that ceres::Jet
// flows through it (the filter's time constant and damping included).
#ifndef SIM_SENSOR_FRONT_END_H_
#define SIM_SENSOR_FRONT_END_H_

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "sim/scalar.h"

namespace axis {

// exp(m) of a small fixed-size matrix: scaling and squaring with a Taylor
// polynomial of degree 12 (Moler & Van Loan, "Nineteen dubious ways to
// compute the exponential of a matrix, twenty-five years later", SIAM
// Review 45, 2003, methods 1 and 3): m is scaled by 2^−s until its
// ∞-norm (of the values) is at most 1/2, where the truncation error is below
// 0.5¹³/13! ≈ 2·10⁻¹⁴ relative, then squared s times. For the filters
// below, whose matrices are stable with real parts ≤ 0, the squaring does
// not amplify it. Templated so that ceres::Jet flows through (Eigen's
// unsupported MatrixExponential branches on the scalar's values). Never
// throws; a non-finite entry gives a non-finite result.
template <typename T, int N>
Eigen::Matrix<T, N, N> SmallMatrixExp(const Eigen::Matrix<T, N, N>& m) {
  using Matrix = Eigen::Matrix<T, N, N>;
  double norm = 0.0;
  for (int i = 0; i < N; ++i) {
    double row = 0.0;
    for (int j = 0; j < N; ++j) row += std::abs(ScalarValue(m(i, j)));
    norm = std::max(norm, row);
  }
  if (!std::isfinite(norm)) return m;
  int squarings = 0;
  while (norm > 0.5 && squarings < 200) {
    norm *= 0.5;
    ++squarings;
  }
  const Matrix a = m * T(std::ldexp(1.0, -squarings));
  Matrix result = Matrix::Identity();
  Matrix term = Matrix::Identity();
  for (int k = 1; k <= 12; ++k) {
    term = (term * a) / T(static_cast<double>(k));
    result += term;
  }
  for (int s = 0; s < squarings; ++s) result = (result * result).eval();
  return result;
}

// Below this fraction of the grid step a filter's time constant is taken
// to first order (LowPassOnGrid): at 10⁻³·h the second-order term is 10⁻⁶
// of the first relative to the step, below the RK4 solution's own error,
// and τ = 0 (the filter off, where the score test differentiates) needs it:
// the exact step's exp(−h/τ) has no derivative there.
inline constexpr double kFirstOrderTauFraction = 1e-3;

// A low-pass filter applied to a signal s known on the grid t_n = n·h
// (s.size() = N + 1 ≥ 1) and linear between grid points (first-order hold),
// started at rest at s_0 (the signal held at s_0 before t = 0); returns the
// filtered signal on the same grid.
//   order 1: H(s) = 1/(τ·s + 1), τ = `tau` (s), cut-off 1/(2π·τ) Hz;
//   order 2: H(s) = 1/(τ²·s² + 2ζ·τ·s + 1), ζ = `zeta` (> 0; 1/√2 is the
//            Butterworth response), natural frequency 1/(2π·τ) Hz.
// Exact for the piecewise-linear input: each step is the discretisation
// x_{n+1} = Φ·x_n + Γ₀·s_n + Γ₁·(s_{n+1} − s_n)/h from one matrix
// exponential of the augmented system (Van Loan 1978, "Computing integrals
// involving the matrix exponential", IEEE TAC 23), with the state (f, τ·f')
// for order 2 so that the matrix is dimensionless. For τ below
// kFirstOrderTauFraction·h: f_n = s_n − g·τ·(s_n − s_{n−1})/h with g = 1
// (order 1) or 2ζ (order 2), the filter to first order in τ (a delay of g·τ
// on the grid's slope), exact at τ = 0 and differentiable there.
// Requires τ ≥ 0, h > 0, order 1 or 2. Never throws.
template <typename T>
std::vector<T> LowPassOnGrid(const std::vector<T>& s, double h, int order, const T& tau,
                             const T& zeta) {
  std::vector<T> out(s.size());
  if (s.empty()) return out;
  const T gain = order == 1 ? T(1.0) : T(2.0) * zeta;
  if (ScalarValue(tau) < kFirstOrderTauFraction * h) {
    out[0] = s[0];
    for (size_t n = 1; n < s.size(); ++n) {
      out[n] = s[n] - gain * tau * (s[n] - s[n - 1]) / T(h);
    }
    return out;
  }
  // The augmented system z = (x, u, w): x' = A·x + B·u, u' = w, w' = 0,
  // over one step from u = s_n with w = (s_{n+1} − s_n)/h.
  constexpr int kMax = 4;
  const int nx = order;
  Eigen::Matrix<T, kMax, kMax> m = Eigen::Matrix<T, kMax, kMax>::Zero();
  const T rate = T(h) / tau;  // h/τ
  if (order == 1) {
    m(0, 0) = -rate;
    m(0, 1) = rate;
    m(1, 2) = T(h);
    // The unused last row and column stay zero: exp keeps them the identity.
  } else {
    m(0, 1) = rate;
    m(1, 0) = -rate;
    m(1, 1) = T(-2.0) * zeta * rate;
    m(1, 2) = rate;
    m(2, 3) = T(h);
  }
  const Eigen::Matrix<T, kMax, kMax> e = SmallMatrixExp<T, kMax>(m);
  // x_{n+1} = Φ·x_n + Γ₀·s_n + Γ₁·w_n: Φ = e[0:nx, 0:nx], Γ₀ = e[0:nx, nx],
  // Γ₁ = e[0:nx, nx+1] (w enters through u' = w with the factor h in m).
  T x0 = s[0];
  T x1(0.0);
  out[0] = s[0];
  for (size_t n = 0; n + 1 < s.size(); ++n) {
    const T w = (s[n + 1] - s[n]) / T(h);
    if (nx == 1) {
      x0 = e(0, 0) * x0 + e(0, 1) * s[n] + e(0, 2) * w;
    } else {
      const T next0 = e(0, 0) * x0 + e(0, 1) * x1 + e(0, 2) * s[n] + e(0, 3) * w;
      const T next1 = e(1, 0) * x0 + e(1, 1) * x1 + e(1, 2) * s[n] + e(1, 3) * w;
      x0 = next0;
      x1 = next1;
    }
    out[n + 1] = x0;
  }
  return out;
}

// The value at time `time` (s; any real) of a signal known on the grid
// t_n = n·h (`s`, N + 1 ≥ 1 entries), linear between grid points and held at
// s_0 before t = 0 and at s_N after t = N·h. Templated so that a delay's
// derivative flows through `time`. Never throws.
template <typename T>
T ValueOnGrid(const std::vector<T>& s, double h, const T& time) {
  const T pos = time / T(h);
  const double pv = ScalarValue(pos);
  const long last = static_cast<long>(s.size()) - 1;
  if (pv <= 0.0 || last < 1) return s[0];
  if (pv >= static_cast<double>(last)) return s[last];
  const long n0 = std::min(static_cast<long>(std::floor(pv)), last - 1);
  const T frac = pos - T(static_cast<double>(n0));
  return s[n0] + frac * (s[n0 + 1] - s[n0]);
}

// The accelerometer's signal on the grid from the arm velocity v on it
// (`v`, N + 1 ≥ 1 entries, v_n = y1(n·h)) and y1'(0) (`a0`), continuous in
// the model's parameters: y1' itself jumps at every backlash contact
// (MODEL.md §6), v does not.
//   period_mean (`period_steps` = T_o/h ≥ 1): (v(t_n) − v(t_n − T_o))/T_o,
//     the mean of y1' over the output period ending at t_n;
//   instant (`period_steps` = 0, `window_steps` = w/h ≥ 1):
//     (v(t_n + w) − v(t_n − w))/(2w), the mean of y1' over [t_n − w, t_n + w]
//     — the sensor's own bandwidth; y1'(t_n) to O(w²) between contacts.
//     Near the end the window is cut at t_N (one-sided at t_N itself).
// Before t = 0 the motion is continued back as v(0) + a0·t. Never throws.
template <typename T>
std::vector<T> AccelerationOnGrid(const std::vector<T>& v, double h, long period_steps,
                                  long window_steps, const T& a0) {
  const long size = static_cast<long>(v.size());
  std::vector<T> s(v.size());
  const auto v_at = [&](long n) -> T {
    if (n >= 0) return v[std::min(n, size - 1)];
    return v[0] + a0 * T(static_cast<double>(n) * h);
  };
  const long k = std::max(1L, window_steps);
  for (long n = 0; n < size; ++n) {
    if (period_steps > 0) {
      s[n] = (v_at(n) - v_at(n - period_steps)) / T(static_cast<double>(period_steps) * h);
    } else if (size == 1) {
      s[n] = a0;
    } else {
      const long hi = std::min(n + k, size - 1);
      const long lo = n + k < size ? n - k : std::min(n - 1, n - (hi - n));
      s[n] = (v_at(hi) - v_at(lo)) / T(static_cast<double>(hi - lo) * h);
    }
  }
  return s;
}

// The instant accelerometer's half-window in RK4 steps of length h:
// `window` / h rounded, at least 1 (MODEL.md §6). Never throws.
inline long InstantWindowSteps(double window, double h) {
  return std::max(1L, std::lround(window / h));
}

}  // namespace axis

#endif  // SIM_SENSOR_FRONT_END_H_
