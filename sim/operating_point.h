// The operating point of the axis under a constant input, and whether the
// model linearised there (sim/linearisation.h) describes small motions
// about it (MODEL.md §9).
//
// The operating point is the model's steady state under the constant input
// u (V): steady motion, where every rate but the positions' vanishes
// (a = 0, ω' = 0, the amplifier's states at rest, and with gear coupling
// r_g·ω = v), the position held at the start's; or, where the load has a
// position-dependent restoring force (a spring, a pendulum), the
// equilibrium at rest (v = ω = 0, the position free). It is found by
// Gauss–Newton on those equations from `start` (AxisDerivative with ceres::Jet
// for the Jacobian, a minimum-norm step, halved until the residual falls);
// with backlash, where that fails, from the gear in contact on either side
// (r_g·θ − x = ±2H): inside the backlash the deflection enters no equation.
// Forces periodic in the load's or the motor's position (cogging, the
// position ripple, the friction patch) average out over steady motion and
// are left out (AveragedStructure).
//
// The linear model is meaningful there (LinearModelBlocker returns "")
// unless a hard nonlinearity acts at the point: a friction that switches
// with the sign of the velocity (Coulomb, Stribeck, viscous asymmetry, the
// velocity bump, load_friction, a friction force map) with |v| < 3·v_ε
// (tanh(3) = 0.995: outside that band its slope is that of the smooth
// friction), motor Coulomb friction with |ω| < 3·ω_ε, the static friction
// band |v| < w with F_s > 0, the preamp output at its limit V_L, the
// current loop's voltage at V_M (full loop), or the gear inside its
// backlash (|r_g·θ − x| ≤ H with H > 0).
#ifndef SIM_OPERATING_POINT_H_
#define SIM_OPERATING_POINT_H_

#include <string>

#include "sim/axis_model.h"
#include "sim/axis_params.h"

namespace axis {

struct OperatingPoint {
  AxisState<double> state = AxisState<double>::Zero();
  double input = 0.0;      // u, V
  bool converged = false;  // the steady-state equations hold (relative 1e-9)
  int iterations = 0;
};

// `structure` without the forces periodic in position (cogging,
// position_ripple, friction_patch). Never throws.
AxisStructure AveragedStructure(const AxisStructure& structure);

// The steady state under constant input `u` from `start` (see above), for
// the structure as given (pass AveragedStructure's for the rule above).
// Never throws; converged false where Gauss–Newton did not reach it within
// 200 iterations (no steady state, e.g. a drive that cannot overcome the
// load, or one it reaches only through a switching nonlinearity).
OperatingPoint FindOperatingPoint(const AxisStructure& structure, const AxisParams<double>& p,
                                  const AxisState<double>& start, double u);

// "" if the linear model at `point` is meaningful, else why not, in words
// (e.g. "the velocity 1.2e-05 m/s is within 3·v_eps of zero, where Coulomb
// friction switches"). A point that did not converge is "no steady state
// under the mean input …". Never throws (but std::bad_alloc).
std::string LinearModelBlocker(const AxisStructure& structure, const AxisParams<double>& p,
                               const OperatingPoint& point);

}  // namespace axis

#endif  // SIM_OPERATING_POINT_H_
