// Parameters of one servo axis: the symbols of MODEL.md §2 and the effect
// parameters of MODEL.md §7, as a plain struct templated on the scalar so that
// the same values can be doubles or ceres::Jet for automatic differentiation.
//
// Every field carries the config name used in YAML files, in the fit's
// parameter tables and on the command line (`--set NAME=VALUE`); the table of
// names and units is VisitParams() below, the single place that lists them.
#ifndef SIM_AXIS_PARAMS_H_
#define SIM_AXIS_PARAMS_H_

#include <array>
#include <string>
#include <vector>

#include "sim/channels.h"
#include "sim/force_map.h"

namespace axis {

// Amplifier configuration, MODEL.md §4.
enum class Amplifier {
  kAnalogVelocityLoop,  // preamp, current loop and both limits (§3 as written)
  kCurrentSource,       // y6 = K_i·V_c exactly; V_c clamped only if V_L finite
  kForceSource,         // F = g_F·U on the load; no motor or preamp states
  kVoltageDrive,        // U (V) on the motor's terminals (a PWM bridge from its
                        // supply, no current loop): i = (U − K_e·ω)/R with the
                        // armature inductance neglected (the default), or
                        // L·y6' = U − R·y6 − K_e·ω with AxisStructure::inductance;
                        // no preamp states
};

// Whether the load moves in a line or turns, MODEL.md §4: the units of the
// load's position, velocity, force, mass and friction (m, m/s, N, kg, N·s/m
// or rad, rad/s, N·m, kg·m², N·m·s/rad). The equations are the same.
enum class Motion {
  kLinear,
  kRotary,
};

// A load term a model config declares (`load:`, MODEL.md §4), acting on the
// load beside the §7 effects. Not a discovery candidate: the user knows
// whether the axis lifts its load.
enum class LoadTerm {
  kNone,
  kGravity,   // a vertical linear axis: F += m_g·g (m_g the lifted mass, kg)
  kPendulum,  // a rotary joint carrying a mass m_p at l_p from its axis:
              // T += m_p·g·l_p·sin(x + θ_p) (x = 0 hanging down), and the
              // load inertia gains m_p·l_p²
};

// Standard gravity g (m/s², CGPM 1901), the g of LoadTerm.
inline constexpr double kStandardGravity = 9.80665;

// Mechanical coupling between motor and load, MODEL.md §4.
enum class Coupling {
  kGear,   // eq. 4–5: separate motor and load states, backlash H, stiffness k_g
  kRigid,  // X ≡ 0: one inertia, x = r_g·θ
};

// Which dynamic effects of MODEL.md §7 are switched on. An enabled effect
// whose parameters are zero adds nothing, which the score test relies on.
// The sensor effects (`sensor_delay`, `sensor_bias`) are per output channel
// and live in AxisParams::tau_d and AxisParams::b with SensorSwitches.
struct EffectSwitches {
  bool coulomb = false;
  bool stribeck = false;
  bool viscous_asymmetry = false;
  bool load_offset = false;
  bool spring = false;
  bool payload = false;
  bool motor_coulomb = false;
  bool cogging = false;
  bool load_friction = false;  // gear friction growing with the transmitted force
  // The Stribeck term's shape exponent δ (`delta_st`) is the model's own
  // (declared, or freed by the discovery loop), not the Gaussian δ = 2 it
  // defaults to; needs `stribeck`. No force of its own: the Stribeck term
  // reads delta_st either way (MODEL.md §7).
  bool stribeck_shape = false;
  // Forces outside MODEL.md §7, for generating data only (issue 10: data
  // whose missing force the discovery loop's library cannot express must end
  // with the verdict `incomplete`). The model config accepts them
  // (GeneratorOnlyEffectTable in sim/config.h); the loop never proposes them.
  bool friction_patch = false;  // F_pt·sgn_ε(v) inside x_pt0 < x < x_pt1
  bool quadratic_drag = false;  // C_d·v·|v|
  bool position_ripple = false;  // F_rp·sin(2π·x/λ_rp + φ_rp)
  bool velocity_bump = false;  // F_vb·exp(−((|v| − v_vb)/w_vb)²)·sgn_ε(v)
};

// Per-channel sensor effects of MODEL.md §7 — the sensor front end of §6 —
// indexed by Channel (sim/sensor_front_end.h).
struct SensorSwitches {
  std::array<bool, kNumChannels> delay{};     // sensor_delay: tau_d.<channel>
  std::array<bool, kNumChannels> bias{};      // sensor_bias: b.<channel>
  std::array<bool, kNumChannels> lowpass{};   // sensor_lowpass: tau_lp.<channel>
  std::array<bool, kNumChannels> lowpass2{};  // sensor_lowpass2: tau_lp2, zeta_lp2
};

// The sensor effects of MODEL.md §7 as a table: the effect's name, the
// prefixes of its per-channel parameters ("tau_d" → "tau_d.a") and its
// switch. The only list of them; the config, the candidates and the
// reports read it.
struct SensorEffectInfo {
  const char* name;
  std::vector<const char*> params;
  std::array<bool, kNumChannels> SensorSwitches::*flag;
};
const std::vector<SensorEffectInfo>& SensorEffectTable();

// True if `name` is a sensor parameter of SensorEffectTable ("tau_d.a",
// "zeta_lp2.tach", ...): one that acts only in the sensor front end of
// MODEL.md §6, after the plant's integration (sim/simulate.h
// ApplySensorFrontEnd). Never throws.
bool IsSensorParameter(const std::string& name);

// How a recorded sample of the accelerometer channel `a` relates to the arm
// acceleration y1' (MODEL.md §6). y1' jumps by b_g·(r_g·ω − v)/M at every
// backlash contact (eq. 5), so its value at a sample instant is a
// discontinuous function of the parameters (the cost jumps whenever a contact
// time crosses a sample time); the mean over the output period is continuous.
enum class AccelerometerSampling {
  kPeriodMean,  // (v(t_k) − v(t_k − T_o))/T_o: mean of y1' over the period
                // T_o ending at the sample (integrate-and-dump anti-aliasing)
  kInstant,     // y1'(t_k) as a sensor of finite bandwidth sees it: the
                // mean over ±AxisStructure::instant_window
};

// How the motor current y6 of the analog_velocity_loop follows eq. 3.
// The current loop is the model's stiffest mode (λ ≈ −(K_a/K_i + R)/L =
// −1.43·10⁵ 1/s for the X axis: RK4 needs h ≤ 19.5 µs); MODEL.md §2 calls
// K_a only "sufficiently large", i.e. the loop is meant to be fast.
enum class CurrentLoop {
  kFull,         // eq. 3 as written (the paper's model, the default)
  kQuasiSteady,  // the unsaturated loop as its fast limit K_a → ∞ (i follows
                 // (K_a·V_c − K_e·ω)/(K_a/K_i + R) and its rate), the
                 // saturated one (|V_m| = V_M) exactly as eq. 3: allows RK4
                 // steps up to about 100 µs. Model error against kFull:
                 // README "Numerics" and tests/axis_model_test.cc.
};

// The discrete (non-differentiable) part of a model: which equations apply.
struct AxisStructure {
  Amplifier amplifier = Amplifier::kAnalogVelocityLoop;
  CurrentLoop current_loop = CurrentLoop::kFull;  // analog_velocity_loop only
  // voltage_drive only (MODEL.md §4, model key `inductance`): the winding
  // current is the state y6, L·y6' = U − R·y6 − K_e·ω, instead of its
  // quasi-steady value (U − K_e·ω)/R. Its fast mode (about −R/L where L/R is
  // far below the mechanics') bounds the RK4 step (about 2.785·L/R;
  // sim/auto_step.h takes it into account).
  bool inductance = false;
  Coupling coupling = Coupling::kGear;
  Motion motion = Motion::kLinear;
  LoadTerm load = LoadTerm::kNone;
  EffectSwitches effects;
  SensorSwitches sensors;
  AccelerometerSampling accelerometer = AccelerometerSampling::kPeriodMean;
  // The instant accelerometer's half-window w (s, > 0; MODEL.md §6): a sample
  // is the mean of y1' over [t_k − w, t_k + w], w rounded to a whole number
  // of RK4 steps (at least one). A property of the sensor, not of the
  // integrator: fits at different steps see the same signal where the step
  // divides it. The default is the paper's step: the narrowest window a fit
  // at 10 µs resolves; a sensor_lowpass on `a` widens the bandwidth, nothing
  // narrows a window wider than the records'.
  double instant_window = 1.0e-5;
  int N_cog = 6;  // cogging periods per motor revolution (fixed, §7)
  // MODEL.md §7 force_map: its variable and knots (sim/force_map.h); its
  // values are AxisParams::f_map.
  ForceMap force_map;
};

// Numerical parameters. Defaults are the X axis of MODEL.md §2 and the
// "off" values of the §7 effects. Units are SI as listed in VisitParams.
// The Stribeck term's Gaussian shape exponent, exp(−(v/v_st)²): delta_st's
// default, and the value the stribeck_shape candidate is tested against and
// reset to (MODEL.md §7).
inline constexpr double kGaussianStribeckShape = 2.0;

template <typename T>
struct AxisParams {
  // MODEL.md §2 (paper table, fitted values and assumptions).
  T R{0.56};
  T L{0.00235};
  T K_e{0.289};
  T K_tau{0.289};
  T J_m{0.000847};
  T B_m{0.000733};
  T K_t{0.0668};
  T r_g{0.00573};
  T H{0.00001};
  T M{146.0};
  T T_z{0.00705};
  T T_p{0.04};
  T T_r{0.000159};
  T K1{1014.0};
  T K2{870.0};
  T K_i{3.0};
  T V_M{95.0};
  T V_L{2.7};
  T B_a{200.0};
  T b_g{1500.0};
  T k_g{5.0e6};
  T K_a{1000.0};
  T F_s{0.0};
  T w{0.001};
  // MODEL.md §4, force_source drive gain.
  T g_F{0.0};
  // MODEL.md §7 effects.
  T v_eps{1e-3};      // sgn_ε width on the load side
  T omega_eps{1e-3};  // sgn_ε width on the motor side
  T F_c{0.0};
  T F_st{0.0};
  T v_st{0.01};
  T delta_st{kGaussianStribeckShape};  // Stribeck shape exponent δ: exp(−|v/v_st|^δ), > 0
  T Delta_B{0.0};
  T F_0{0.0};
  T k_x{0.0};
  T x_0{0.0};
  T Delta_M{0.0};
  T T_c{0.0};
  T A_cog{0.0};
  T phi_cog{0.0};
  // load_friction: Coulomb friction per unit of the drive's force (or
  // torque) on the load, when the motor drives the load (mu_d) and when the
  // load drives the motor (mu_b); both ≥ 0, dimensionless.
  T mu_d{0.0};
  T mu_b{0.0};
  // Load terms (AxisStructure::load, MODEL.md §4).
  T m_g{0.0};      // gravity: the lifted mass (kg)
  T m_p{0.0};      // pendulum: its mass (kg)
  T l_p{0.0};      // pendulum: the distance of its mass from the axis (m)
  T theta_p{0.0};  // pendulum: the angle of the load at which it hangs down is −θ_p (rad)
  // Generator-only forces (EffectSwitches::friction_patch, quadratic_drag,
  // position_ripple, velocity_bump).
  T F_pt{0.0};    // friction inside the patch (N)
  T x_pt0{0.0};   // patch start (m)
  T x_pt1{0.0};   // patch end (m), above x_pt0
  T w_pt{1e-3};   // width of the patch's smooth edges (m), positive
  T C_d{0.0};     // quadratic drag coefficient (N*s^2/m^2)
  T F_rp{0.0};        // position ripple amplitude (N)
  T lambda_rp{0.05};  // its period in the load position x (m), positive
  T phi_rp{0.0};      // its phase (rad)
  T F_vb{0.0};    // velocity bump's peak friction (N)
  T v_vb{0.1};    // the speed of its peak (m/s), non-negative
  T w_vb{0.05};   // its width in speed (m/s), positive
  // Sensor effects, per channel (index Channel), MODEL.md §6–§7:
  // tau_d.<channel> (s, either sign: a delay or an advance), b.<channel>,
  // tau_lp.<channel> (s, ≥ 0: first-order low-pass 1/(τ·s + 1)),
  // tau_lp2.<channel> (s, ≥ 0) and zeta_lp2.<channel> (> 0): second-order
  // low-pass 1/(τ²·s² + 2ζ·τ·s + 1), Butterworth (ζ = 1/√2) by default.
  std::array<T, kNumChannels> tau_d{};
  std::array<T, kNumChannels> b{};
  std::array<T, kNumChannels> tau_lp{};
  std::array<T, kNumChannels> tau_lp2{};
  std::array<T, kNumChannels> zeta_lp2 = Filled(0.70710678118654752);
  // MODEL.md §7 force_map: the force at knot k (N), "f_map.<k>"; entries at
  // and past AxisStructure::force_map.knots.size() are unused.
  std::array<T, kMaxForceMapKnots> f_map{};

