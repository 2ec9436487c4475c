// The linear fourth-order axis of Nelson & Chang (1984), Fig. 3: the model of
// MODEL.md §3 in the `current_source` + `rigid` configuration of MODEL.md §4
// with no limits (V_L = ∞), F_s = 0 and H = 0, whose step response has a
// closed form. It is the reference the RK4 simulator is checked against.
#ifndef SIM_LINEAR_MODEL_H_
#define SIM_LINEAR_MODEL_H_

#include <Eigen/Core>

#include "sim/axis_params.h"

namespace axis {

// The linear system x' = A·x + B·U of MODEL.md §4 with state
// x = (θ, ω, y4, y5): motor angle θ (rad), motor angular velocity ω (rad/s),
// preamp variables y4 (V) and y5 (V/s); input U, the set-velocity voltage (V).
//   θ'  = ω
//   J·ω' = K_τ·K_i·(y4 + T_z·y5) − B·ω,   J = J_m + r_g²·M, B = B_m + r_g²·B_a
//   y4' = y5
//   y5' = (K_1·U − K_2·K_t·ω − y4 − (T_p + T_r)·y5) / (T_p·T_r)
// Derived outputs: arm velocity v = r_g·ω (m/s), motor current
// i = K_i·(y4 + T_z·y5) (A).
struct LinearAxis {
  Eigen::Matrix4d A;  // 4×4 system matrix, rows and columns in state order
  Eigen::Vector4d B;  // 4×1 input vector, K_1/(T_p·T_r) in the y5 row (1/s²)
};

// Builds the linear system from the parameters of MODEL.md §2 (SI units). Only
// the fields named above are used: the limits V_L, V_M, the static friction
// F_s, the backlash H and the §7 effect parameters are ignored (this is the
// unlimited, frictionless system). Throws std::invalid_argument("expected
// positive J_m, M, T_p, T_r, got …") if any of J_m, M, T_p, T_r is not
// positive (or is NaN).
LinearAxis MakeLinearAxis(const AxisParams<double>& p);

// The closed-form response of `sys` from rest (x(0) = 0) to a step of height
// U0 (V) applied at t = 0, evaluated at time t (s, ≥ 0; t < 0 gives the rest
// state): x(t) = [I 0]·exp(G·t)·[0; 1] with the augmented 5×5 matrix
// G = [[A, B·U0], [0, 0]], computed by the matrix exponential (Padé with
// scaling and squaring, Eigen's MatrixFunctions), not by time stepping.
// Returns the state (θ, ω, y4, y5) in rad, rad/s, V, V/s.
Eigen::Vector4d LinearStepResponse(const LinearAxis& sys, double U0, double t);

// Steady-state velocity gain ω/U (rad/s per V) of MODEL.md §3:
// K_1·K_τ·K_i / (B + K_2·K_t·K_τ·K_i), B = B_m + r_g²·B_a. Multiply by r_g for
// m/s per V (0.09995 for the X axis with K_1 = 1014, K_2 = 870). It is also
// the DC gain −(A⁻¹B)[1] of MakeLinearAxis(p). Never throws; a zero
// denominator gives ±∞ or NaN.
double SteadyStateGain(const AxisParams<double>& p);

}  // namespace axis

#endif  // SIM_LINEAR_MODEL_H_
