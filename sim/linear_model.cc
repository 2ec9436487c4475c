#include "sim/linear_model.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <unsupported/Eigen/MatrixFunctions>

namespace axis {
namespace {

using Matrix5d = Eigen::Matrix<double, 5, 5>;

// Diagonal similarity D⁻¹·m·D with D = diag(*scale), powers of two (exact in
// floating point), that makes the off-diagonal row and column norms of m
// comparable: Parlett & Reinsch (1969), the balancing of LAPACK's dgebal
// without its permutation step. The axis matrix mixes entries from 1 to 1e7
// (y5' responds to ω with −K_2·K_t/(T_p·T_r)); unbalanced, the scaling and
// squaring of the exponential loses up to 1e-7 of relative accuracy by t = 3 s,
// balanced it keeps about 1e-13.
Matrix5d Balance(Matrix5d m, Eigen::Matrix<double, 5, 1>* scale) {
  constexpr double kRadix = 2.0;
  scale->setOnes();
  bool done = false;
  while (!done) {
    done = true;
    for (int i = 0; i < 5; ++i) {
      double c = 0.0, r = 0.0;
      for (int j = 0; j < 5; ++j) {
        if (j == i) continue;
        c += std::abs(m(j, i));
        r += std::abs(m(i, j));
      }
      if (c == 0.0 || r == 0.0) continue;
      const double s = c + r;
      double f = 1.0;
      double g = r / kRadix;
      while (c < g) {
        f *= kRadix;
        c *= kRadix * kRadix;
      }
      g = r * kRadix;
      while (c > g) {
        f /= kRadix;
        c /= kRadix * kRadix;
      }
      if ((c + r) / f < 0.95 * s) {
        done = false;
        (*scale)[i] *= f;
        m.row(i) /= f;
        m.col(i) *= f;
      }
    }
  }
  return m;
}

}  // namespace

LinearAxis MakeLinearAxis(const AxisParams<double>& p) {
  if (!(p.J_m > 0.0) || !(p.M > 0.0) || !(p.T_p > 0.0) || !(p.T_r > 0.0)) {
    std::ostringstream msg;
    msg << "expected positive J_m, M, T_p, T_r, got J_m = " << p.J_m
        << ", M = " << p.M << ", T_p = " << p.T_p << ", T_r = " << p.T_r;
    throw std::invalid_argument(msg.str());
  }
  const double inertia = p.J_m + p.r_g * p.r_g * p.M;     // J
  const double damping = p.B_m + p.r_g * p.r_g * p.B_a;   // B
  const double torque_per_volt = p.K_tau * p.K_i;         // K_τ·K_i
  const double pre = 1.0 / (p.T_p * p.T_r);
  LinearAxis sys;
  sys.A.setZero();
  sys.B.setZero();
  // θ' = ω
  sys.A(0, 1) = 1.0;
  // ω' = (K_τ·K_i·(y4 + T_z·y5) − B·ω) / J
  sys.A(1, 1) = -damping / inertia;
  sys.A(1, 2) = torque_per_volt / inertia;
  sys.A(1, 3) = torque_per_volt * p.T_z / inertia;
  // y4' = y5
  sys.A(2, 3) = 1.0;
  // y5' = (K_1·U − K_2·K_t·ω − y4 − (T_p + T_r)·y5) / (T_p·T_r)
  sys.A(3, 1) = -p.K2 * p.K_t * pre;
  sys.A(3, 2) = -pre;
  sys.A(3, 3) = -(p.T_p + p.T_r) * pre;
  sys.B(3) = p.K1 * pre;
  return sys;
}

Eigen::Vector4d LinearStepResponse(const LinearAxis& sys, double U0,
                                   double t) {
  if (!(t > 0.0)) return Eigen::Vector4d::Zero();
  // d/dt [x; s] = [[A, B·U0], [0, 0]]·[x; s] with x(0) = 0, s ≡ 1, so
  // [x(t); 1] = exp(G·t)·[0; 1] with G = [[A, B·U0], [0, 0]]: the last
  // column of the exponential.
  // With the balanced m̃ = D⁻¹·m·D, exp(m)·e_5 = D·exp(m̃)·e_5 / D_55.
  Matrix5d m = Matrix5d::Zero();
  m.topLeftCorner<4, 4>() = sys.A * t;
  m.topRightCorner<4, 1>() = sys.B * (U0 * t);
  Eigen::Matrix<double, 5, 1> scale;
  const Matrix5d balanced = Balance(m, &scale);
  const Matrix5d e = balanced.exp();
  return scale.head<4>().cwiseProduct(e.topRightCorner<4, 1>()) / scale[4];
}

double SteadyStateGain(const AxisParams<double>& p) {
  const double damping = p.B_m + p.r_g * p.r_g * p.B_a;
  const double torque_per_volt = p.K_tau * p.K_i;
  return p.K1 * torque_per_volt / (damping + p.K2 * p.K_t * torque_per_volt);
}

}  // namespace axis