  // Element-wise conversion, e.g. AxisParams<double> → AxisParams<Jet>.
  template <typename U>
  AxisParams<U> cast() const;

 private:
  static std::array<T, kNumChannels> Filled(double value) {
    std::array<T, kNumChannels> a;
    a.fill(T(value));
    return a;
  }
};

// Calls visit(name, unit, field...) once for every parameter, passing the
// same field of each of the structs `params...` (all AxisParams of any
// scalar). Names are the config names of MODEL.md §2/§7; per-channel sensor
// parameters are named "tau_d.<channel>", "b.<channel>" (unit of the
// channel for b), "tau_lp.<channel>", "tau_lp2.<channel>" and
// "zeta_lp2.<channel>", the force map's values "f_map.<k>" (N). This is the only list of parameter names in the project.
template <typename Visitor, typename... Params>
void VisitParams(Visitor&& visit, Params&... params) {
  visit("R", "Ohm", params.R...);
  visit("L", "H", params.L...);
  visit("K_e", "V*s/rad", params.K_e...);
  visit("K_tau", "N*m/A", params.K_tau...);
  visit("J_m", "kg*m^2", params.J_m...);
  visit("B_m", "N*m*s", params.B_m...);
  visit("K_t", "V*s/rad", params.K_t...);
  visit("r_g", "m", params.r_g...);
  visit("H", "m", params.H...);
  visit("M", "kg", params.M...);
  visit("T_z", "s", params.T_z...);
  visit("T_p", "s", params.T_p...);
  visit("T_r", "s", params.T_r...);
  visit("K1", "1", params.K1...);
  visit("K2", "1", params.K2...);
  visit("K_i", "A/V", params.K_i...);
  visit("V_M", "V", params.V_M...);
  visit("V_L", "V", params.V_L...);
  visit("B_a", "N*s/m", params.B_a...);
  visit("b_g", "N*s/m", params.b_g...);
  visit("k_g", "N/m", params.k_g...);
  visit("K_a", "V/V", params.K_a...);
  visit("F_s", "N", params.F_s...);
  visit("w", "m/s", params.w...);
  visit("g_F", "N/V", params.g_F...);
  visit("v_eps", "m/s", params.v_eps...);
  visit("omega_eps", "rad/s", params.omega_eps...);
  visit("F_c", "N", params.F_c...);
  visit("F_st", "N", params.F_st...);
  visit("v_st", "m/s", params.v_st...);
  visit("delta_st", "1", params.delta_st...);
  visit("Delta_B", "N*s/m", params.Delta_B...);
  visit("F_0", "N", params.F_0...);
  visit("k_x", "N/m", params.k_x...);
  visit("x_0", "m", params.x_0...);
  visit("Delta_M", "kg", params.Delta_M...);
  visit("T_c", "N*m", params.T_c...);
  visit("A_cog", "N*m", params.A_cog...);
  visit("phi_cog", "rad", params.phi_cog...);
  visit("mu_d", "1", params.mu_d...);
  visit("mu_b", "1", params.mu_b...);
  visit("m_g", "kg", params.m_g...);
  visit("m_p", "kg", params.m_p...);
  visit("l_p", "m", params.l_p...);
  visit("theta_p", "rad", params.theta_p...);
  visit("F_pt", "N", params.F_pt...);
  visit("x_pt0", "m", params.x_pt0...);
  visit("x_pt1", "m", params.x_pt1...);
  visit("w_pt", "m", params.w_pt...);
  visit("C_d", "N*s^2/m^2", params.C_d...);
  visit("F_rp", "N", params.F_rp...);
  visit("lambda_rp", "m", params.lambda_rp...);
  visit("phi_rp", "rad", params.phi_rp...);
  visit("F_vb", "N", params.F_vb...);
  visit("v_vb", "m/s", params.v_vb...);
  visit("w_vb", "m/s", params.w_vb...);
  for (int c = 0; c < kNumChannels; ++c) {
    const Channel ch = static_cast<Channel>(c);
    if (ch == Channel::kT) continue;
    const std::string name = ChannelName(ch);
    visit(("tau_d." + name).c_str(), "s", params.tau_d[c]...);
    visit(("b." + name).c_str(), ChannelUnit(ch), params.b[c]...);
    visit(("tau_lp." + name).c_str(), "s", params.tau_lp[c]...);
    visit(("tau_lp2." + name).c_str(), "s", params.tau_lp2[c]...);
    visit(("zeta_lp2." + name).c_str(), "1", params.zeta_lp2[c]...);
  }
  for (int k = 0; k < kMaxForceMapKnots; ++k) {
    visit(("f_map." + std::to_string(k)).c_str(), "N", params.f_map[k]...);
  }
}

template <typename T>
template <typename U>
AxisParams<U> AxisParams<T>::cast() const {
  AxisParams<U> out;
  VisitParams([](const char*, const char*, const T& from,
                 U& to) { to = U(from); },
              *this, out);
  return out;
}

// Name and unit of every parameter, in VisitParams order.
struct ParamInfo {
  std::string name;
  std::string unit;
};
std::vector<ParamInfo> ListParams();

// Unit of parameter `name` ("" if there is none of that name), as
// VisitParams lists it: a linear axis's.
std::string ParamUnit(const std::string& name);

// Unit of parameter `name` on an axis whose load moves as `motion`: on a
// rotary axis the load's quantities are angles, torques and inertias (M
// "kg*m^2", B_a "N*m*s/rad", F_c "N*m", v_st "rad/s", x_0 "rad", r_g
// "rad/rad": load radians per motor radian, ...); the motor's, the drive's, the
// pendulum's (m_p, l_p) and the sensors' do not change. "" for an unknown
// name. Never throws.
std::string ParamUnit(const std::string& name, Motion motion);

// Pointer to the field called `name`, or nullptr if no parameter has it.
double* FindParam(AxisParams<double>* params, const std::string& name);

}  // namespace axis

#endif  // SIM_AXIS_PARAMS_H_
