// Checks made before simulating (issue 17): the largest step at which
// classical RK4 (sim/rk4.h) is stable on the axis model (a step beyond it
// used to simulate and then fail with "left the finite numbers"), and the
// memory a simulation or fit will need.
//
// The model (MODEL.md §3, with the structure's §4 options and §7 effects)
// is linearised by ceres::Jet at two points with no clamp active: at rest
// (the gear inside the backlash) and at rest with the gear in contact
// (pinion ahead of the rack by 2·H, where the gear stiffness couples motor
// and arm). RK4 is stable for an eigenvalue λ while |R(hλ)| ≤ 1, R(z) = 1 +
// z + z²/2 + z³/6 + z⁴/24 (Hairer & Wanner, "Solving ODEs II", §IV.2); on
// the negative real axis that is h ≤ 2.785/|λ|. For the X axis the fastest
// mode is the current loop, λ ≈ −(K_a/K_i + R)/L = −1.42·10⁵ 1/s, limit
// 19.6 µs (tests/axis_model_test.cc, StabilityTest).
#ifndef SIM_PREFLIGHT_H_
#define SIM_PREFLIGHT_H_

#include <complex>
#include <string>

#include "sim/axis_model.h"
#include "sim/axis_params.h"

namespace axis {

// The stability limit and the eigenvalue that sets it.
struct Rk4StabilityLimit {
  double max_step = 0.0;               // s; +∞ if no eigenvalue limits it
  std::complex<double> eigenvalue;     // 1/s, the limiting one
};

// The largest RK4 step (s) stable at both linearisation points above, found
// by bisection on |R(hλ)| ≤ 1 for every eigenvalue with |λ| > 1e-6 1/s
// (a growing real mode is skipped: it grows in the exact solution too; a
// growing oscillation counts as its undamped twin i·Im λ).
// Never throws; non-finite parameters give a NaN max_step.
Rk4StabilityLimit Rk4StabilityLimitOf(const AxisStructure& structure,
                                      const AxisParams<double>& params);

// Throws std::invalid_argument "<where>: key 'step': expected a step of at
// most <limit> s (the RK4 stability limit of the linearised model, fastest
// eigenvalue <λ> 1/s), got <step> s" if `step` exceeds the limit. `where` is
// the file (and line) for the message.
void CheckRk4Step(const AxisStructure& structure, const AxisParams<double>& params,
                  double step, const std::string& where, const std::string& key);

// Physical memory of this machine in bytes (sysconf), or 0 if unknown.
double PhysicalMemoryBytes();

// Throws std::invalid_argument "<where>: expected <what> to fit in memory
// (at most half of this machine's <P> GiB), got an estimated <B> GiB: <advice>"
// if `bytes` exceeds half the physical memory (checked before allocating:
// a simulation of duration 1e9 s used to end in std::bad_alloc). Does
// nothing if the physical memory is unknown.
void CheckMemory(double bytes, const std::string& where, const std::string& what,
                 const std::string& advice);

}  // namespace axis

#endif  // SIM_PREFLIGHT_H_
