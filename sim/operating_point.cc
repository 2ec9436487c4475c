#include "sim/operating_point.h"

#include <cmath>
#include <sstream>
#include <vector>

#include <Eigen/Core>

#include "sim/dense_decompositions.h"
#include "sim/linearisation.h"
#include "sim/simulate.h"

namespace axis {
namespace {

using Jet = ceres::Jet<double, kNumStates>;
constexpr int kMaxIterations = 200;

// Which states are unknown and which equations hold at the steady state.
struct SteadyEquations {
  std::vector<int> unknowns;
  bool rest = false;  // equilibrium at rest (v = ω = 0) rather than steady motion
  bool gear = false;  // r_g·ω − v = 0 among the equations
};

SteadyEquations EquationsFor(const AxisStructure& s) {
  SteadyEquations q;
  q.rest = s.effects.spring || s.load == LoadTerm::kPendulum;
  q.gear = s.coupling != Coupling::kRigid && !q.rest;
  q.unknowns = q.rest ? std::vector<int>{0, 2, 4, 5, 6} : std::vector<int>{1, 2, 3, 4, 5, 6};
  return q;
}

// The residual of the steady-state equations at y and its Jacobian in the
// unknowns, each row divided by its Jacobian row's norm (equilibrated).
void Residual(const AxisStructure& s, const AxisParams<Jet>& pj, const AxisParams<double>& p,
              const SteadyEquations& q, const AxisState<double>& y, double u,
              Eigen::VectorXd* r, Eigen::MatrixXd* jacobian) {
  AxisState<Jet> yj;
  for (int k = 0; k < kNumStates; ++k) yj[k] = Jet(y[k], k);
  AxisState<Jet> dy;
  AxisDerivative(s, pj, MakeAxisCoefficients(s, pj), yj, Jet(u), &dy,
                 static_cast<AxisAux<Jet>*>(nullptr), LinearisationContact(s, p, y));
  std::vector<Jet> eq = {dy[1], dy[3], dy[4], dy[5], dy[6]};
  if (q.gear) eq.push_back(yj[3] * p.r_g - yj[1]);
  r->resize(static_cast<Eigen::Index>(eq.size()));
  jacobian->resize(static_cast<Eigen::Index>(eq.size()),
                   static_cast<Eigen::Index>(q.unknowns.size()));
  for (size_t i = 0; i < eq.size(); ++i) {
    double norm = 0.0;
    for (size_t j = 0; j < q.unknowns.size(); ++j) {
      (*jacobian)(i, j) = eq[i].v[q.unknowns[j]];
      norm += (*jacobian)(i, j) * (*jacobian)(i, j);
    }
    norm = norm > 0.0 ? std::sqrt(norm) : 1.0;
    (*r)(i) = eq[i].a / norm;
    jacobian->row(static_cast<Eigen::Index>(i)) /= norm;
  }
}

bool SwitchingFriction(const AxisStructure& s) {
  const EffectSwitches& e = s.effects;
  return e.coulomb || e.stribeck || e.viscous_asymmetry || e.velocity_bump ||
         e.load_friction || (s.force_map.enabled && s.force_map.friction);
}

}  // namespace

AxisStructure AveragedStructure(const AxisStructure& structure) {
  AxisStructure s = structure;
  s.effects.cogging = false;
  s.effects.position_ripple = false;
  s.effects.friction_patch = false;
  return s;
}

namespace {

// Gauss–Newton from one start (FindOperatingPoint).
OperatingPoint SolveFrom(const AxisStructure& structure, const AxisParams<double>& p,
                         const AxisState<double>& start, double u) {
  const SteadyEquations q = EquationsFor(structure);
  const AxisParams<Jet> pj = internal::ParamsAs<Jet>(p);
  OperatingPoint point;
  point.input = u;
  point.state = start;
  if (q.rest) point.state[1] = point.state[3] = 0.0;
  Eigen::VectorXd r;
  Eigen::MatrixXd jacobian;
  Residual(structure, pj, p, q, point.state, u, &r, &jacobian);
  const double r0 = r.norm();
  // Past the tolerance the steps go on while they lower the residual (to
  // round-off: Newton converges quadratically there).
  for (int it = 0; it < kMaxIterations && std::isfinite(r.norm()); ++it) {
    if (r.norm() <= 1e-9 * r0 || r.norm() == 0.0) point.converged = true;
    if (r.norm() == 0.0) break;
    point.iterations = it + 1;
    const Eigen::VectorXd step = CodSolve(jacobian, -r);
    double length = 1.0;
    bool decreased = false;
    for (int halving = 0; halving < 40 && !decreased; ++halving, length *= 0.5) {
      AxisState<double> trial = point.state;
      for (size_t j = 0; j < q.unknowns.size(); ++j) trial[q.unknowns[j]] += length * step(j);
      Eigen::VectorXd r_trial;
      Eigen::MatrixXd j_trial;
      Residual(structure, pj, p, q, trial, u, &r_trial, &j_trial);
      if (r_trial.norm() < r.norm()) {
        point.state = trial;
        r = r_trial;
        jacobian = j_trial;
        decreased = true;
      }
    }
    if (!decreased) break;
  }
  if (!point.converged) point.converged = r.norm() <= 1e-9 * r0 || r.norm() == 0.0;
  return point;
}

}  // namespace

OperatingPoint FindOperatingPoint(const AxisStructure& structure, const AxisParams<double>& p,
                                  const AxisState<double>& start, double u) {
  OperatingPoint point = SolveFrom(structure, p, start, u);
  if (point.converged || structure.coupling == Coupling::kRigid || !(p.H > 0.0)) return point;
  // Inside the backlash the gear's deflection enters no equation: steady
  // motion is found from a start in contact, on either side.
  for (double side : {1.0, -1.0}) {
    AxisState<double> y = start;
    y[2] = (y[0] + side * 2.0 * p.H) / p.r_g;
    const OperatingPoint other = SolveFrom(structure, p, y, u);
    if (other.converged) return other;
  }
  return point;
}

std::string LinearModelBlocker(const AxisStructure& s, const AxisParams<double>& p,
                               const OperatingPoint& point) {
  std::ostringstream m;
  const AxisState<double>& y = point.state;
  const bool rigid = s.coupling == Coupling::kRigid;
  const double v = y[1];
  const double omega = rigid ? y[1] / p.r_g : y[3];
  if (!point.converged) {
    m << "no steady state under the mean input " << point.input << " V";
  } else if (SwitchingFriction(s) && std::abs(v) < 3.0 * p.v_eps) {
    m << "the velocity " << v << " is within 3*v_eps = " << 3.0 * p.v_eps
      << " of zero, where the friction switches with its sign";
  } else if (s.effects.motor_coulomb && std::abs(omega) < 3.0 * p.omega_eps) {
    m << "the motor velocity " << omega << " rad/s is within 3*omega_eps = "
      << 3.0 * p.omega_eps << " of zero, where motor Coulomb friction switches";
  } else if (p.F_s != 0.0 && std::abs(v) < p.w) {
    m << "the velocity " << v << " is inside the static friction band w = " << p.w;
  } else if (!rigid && p.H > 0.0 && std::abs(p.r_g * y[2] - y[0]) <= p.H) {
    m << "the gear is inside its backlash (|r_g*theta - x| <= H = " << p.H << ")";
  } else if (s.amplifier == Amplifier::kAnalogVelocityLoop ||
             s.amplifier == Amplifier::kCurrentSource) {
    AxisState<double> dy;
    AxisAux<double> aux;
    AxisDerivative(s, p, MakeAxisCoefficients(s, p), y, point.input, &dy, &aux);
    const double pre_vc = y[4] + p.T_z * y[5];
    if (std::abs(pre_vc) >= p.V_L) {
      m << "the preamp output " << pre_vc << " V is at its limit V_L = " << p.V_L << " V";
    } else if (s.amplifier == Amplifier::kAnalogVelocityLoop &&
               s.current_loop == CurrentLoop::kFull && std::abs(aux.vm) >= p.V_M) {
      m << "the motor voltage is at its limit V_M = " << p.V_M << " V";
    }
  }
  return m.str();
}

}  // namespace axis
