// The axis model of MODEL.md §3 (Nelson & Chang 1984, eq. 1–6) with the
// configurations of §4 and the dynamic effects of §7: a pure function of
// (structure, parameters, state, input) that writes the state derivative.
// Templated on the scalar so that double and ceres::Jet flow through it.
#ifndef SIM_AXIS_MODEL_H_
#define SIM_AXIS_MODEL_H_

#include <algorithm>
#include <cmath>
#include <type_traits>

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

// Which side of the preamp output limit (MODEL.md eq. 2, V_c = clamp(y4 +
// T_z·y5, ±V_L)) applies: below −V_L, within, above V_L. kFromState picks it
// from the state, as eq. 2 is written; the other values hold one side fixed
// (V_c = −V_L, y4 + T_z·y5 unclamped, or V_L), so that the right-hand side is
// smooth in the state. Under the quasi-steady current loop the current's
// rate carries V_c' (zero outside the limits), which jumps at ±V_L; the
// simulator integrates across those events with the side held between them
// (sim/switched_rk4.h), as across the gear contacts.
enum class PreampRegion : int {
  kLow = -1,
  kLinear = 0,
  kHigh = 1,
  kFromState = 2,
};

// The side of the limit for an unclamped preamp output y4 + T_z·y5 (V) and
// limit V_L (V, > 0); T is double or ceres::Jet (compared by value). Never
// throws.
template <typename T>
PreampRegion PreampRegionOf(const T& pre_vc, const T& V_L) {
  if (pre_vc > V_L) return PreampRegion::kHigh;
  if (pre_vc < -V_L) return PreampRegion::kLow;
  return PreampRegion::kLinear;
}

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

// A parameter or parameter combination as it enters the derivative: its
// value as a T and, when its derivative part is zero (it involves no free
// parameter: every fixed parameter of a fit), the plain double, so that a
// product with it costs a Jet×double instead of a Jet×Jet (bench/: about a
// third of the arithmetic of a Jet step). The product is the same number
// either way: with a zero derivative part, Jet×Jet computes exactly the
// terms of Jet×double plus zeros.
template <typename T>
struct Coefficient {
  T value = T(0.0);
  double plain = 0.0;
  bool constant = true;

  Coefficient() = default;
  explicit Coefficient(const T& v)
      : value(v), plain(ScalarValue(v)), constant(MaxAbsDerivative(v) == 0.0) {}
};

// c·x, as Jet×double when c is constant.
template <typename T>
T operator*(const Coefficient<T>& c, const T& x) {
  if constexpr (std::is_same<T, double>::value) {
    return x * c.plain;
  }
  if (c.constant) return T(x * c.plain);
  return T(c.value * x);
}

// CurrentLoop::kQuasiSteady: the rate (1/s) at which the current returns to
// its quasi-steady value i_qs = (K_a·V_c − K_e·ω)/(K_a/K_i + R) when it is
// off it (after the voltage limit V_M released it), in place of the loop's
// own (K_a/K_i + R)/L when that is faster. A numerical device, not a
// parameter: 2·10⁴ 1/s (50 µs) keeps RK4 stable up to h = 2.785/κ = 139 µs,
// the preamp roll-off T_r (1/T_r = 6.3·10³ 1/s) up to 443 µs.
constexpr double kQuasiSteadyCurrentRate = 2.0e4;

