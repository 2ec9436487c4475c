// The axis model of MODEL.md §3 (Nelson & Chang 1984, eq. 1–6) with the
// configurations of §4 and the dynamic effects of §7: a pure function of
// (structure, parameters, state, input) that writes the state derivative.
// Templated on the scalar so that double and ceres::Jet flow through it.
#ifndef SIM_AXIS_MODEL_H_
#define SIM_AXIS_MODEL_H_

#include <cmath>

#include <Eigen/Core>

#include "sim/axis_params.h"
#include "sim/scalar.h"  // AXIS_FLATTEN


namespace axis {

// The 7 states of MODEL.md §1, in the paper's numbering y0..y6:
// y0 arm position x (m), y1 arm velocity v (m/s), y2 motor angle θ (rad),
// y3 motor angular velocity ω (rad/s), y4 preamp variable 1 (V),
// y5 preamp variable 2 (V/s), y6 motor current i (A).
// Reduced configurations keep all 7 entries: rigid coupling keeps
// y2 = y0/r_g and y3 = y1/r_g; current_source leaves y6 constant (the current
// is algebraic, AxisAux::i); force_source leaves y2..y6 constant.
template <typename T>
using AxisState = Eigen::Matrix<T, 7, 1>;
inline constexpr int kNumStates = 7;

// Algebraic quantities computed alongside the derivative (MODEL.md §3, §6).
template <typename T>
struct AxisAux {
  T a;      // arm acceleration y1' (m/s²)
  T i;      // motor current (A): y6, or K_i·V_c for current_source, 0 for force_source
  T vc;     // preamp output V_c, eq. 2 (V)
  T vm;     // motor voltage V_m, eq. 3 (V); for current_source R·i + K_e·ω
  T fg;     // force through the gear onto the arm, eq. 5 (N); for rigid
            // coupling the force the coupling must carry, M·a + B_a·v + friction
  T force;  // drive force on the load (N): f_g (gear), K_τ·i/r_g (rigid), g_F·U
};

// Which branch of the gear force (MODEL.md eq. 5) applies: X < −H, |X| ≤ H
// (inside the backlash, f_g = 0) or X > H. kFromState picks it from the
// state, as eq. 5 is written; the other values hold one branch fixed, so that
// the right-hand side is smooth in the state (sim/switched_rk4.h integrates
// across the contacts with the branch held between them).
enum class GearContact : int {
  kNegative = -1,
  kFree = 0,
  kPositive = 1,
  kFromState = 2,
};

// The branch of eq. 5 for a pinion–rack difference X = r_g·θ − x (m) and
// backlash half-width H (m, ≥ 0). Never throws.
inline GearContact GearContactOf(double gap, double H) {
  if (gap > H) return GearContact::kPositive;
  if (gap < -H) return GearContact::kNegative;
  return GearContact::kFree;
}

namespace internal {

template <typename T>
T Clamp(const T& x, const T& limit) {
  if (x > limit) return limit;
  if (x < -limit) return -limit;
  return x;
}

}  // namespace internal

// Combinations of parameters that do not depend on the state, formed once
// per simulation instead of at every derivative evaluation: with Jet scalars
// every product and quotient costs as much as the state arithmetic itself.
template <typename T>
struct AxisCoefficients {
  T inv_mass;       // 1/(M + ΔM) (ΔM only with payload)
  T B_a_per_mass;   // B_a/(M + ΔM)
  T K_tau_per_J;    // K_τ/J_m
  T B_m_per_J;      // B_m/J_m
  T r_g_per_J;      // r_g/J_m
  T inv_J_m;        // 1/J_m
  T K_a_per_K_i;    // K_a/K_i
  T inv_L;          // 1/L
  T R_per_L;        // R/L
  T K_e_per_L;      // K_e/L
  T inv_r_g;        // 1/r_g
  T inv_inertia;    // rigid: 1/(J_m + r_g²·mass)
  T damping;        // rigid: B_m + r_g²·B_a
  T pre_u;          // K_1/(T_p·T_r)
  T pre_omega;      // K_2·K_t/(T_p·T_r)
  T pre_y4;         // 1/(T_p·T_r)
  T pre_y5;         // (T_p + T_r)/(T_p·T_r)
};

// The coefficients of `p` for `structure`. Never throws.
template <typename T>
AxisCoefficients<T> MakeAxisCoefficients(const AxisStructure& structure,
                                         const AxisParams<T>& p) {
  AxisCoefficients<T> c;
  const T mass = structure.effects.payload ? T(p.M + p.Delta_M) : p.M;
  c.inv_mass = T(1.0) / mass;
  c.B_a_per_mass = p.B_a * c.inv_mass;
  c.inv_J_m = T(1.0) / p.J_m;
  c.K_tau_per_J = p.K_tau * c.inv_J_m;
  c.B_m_per_J = p.B_m * c.inv_J_m;
  c.r_g_per_J = p.r_g * c.inv_J_m;
  c.K_a_per_K_i = p.K_a / p.K_i;
  c.inv_L = T(1.0) / p.L;
  c.R_per_L = p.R * c.inv_L;
  c.K_e_per_L = p.K_e * c.inv_L;
  c.inv_r_g = T(1.0) / p.r_g;
  c.inv_inertia = T(1.0) / (p.J_m + p.r_g * p.r_g * mass);
  c.damping = p.B_m + p.r_g * p.r_g * p.B_a;
  c.pre_y4 = T(1.0) / (p.T_p * p.T_r);
  c.pre_u = p.K1 * c.pre_y4;
  c.pre_omega = p.K2 * p.K_t * c.pre_y4;
  c.pre_y5 = (p.T_p + p.T_r) * c.pre_y4;
  return c;
}

namespace internal {

inline bool AnyLoadEffect(const EffectSwitches& e) {
  return e.coulomb || e.stribeck || e.viscous_asymmetry || e.load_offset ||
         e.spring;
}

}  // namespace internal

// Writes dy = f(y, u) for the model of MODEL.md §3–4 and §7.
//   structure: amplifier, coupling and enabled effects (not differentiated).
//   p: parameters in SI units (MODEL.md §2, §7). Masses, inertias, L, T_p,
//      T_r must be positive (the config loader checks; not checked here).
//   c: MakeAxisCoefficients(structure, p).
//   y: state y0..y6 (MODEL.md §1). u: set-velocity voltage U (V), or the
//      force-source input (V, force g_F·U).
//   dy: derivative of y (must not alias y). aux: optional algebraic outputs.
//   contact: the branch of eq. 5 (gear coupling only); by default the one
//      the state is in.
// Never throws; non-finite inputs give non-finite outputs.
template <typename T>
AXIS_FLATTEN void AxisDerivative(const AxisStructure& structure,
                                 const AxisParams<T>& p,
                                 const AxisCoefficients<T>& c,
                                 const AxisState<T>& y,
                    const T& u, AxisState<T>* dy, AxisAux<T>* aux = nullptr,
                    GearContact contact = GearContact::kFromState) {
  using std::exp;
  using std::sin;
  using std::tanh;
  const EffectSwitches& e = structure.effects;
  const bool rigid = structure.coupling == Coupling::kRigid;
  const T& x = y[0];
  const T& v = y[1];
  // In rigid coupling the motor follows the load exactly.
  const T theta = rigid ? T(x * c.inv_r_g) : y[2];
  const T omega = rigid ? T(v * c.inv_r_g) : y[3];

  // Load-side friction: static friction eq. 6 and the §7 force effects.
  const bool static_friction = p.F_s != 0.0 && v < p.w && v > -p.w &&
                               v != 0.0;
  const bool has_load_force = static_friction || internal::AnyLoadEffect(e);
  T f_load(0.0);
  if (has_load_force) {
    if (static_friction) f_load += v > 0.0 ? p.F_s : T(-p.F_s);
    if (e.coulomb || e.stribeck || e.viscous_asymmetry) {
      const T sgn = tanh(v / p.v_eps);
      if (e.coulomb) f_load += p.F_c * sgn;
      if (e.stribeck) {
        const T r = v / p.v_st;
        f_load += (p.F_st - p.F_c) * exp(-r * r) * sgn;
      }
      if (e.viscous_asymmetry) {
        f_load += p.Delta_B * v * (T(1.0) - sgn) * 0.5;
      }
    }
    if (e.load_offset) f_load += p.F_0;
    if (e.spring) f_load += p.k_x * (x - p.x_0);
  }

  // Motor-side torque effects.
  const bool has_motor_torque = e.motor_coulomb || e.cogging;
  T t_motor(0.0);
  if (e.motor_coulomb) t_motor += p.T_c * tanh(omega / p.omega_eps);
  if (e.cogging) {
    t_motor += p.A_cog * sin(double(structure.N_cog) * theta + p.phi_cog);
  }

  // Amplifier: preamp (eq. 2, y4–y5), current loop (eq. 3, y6).
  T i, vc, vm;
  if (structure.amplifier != Amplifier::kForceSource) {
    vc = internal::Clamp(T(y[4] + p.T_z * y[5]), p.V_L);
    (*dy)[4] = y[5];
    (*dy)[5] = c.pre_u * u - c.pre_omega * omega - c.pre_y4 * y[4] -
               c.pre_y5 * y[5];
    if (structure.amplifier == Amplifier::kAnalogVelocityLoop) {
      i = y[6];
      vm = internal::Clamp(T(p.K_a * vc - c.K_a_per_K_i * i), p.V_M);
      (*dy)[6] = c.inv_L * vm - c.R_per_L * i - c.K_e_per_L * omega;
    } else {
      i = p.K_i * vc;
      vm = p.R * i + p.K_e * omega;
      (*dy)[6] = T(0.0);
    }
  } else {
    i = vc = vm = T(0.0);
    (*dy)[4] = (*dy)[5] = (*dy)[6] = T(0.0);
  }

  // Mechanics (eq. 1, 4, 5 or the rigid reduction of §4).
  T a, fg, force;
  if (!rigid) {
    const T gap = p.r_g * theta - x;  // X, eq. 4
    if (contact == GearContact::kFromState) {
      contact = gap > p.H    ? GearContact::kPositive
                : gap < -p.H ? GearContact::kNegative
                             : GearContact::kFree;
    }
    if (contact == GearContact::kPositive) {
      fg = p.k_g * (gap - p.H) + p.b_g * (p.r_g * omega - v);
    } else if (contact == GearContact::kNegative) {
      fg = p.k_g * (gap + p.H) + p.b_g * (p.r_g * omega - v);
    } else {
      fg = T(0.0);
    }
    a = c.inv_mass * fg - c.B_a_per_mass * v;
    if (has_load_force) a -= c.inv_mass * f_load;
    (*dy)[2] = omega;
    (*dy)[3] = c.K_tau_per_J * i - c.B_m_per_J * omega - c.r_g_per_J * fg;
    if (has_motor_torque) (*dy)[3] -= c.inv_J_m * t_motor;
    force = fg;
  } else if (structure.amplifier == Amplifier::kForceSource) {
    force = p.g_F * u;
    T f = force - p.B_a * v - f_load;
    if (has_motor_torque) f -= t_motor * c.inv_r_g;
    a = f * c.inv_mass;
    fg = force;
    (*dy)[2] = omega;
    (*dy)[3] = a * c.inv_r_g;
  } else {
    const T domega =
        (p.K_tau * i - c.damping * omega - p.r_g * f_load - t_motor) *
        c.inv_inertia;
    a = p.r_g * domega;
    force = p.K_tau * i * c.inv_r_g;
    fg = a / c.inv_mass + p.B_a * v + f_load;
    (*dy)[2] = omega;
    (*dy)[3] = domega;
  }
  (*dy)[0] = v;
  (*dy)[1] = a;

  if (aux != nullptr) {
    aux->a = a;
    aux->i = i;
    aux->vc = vc;
    aux->vm = vm;
    aux->fg = fg;
    aux->force = force;
  }
}

// As above, forming the coefficients first: for single evaluations (tests,
// linearisation). Simulations form them once and call the overload above.
template <typename T>
void AxisDerivative(const AxisStructure& structure, const AxisParams<T>& p,
                    const AxisState<T>& y, const T& u, AxisState<T>* dy,
                    AxisAux<T>* aux = nullptr) {
  AxisDerivative(structure, p, MakeAxisCoefficients(structure, p), y, u, dy,
                 aux);
}

}  // namespace axis

#endif  // SIM_AXIS_MODEL_H_
