// The axis model of MODEL.md §3–4 and §7 linearised at an operating point
// (MODEL.md §9): x' = A·x + B·u, y_c = C_c·x + D_c·u for each recorded
// channel c of MODEL.md §6, with A = ∂f/∂y and B = ∂f/∂u of AxisDerivative
// (sim/axis_model.h) and C_c, D_c the derivatives of the channel's value,
// all by automatic differentiation (ceres::Jet) at the point; its
// frequency response C_c·(j2πf·I − A)⁻¹·B + D_c times the channel's sensor
// front end (delay, low-passes: sim/sensor_front_end.h), its resonances
// (the lightly damped complex poles) and each channel's anti-resonances
// (its lightly damped complex transmission zeros).
#ifndef SIM_LINEARISATION_H_
#define SIM_LINEARISATION_H_

#include <complex>
#include <vector>

#include <Eigen/Core>

#include "sim/axis_model.h"
#include "sim/axis_params.h"
#include "sim/channels.h"

namespace axis {

// The linear system at (y, u). States y0..y6 as AxisState (unused ones of
// a reduced configuration give zero rows and columns); one row of C and D
// per channel of `channels`, in that order.
struct LinearisedAxis {
  Eigen::Matrix<double, kNumStates, kNumStates> A;  // ∂f/∂y, 1/s (state units)
  Eigen::Matrix<double, kNumStates, 1> B;           // ∂f/∂u, state rate per input unit
  std::vector<Channel> channels;
  Eigen::MatrixXd C;  // channels × 7: ∂(channel)/∂y
  Eigen::VectorXd D;  // channels: ∂(channel)/∂u (e.g. a of a force source)
  // Per channel, the sensor front end of MODEL.md §6 (0 where off): delay
  // τ_d (s), first-order τ_lp (s), second-order τ_lp2 (s) and ζ_lp2.
  std::vector<double> tau_d, tau_lp, tau_lp2, zeta_lp2;
};

// Whether channel c is a function of the state and input (not t, u,
// x_ref, v_ref): the channels Linearise takes. Never throws.
inline bool IsStateChannel(Channel c) {
  return c != Channel::kT && c != Channel::kU && c != Channel::kXRef && c != Channel::kVRef;
}

// The gear branch (MODEL.md eq. 5) a linearisation at state y holds: the
// state's (GearContactOf), except with no backlash (H = 0), where both
// contact branches are the same equation and the state's gap 0 would pick
// the free one: then kPositive. kFromState for rigid coupling. Never throws.
GearContact LinearisationContact(const AxisStructure& structure, const AxisParams<double>& p,
                                 const AxisState<double>& y);

// Linearises the model at state `y` and input `u` (the set-velocity
// voltage, the force-source input or the voltage drive's terminal voltage,
// V) for the channels `channels` (not t, u, x_ref or v_ref: those are not
// functions of the state). The gear branch is LinearisationContact's, the
// preamp side the state's. Throws std::invalid_argument naming a channel
// that is not a function of the state, or if A, B, C or D is not finite.
LinearisedAxis Linearise(const AxisStructure& structure, const AxisParams<double>& p,
                         const AxisState<double>& y, double u,
                         const std::vector<Channel>& channels);

// C_k·(j2πf·I − A)⁻¹·B + D_k times the sensor front end of channel row
// `row`, at `frequency` Hz (> 0 where A has a pole at 0). Channel unit per
// input unit. Throws std::out_of_range for a row past the channels.
std::complex<double> LinearResponse(const LinearisedAxis& system, size_t row,
                                    double frequency);

// A root of the system: pole or zero s = −ζ·ω_n ± j·ω_d, reported by its
// natural frequency f_n = |s|/2π (Hz) and damping ratio ζ = −Re s/|s|.
struct LinearMode {
  double frequency = 0.0;  // f_n, Hz
  double damping = 0.0;    // ζ
  std::complex<double> root;  // s (1/s), Im s > 0
};

// Roots with Im s > 0 and |ζ| below this are resonances (poles) or
// anti-resonances (zeros): a second-order pair peaks (or dips) only for
// |ζ| < 1/√2.
inline constexpr double kLightDamping = 0.70710678118654752;

// The resonances: eigenvalues of A with Im s > 0 and |ζ| < kLightDamping,
// by frequency. Never throws.
std::vector<LinearMode> Resonances(const LinearisedAxis& system);

// The anti-resonances of channel row `row`: its transmission zeros with
// Im s > 0 and |ζ| < kLightDamping, by frequency. The zeros are the
// eigenvalues of A − B·(C_k·A^(r−1)·B)⁻¹·C_k·A^r, the dynamics left when
// the input holds the channel at zero (r the relative degree, the first
// r with C_k·A^(r−1)·B ≠ 0; A − B·C_k/D_k where D_k ≠ 0), less its r
// eigenvalues at 0 (Isidori, "Nonlinear Control Systems", 3rd ed., §4.3),
// less those within 10⁻⁶·|s| of a pole of A (a mode the channel does
// not see, or the input does not reach, cancels and is no
// anti-resonance), and less those within 10⁻⁶ of the largest pole's
// magnitude of the origin (zeros at s = 0 of a differentiating channel,
// split by round-off). Empty where the channel's response is identically
// zero. Throws std::out_of_range for a row past the channels.
std::vector<LinearMode> AntiResonances(const LinearisedAxis& system, size_t row);

}  // namespace axis

#endif  // SIM_LINEARISATION_H_