// Combinations of parameters that do not depend on the state, formed once
// per simulation instead of at every derivative evaluation: with Jet scalars
// every product and quotient costs as much as the state arithmetic itself.
template <typename T>
struct AxisCoefficients {
  Coefficient<T> inv_mass;       // 1/(M + ΔM + m_p·l_p²) (ΔM only with payload,
                                 // m_p·l_p² only with the pendulum load)
  Coefficient<T> B_a_per_mass;   // B_a/(M + ΔM + m_p·l_p²)
  Coefficient<T> K_tau_per_J;    // K_τ/J_m
  Coefficient<T> B_m_per_J;      // B_m/J_m
  Coefficient<T> r_g_per_J;      // r_g/J_m
  Coefficient<T> inv_J_m;        // 1/J_m
  Coefficient<T> K_a_per_K_i;    // K_a/K_i
  Coefficient<T> inv_L;          // 1/L
  Coefficient<T> R_per_L;        // R/L
  Coefficient<T> inv_R;          // 1/R (voltage_drive)
  Coefficient<T> K_e_per_L;      // K_e/L
  // CurrentLoop::kQuasiSteady only (zero otherwise): the quasi-steady
  // current i_qs = K_a_loop·V_c − K_e_loop·ω and its relaxation rate κ.
  Coefficient<T> K_a_loop;       // K_a/(K_a/K_i + R), A/V
  Coefficient<T> K_e_loop;       // K_e/(K_a/K_i + R), A·s/rad
  double loop_rate = 0.0;        // κ, 1/s (kQuasiSteadyCurrentRate)
  Coefficient<T> inv_r_g;        // 1/r_g
  Coefficient<T> inv_inertia;    // rigid: 1/(J_m + r_g²·mass)
  Coefficient<T> damping;        // rigid: B_m + r_g²·B_a
  Coefficient<T> pre_u;          // K_1/(T_p·T_r)
  Coefficient<T> pre_omega;      // K_2·K_t/(T_p·T_r)
  Coefficient<T> pre_y4;         // 1/(T_p·T_r)
  Coefficient<T> pre_y5;         // (T_p + T_r)/(T_p·T_r)
  // Parameters used as factors in eq. 2–5 themselves.
  Coefficient<T> T_z;            // preamp zero T_z (eq. 2)
  Coefficient<T> K_a;            // current-loop gain K_a (eq. 3)
  Coefficient<T> r_g;            // gear radius r_g (eq. 4–5)
  Coefficient<T> k_g;            // gear stiffness k_g (eq. 5)
  Coefficient<T> b_g;            // gear friction b_g (eq. 5)
  // The load terms of §4: the lifted weight m_g·g (N) and the pendulum's
  // m_p·g·l_p (N·m); zero where the model has none.
  Coefficient<T> weight;
  Coefficient<T> pendulum;
  Coefficient<T> delta_st;       // the Stribeck exponent δ (§7)
  // MODEL.md §7 force_map (if enabled): the spline's second derivatives at
  // its knots (ForceMapSecondDerivatives, sim/force_map.h), N/unit².
  std::array<T, kMaxForceMapKnots> f_map_m{};
};

// The coefficients of `p` for `structure`. Never throws.
template <typename T>
AxisCoefficients<T> MakeAxisCoefficients(const AxisStructure& structure,
                                         const AxisParams<T>& p) {
  using C = Coefficient<T>;
  AxisCoefficients<T> c;
  T mass = structure.effects.payload ? T(p.M + p.Delta_M) : p.M;
  if (structure.load == LoadTerm::kPendulum) mass += p.m_p * p.l_p * p.l_p;
  const T inv_mass = T(1.0) / mass;
  const T inv_J_m = T(1.0) / p.J_m;
  const T inv_L = T(1.0) / p.L;
  const T pre_y4 = T(1.0) / (p.T_p * p.T_r);
  c.inv_mass = C(inv_mass);
  c.B_a_per_mass = C(p.B_a * inv_mass);
  c.inv_J_m = C(inv_J_m);
  c.K_tau_per_J = C(p.K_tau * inv_J_m);
  c.B_m_per_J = C(p.B_m * inv_J_m);
  c.r_g_per_J = C(p.r_g * inv_J_m);
  c.K_a_per_K_i = C(p.K_a / p.K_i);
  c.inv_L = C(inv_L);
  c.R_per_L = C(p.R * inv_L);
  c.K_e_per_L = C(p.K_e * inv_L);
  c.inv_R = C(T(1.0) / p.R);
  if (structure.current_loop == CurrentLoop::kQuasiSteady) {
    const T inv_loop = T(1.0) / (p.K_a / p.K_i + p.R);
    c.K_a_loop = C(p.K_a * inv_loop);
    c.K_e_loop = C(p.K_e * inv_loop);
    c.loop_rate = std::min(ScalarValue(inv_L) / ScalarValue(inv_loop), kQuasiSteadyCurrentRate);
  }
  c.inv_r_g = C(T(1.0) / p.r_g);
  c.inv_inertia = C(T(1.0) / (p.J_m + p.r_g * p.r_g * mass));
  c.damping = C(p.B_m + p.r_g * p.r_g * p.B_a);
  c.pre_y4 = C(pre_y4);
  c.pre_u = C(p.K1 * pre_y4);
  c.pre_omega = C(p.K2 * p.K_t * pre_y4);
  c.pre_y5 = C((p.T_p + p.T_r) * pre_y4);
  c.T_z = C(p.T_z);
  c.K_a = C(p.K_a);
  c.r_g = C(p.r_g);
  c.k_g = C(p.k_g);
  c.b_g = C(p.b_g);
  if (structure.load == LoadTerm::kGravity) c.weight = C(p.m_g * kStandardGravity);
  if (structure.load == LoadTerm::kPendulum) {
    c.pendulum = C(p.m_p * kStandardGravity * p.l_p);
  }
  c.delta_st = C(p.delta_st);
  if (structure.force_map.enabled) {
    ForceMapSecondDerivatives(structure.force_map.knots, p.f_map, &c.f_map_m);
  }
  return c;
}

namespace internal {

inline bool AnyLoadEffect(const AxisStructure& s) {
  const EffectSwitches& e = s.effects;
  return e.coulomb || e.stribeck || e.viscous_asymmetry || e.load_offset ||
         e.spring || e.friction_patch || e.quadratic_drag || e.position_ripple ||
         e.velocity_bump || s.force_map.enabled || s.load != LoadTerm::kNone;
}

// The Stribeck term's shape exp(−|v/v_st|^δ) (MODEL.md §7): the Gaussian
// exp(−(v/v_st)²) where δ is a constant 2 (the default), else through pow,
// 1 at v = 0 (where pow's derivative in δ, log 0, is not defined).
template <typename T>
T StribeckShape(const AxisParams<T>& p, const AxisCoefficients<T>& c, const T& v) {
  using std::abs;
  using std::exp;
  using std::pow;
  const T r = v / p.v_st;
  if (c.delta_st.constant && c.delta_st.plain == 2.0) return exp(-r * r);
  const T a = abs(r);
  if (ScalarValue(a) == 0.0) return T(1.0);
  return exp(-pow(a, p.delta_st));
}

// The load-side force opposing the motion (N, or N·m on a rotary axis):
// static friction eq. 6, the load term of §4 (a weight, a pendulum) and
// the §7 force effects, with the generator-only forces; *any false (and
// zero) where the structure has none.
template <typename T>
T LoadForce(const AxisStructure& structure, const AxisParams<T>& p,
            const AxisCoefficients<T>& c, const T& x, const T& v, bool* any) {
  using std::abs;
  using std::exp;
  using std::sin;
  using std::tanh;
  const EffectSwitches& e = structure.effects;
  const bool static_friction = p.F_s != 0.0 && v < p.w && v > -p.w &&
                               v != 0.0;
  *any = static_friction || AnyLoadEffect(structure);
  T f_load(0.0);
  if (!*any) return f_load;
  if (static_friction) f_load += v > 0.0 ? p.F_s : T(-p.F_s);
  if (e.coulomb || e.stribeck || e.viscous_asymmetry) {
    const T sgn = tanh(v / p.v_eps);
    if (e.coulomb) f_load += p.F_c * sgn;
    if (e.stribeck) f_load += (p.F_st - p.F_c) * StribeckShape(p, c, v) * sgn;
    if (e.viscous_asymmetry) {
      f_load += p.Delta_B * v * (T(1.0) - sgn) * 0.5;
    }
  }
  if (e.load_offset) f_load += p.F_0;
  // §4 load terms: the weight of a vertical axis's load (x upwards) and the
  // pendulum's gravity torque, restoring towards x = −θ_p.
  if (structure.load == LoadTerm::kGravity) f_load += c.weight.value;
  if (structure.load == LoadTerm::kPendulum) f_load += c.pendulum * T(sin(x + p.theta_p));
  if (e.spring) f_load += p.k_x * (x - p.x_0);
  // Generator-only forces (outside MODEL.md §7; sim/axis_params.h). The
  // patch's window rises from 0 to 1 over ±2·w_pt around x_pt0 and falls
  // back around x_pt1: ½[tanh((x − x_pt0)/w_pt) − tanh((x − x_pt1)/w_pt)].
  if (e.friction_patch) {
    const T window = (tanh((x - p.x_pt0) / p.w_pt) - tanh((x - p.x_pt1) / p.w_pt)) * 0.5;
    f_load += p.F_pt * window * tanh(v / p.v_eps);
  }
  if (e.quadratic_drag) f_load += p.C_d * v * abs(v);
  // A force periodic in the load position (a ball screw's or a rack's
  // pitch error, guide waviness): unlike cogging, whose period is set by
  // the motor angle, its period λ_rp is the job's to choose.
  if (e.position_ripple) {
    f_load += p.F_rp * sin(T(6.283185307179586476925) * x / p.lambda_rp + p.phi_rp);
  }
  // A friction that peaks at a speed and fades above it (a lubrication
  // regime change): F_vb·exp(−((|v| − v_vb)/w_vb)²)·sgn_ε(v).
  if (e.velocity_bump) {
    const T r = (abs(v) - p.v_vb) / p.w_vb;
    f_load += p.F_vb * exp(-r * r) * tanh(v / p.v_eps);
  }
  // MODEL.md §7 force_map: f(x), f(v) or f(x)·sgn_ε(v) (sim/force_map.h).
  const ForceMap& map = structure.force_map;
  if (map.enabled) {
    const T& z = map.variable == ForceMapVariable::kV ? v : x;
    const T f = ForceMapValue(map.knots, p.f_map, c.f_map_m, z);
    f_load += map.friction ? T(f * tanh(v / p.v_eps)) : f;
  }
  return f_load;
}

// MODEL.md §7 load_friction: a gearbox's friction that grows with the force
// (or torque) F it transmits to the load, F = K_τ·i/r_g (the drive's force
// at the load: the motor's inertia and friction neglected), opposing the
// motion: s·(μ_d·(|F| + F·s) + μ_b·(|F| − F·s))/2 with s = sgn_ε(v): μ_d·|F|
// where the motor drives the load (F·v > 0), μ_b·|F| where the load drives
// the motor; continuous where F changes sign (both parts vanish with F).
template <typename T>
T LoadDependentFriction(const AxisParams<T>& p, const AxisCoefficients<T>& c, const T& v,
                        const T& i) {
  using std::abs;
  using std::tanh;
  const T s = tanh(v / p.v_eps);
  const T f = c.inv_r_g * T(p.K_tau * i);
  const T a = abs(f);
  return s * (p.mu_d * (a + f * s) + p.mu_b * (a - f * s)) * 0.5;
}

// The motor-side torque effects (N·m): motor Coulomb friction and cogging.
template <typename T>
T MotorTorque(const AxisStructure& structure, const AxisParams<T>& p, const T& theta,
              const T& omega) {
  using std::sin;
  using std::tanh;
  const EffectSwitches& e = structure.effects;
  T t_motor(0.0);
  if (e.motor_coulomb) t_motor += p.T_c * tanh(omega / p.omega_eps);
  if (e.cogging) {
    t_motor += p.A_cog * sin(double(structure.N_cog) * theta + p.phi_cog);
  }
  return t_motor;
}

// The amplifier's signals: the motor current i (A), V_c and V_m (V).
template <typename T>
struct AmplifierSignals {
  T i, vc, vm;
};

// The amplifier (eq. 2, y4–y5; eq. 3, y6 under the full current loop; the
// voltage drive of §4, y6 its winding current with structure.inductance):
// writes dy[4..6] (dy[6] = 0 under the quasi-steady loop,
// QuasiSteadyCurrent sets it after ω') and *preamp where it is kFromState.
// With the drive off (`drive_on` false, §4 drive enable) a voltage drive or
// a current source passes no current (an inductive winding's y6 then
// returns to 0 at R/L); the analog loop ignores it (the loaders refuse an
// enable channel there).
template <typename T>
AmplifierSignals<T> AmplifierDerivative(const AxisStructure& structure,
                                        const AxisParams<T>& p, const AxisCoefficients<T>& c,
                                        const AxisState<T>& y, const T& u, const T& omega,
                                        bool drive_on, PreampRegion* preamp, AxisState<T>* dy) {
  AmplifierSignals<T> out{T(0.0), T(0.0), T(0.0)};
  if (structure.amplifier == Amplifier::kForceSource) {
    (*dy)[4] = (*dy)[5] = (*dy)[6] = T(0.0);
    return out;
  }
  if (structure.amplifier == Amplifier::kVoltageDrive) {
    // U on the terminals: i = (U − K_e·ω)/R, or with the inductance
    // L·y6' = U − R·y6 − K_e·ω. Off, the bridge is open: no current, and
    // the terminals show the back-EMF; an inductive winding's state then
    // returns to 0 at its own rate R/L (MODEL.md §4).
    (*dy)[4] = (*dy)[5] = (*dy)[6] = T(0.0);
    out.vc = u;
    out.vm = drive_on ? u : T(p.K_e * omega);
    if (structure.inductance) {
      out.i = drive_on ? y[6] : T(0.0);
      (*dy)[6] = drive_on ? T(c.inv_L * u - c.R_per_L * y[6] - c.K_e_per_L * omega)
                          : T(-(c.R_per_L * y[6]));
    } else if (drive_on) {
      out.i = c.inv_R * T(u - p.K_e * omega);
    }
    return out;
  }
  const T pre_vc = y[4] + c.T_z * y[5];  // V_c before the clamp of eq. 2
  if (*preamp == PreampRegion::kFromState) *preamp = PreampRegionOf(pre_vc, p.V_L);
  out.vc = *preamp == PreampRegion::kHigh  ? p.V_L
           : *preamp == PreampRegion::kLow ? T(-p.V_L)
                                           : pre_vc;
  (*dy)[4] = y[5];
  (*dy)[5] = c.pre_u * u - c.pre_omega * omega - c.pre_y4 * y[4] -
             c.pre_y5 * y[5];
  if (structure.amplifier == Amplifier::kAnalogVelocityLoop) {
    out.i = y[6];
    if (structure.current_loop == CurrentLoop::kFull) {
      out.vm = Clamp(T(c.K_a * out.vc - c.K_a_per_K_i * out.i), p.V_M);
      (*dy)[6] = c.inv_L * out.vm - c.R_per_L * out.i - c.K_e_per_L * omega;
    } else {
      (*dy)[6] = T(0.0);  // kQuasiSteady: y6' after ω'
    }
  } else {
    out.i = drive_on ? T(p.K_i * out.vc) : T(0.0);
    out.vm = p.R * out.i + p.K_e * omega;
    (*dy)[6] = T(0.0);
  }
  return out;
}

// The mechanics' outputs: the load's acceleration a (m/s²), the gear force
// F_g and the force on the load the `force` channel records (N).
template <typename T>
struct MechanicsSignals {
  T a, fg, force;
};

// The mechanics (eq. 1, 4, 5, or the rigid reduction of §4, or the force
// source): writes dy[2], dy[3]; the gear contact is the state's where
// `contact` is kFromState.
template <typename T>
MechanicsSignals<T> Mechanics(const AxisStructure& structure, const AxisParams<T>& p,
                              const AxisCoefficients<T>& c, const T& x, const T& v,
                              const T& theta, const T& omega, const T& u, const T& i,
                              const T& f_load, bool has_load_force, const T& t_motor,
                              bool has_motor_torque, GearContact contact, AxisState<T>* dy) {
  MechanicsSignals<T> m;
  if (structure.coupling != Coupling::kRigid) {
    const T gap = c.r_g * theta - x;  // X, eq. 4
    if (contact == GearContact::kFromState) {
      contact = gap > p.H    ? GearContact::kPositive
                : gap < -p.H ? GearContact::kNegative
                             : GearContact::kFree;
    }
    if (contact == GearContact::kPositive) {
      m.fg = c.k_g * T(gap - p.H) + c.b_g * T(c.r_g * omega - v);
    } else if (contact == GearContact::kNegative) {
      m.fg = c.k_g * T(gap + p.H) + c.b_g * T(c.r_g * omega - v);
    } else {
      m.fg = T(0.0);
    }
    m.a = c.inv_mass * m.fg - c.B_a_per_mass * v;
    if (has_load_force) m.a -= c.inv_mass * f_load;
    (*dy)[2] = omega;
    (*dy)[3] = c.K_tau_per_J * i - c.B_m_per_J * omega - c.r_g_per_J * m.fg;
    if (has_motor_torque) (*dy)[3] -= c.inv_J_m * t_motor;
    m.force = m.fg;
  } else if (structure.amplifier == Amplifier::kForceSource) {
    m.force = p.g_F * u;
    T f = m.force - p.B_a * v - f_load;
    if (has_motor_torque) f -= c.inv_r_g * t_motor;
    m.a = c.inv_mass * f;
    m.fg = m.force;
    (*dy)[2] = omega;
    (*dy)[3] = c.inv_r_g * m.a;
  } else {
    const T domega =
        c.inv_inertia *
        T(p.K_tau * i - c.damping * omega - c.r_g * f_load - t_motor);
    m.a = c.r_g * domega;
    m.force = c.inv_r_g * T(p.K_tau * i);
    m.fg = m.a / c.inv_mass.value + p.B_a * v + f_load;
    (*dy)[2] = omega;
    (*dy)[3] = domega;
  }
  return m;
}

// y6' under the quasi-steady current loop (MODEL.md §4), once ω' is known.
// Eq. 3 is L·y6' = clamp(K_a·V_c − (K_a/K_i)·y6, ±V_M) − R·y6 − K_e·ω,
// i.e. y6' = clamp((K_a/K_i + R)/L·(i_qs − y6), lo, hi) with
// lo, hi = (∓V_M − R·y6 − K_e·ω)/L, the rates the voltage limit allows.
// In the limit K_a → ∞ the unsaturated current is i_qs itself: y6' =
// i_qs' (+ κ·(i_qs − y6) to return to it after a saturation), clamped
// to the same [lo, hi]. Returns V_m.
template <typename T>
T QuasiSteadyCurrent(const AxisParams<T>& p, const AxisCoefficients<T>& c, const T& omega,
                     const AmplifierSignals<T>& amp, PreampRegion preamp, AxisState<T>* dy) {
  const T dvc = preamp == PreampRegion::kLinear ? T((*dy)[4] + c.T_z * (*dy)[5])
                                                : T(0.0);
  const T i_qs = c.K_a_loop * amp.vc - c.K_e_loop * omega;
  const T di_qs = c.K_a_loop * dvc - c.K_e_loop * T((*dy)[3]);
  const T drive = di_qs + c.loop_rate * T(i_qs - amp.i);
  const T back = c.R_per_L * amp.i + c.K_e_per_L * omega;  // (R·y6 + K_e·ω)/L
  const T v_max = c.inv_L * p.V_M;
  (*dy)[6] = drive > v_max - back ? T(v_max - back)
             : drive < -v_max - back ? T(-v_max - back) : drive;
  return p.L * T((*dy)[6] + back);
}

}  // namespace internal

// Writes dy = f(y, u) for the model of MODEL.md §3–4 and §7.
//   structure: amplifier, coupling and enabled effects (not differentiated).
//   p: parameters in SI units (MODEL.md §2, §7). Masses, inertias, L, T_p,
//      T_r must be positive (the config loader checks; not checked here).
//   c: MakeAxisCoefficients(structure, p).
//   y: state y0..y6 (MODEL.md §1). u: set-velocity voltage U (V), the
//      force-source input (V, force g_F·U) or the voltage drive's terminal
//      voltage (V).
//   dy: derivative of y (must not alias y). aux: optional algebraic outputs.
//   contact: the branch of eq. 5 (gear coupling only); by default the one
//      the state is in.
//   preamp: the side of the limit of eq. 2 (analog velocity loop); by
//      default the one the state is in.
//   drive_on: the drive enable of MODEL.md §4 (false: a voltage drive or a
//      current source passes no current, a force source applies no force;
//      the analog velocity loop ignores it).
// The parts, in the order they are evaluated: internal::LoadForce,
// internal::MotorTorque, internal::AmplifierDerivative, internal::Mechanics and, under
// the quasi-steady current loop, internal::QuasiSteadyCurrent.
// Never throws; non-finite inputs give non-finite outputs.
template <typename T>
AXIS_FLATTEN void AxisDerivative(const AxisStructure& structure,
                                 const AxisParams<T>& p,
                                 const AxisCoefficients<T>& c,
                                 const AxisState<T>& y,
                    const T& u, AxisState<T>* dy, AxisAux<T>* aux = nullptr,
                    GearContact contact = GearContact::kFromState,
                    PreampRegion preamp = PreampRegion::kFromState, bool drive_on = true) {
  const bool rigid = structure.coupling == Coupling::kRigid;
  const T& x = y[0];
  const T& v = y[1];
  // In rigid coupling the motor follows the load exactly.
  const T theta = rigid ? T(c.inv_r_g * x) : y[2];
  const T omega = rigid ? T(c.inv_r_g * v) : y[3];
  bool has_load_force = false;
  T f_load = internal::LoadForce(structure, p, c, x, v, &has_load_force);
  const bool has_motor_torque = structure.effects.motor_coulomb || structure.effects.cogging;
  const T t_motor = internal::MotorTorque(structure, p, theta, omega);
  internal::AmplifierSignals<T> amp =
      internal::AmplifierDerivative(structure, p, c, y, u, omega, drive_on, &preamp, dy);
  if (structure.effects.load_friction && structure.amplifier != Amplifier::kForceSource) {
    f_load += internal::LoadDependentFriction(p, c, v, amp.i);
    has_load_force = true;
  }
  const internal::MechanicsSignals<T> m =
      internal::Mechanics(structure, p, c, x, v, theta, omega, drive_on ? u : T(0.0), amp.i,
                          f_load, has_load_force, t_motor, has_motor_torque, contact, dy);
  (*dy)[0] = v;
  (*dy)[1] = m.a;
  if (structure.amplifier == Amplifier::kAnalogVelocityLoop &&
      structure.current_loop == CurrentLoop::kQuasiSteady) {
    amp.vm = internal::QuasiSteadyCurrent(p, c, omega, amp, preamp, dy);
  }
  if (aux != nullptr) {
    aux->a = m.a;
    aux->i = amp.i;
    aux->vc = amp.vc;
    aux->vm = amp.vm;
    aux->fg = m.fg;
    aux->force = m.force;
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
