#include "sim/linearisation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "sim/simulate.h"

namespace axis {
namespace {

constexpr double kTwoPi = 6.28318530717958647692;
// Zeros beyond this multiple of the fastest pole are taken as infinite.
constexpr double kFarZero = 1e3;
using Jet = ceres::Jet<double, kNumStates + 1>;  // 7 states and the input

bool IsStateChannel(Channel c) {
  return c != Channel::kT && c != Channel::kU && c != Channel::kXRef && c != Channel::kVRef;
}

void Sort(std::vector<LinearMode>* modes) {
  std::sort(modes->begin(), modes->end(),
            [](const LinearMode& a, const LinearMode& b) { return a.frequency < b.frequency; });
}

// The root as a mode if it is a lightly damped one with Im s > 0.
bool AsMode(std::complex<double> s, LinearMode* mode) {
  const double w = std::abs(s);
  if (!(s.imag() > 0.0) || !std::isfinite(w) || w == 0.0) return false;
  mode->root = s;
  mode->frequency = w / kTwoPi;
  mode->damping = -s.real() / w;
  return mode->damping < kLightDamping;
}

void SensorFrontEnd(const AxisStructure& structure, const AxisParams<double>& p, Channel c,
                    LinearisedAxis* out) {
  const int k = static_cast<int>(c);
  const SensorSwitches& s = structure.sensors;
  out->tau_d.push_back(s.delay[k] ? p.tau_d[k] : 0.0);
  out->tau_lp.push_back(s.lowpass[k] ? p.tau_lp[k] : 0.0);
  out->tau_lp2.push_back(s.lowpass2[k] ? p.tau_lp2[k] : 0.0);
  out->zeta_lp2.push_back(s.lowpass2[k] ? p.zeta_lp2[k] : 0.0);
}

}  // namespace

GearContact LinearisationContact(const AxisStructure& structure, const AxisParams<double>& p,
                                 const AxisState<double>& y) {
  if (structure.coupling == Coupling::kRigid) return GearContact::kFromState;
  if (p.H == 0.0) return GearContact::kPositive;
  return GearContactOf(p.r_g * y[2] - y[0], p.H);
}

LinearisedAxis Linearise(const AxisStructure& structure, const AxisParams<double>& p,
                         const AxisState<double>& y, double u,
                         const std::vector<Channel>& channels) {
  for (Channel c : channels) {
    if (!IsStateChannel(c)) {
      throw std::invalid_argument(std::string("Linearise: expected channels that are functions "
                                              "of the state, got '") +
                                  ChannelName(c) + "'");
    }
  }
  const AxisParams<Jet> pj = internal::ParamsAs<Jet>(p);
  AxisState<Jet> yj;
  for (int k = 0; k < kNumStates; ++k) yj[k] = Jet(y[k], k);
  const Jet uj(u, kNumStates);
  AxisState<Jet> dy;
  AxisAux<Jet> aux;
  AxisDerivative(structure, pj, MakeAxisCoefficients(structure, pj), yj, uj, &dy, &aux,
                 LinearisationContact(structure, p, y));
  LinearisedAxis out;
  for (int r = 0; r < kNumStates; ++r) {
    for (int k = 0; k < kNumStates; ++k) out.A(r, k) = dy[r].v[k];
    out.B(r) = dy[r].v[kNumStates];
  }
  out.channels = channels;
  out.C.setZero(static_cast<Eigen::Index>(channels.size()), kNumStates);
  out.D.setZero(static_cast<Eigen::Index>(channels.size()));
  for (size_t j = 0; j < channels.size(); ++j) {
    const Jet value =
        internal::ChannelValue(channels[j], structure, pj, yj, aux, uj, ReferenceSample{}, 0.0);
    for (int k = 0; k < kNumStates; ++k) out.C(j, k) = value.v[k];
    out.D(j) = value.v[kNumStates];
    SensorFrontEnd(structure, p, channels[j], &out);
  }
  if (!out.A.allFinite() || !out.B.allFinite() || !out.C.allFinite() || !out.D.allFinite()) {
    throw std::invalid_argument("Linearise: expected a finite linearisation, got a non-finite "
                                "derivative at the operating point");
  }
  return out;
}

std::complex<double> LinearResponse(const LinearisedAxis& system, size_t row,
                                    double frequency) {
  if (row >= system.channels.size()) throw std::out_of_range("LinearResponse: no such channel");
  using Complex = std::complex<double>;
  const double w = kTwoPi * frequency;
  const Complex jw(0.0, w);
  Eigen::Matrix<Complex, kNumStates, kNumStates> m =
      -system.A.cast<Complex>();
  m.diagonal().array() += jw;
  const Eigen::Matrix<Complex, kNumStates, 1> x = m.partialPivLu().solve(system.B.cast<Complex>());
  Complex h = system.C.row(static_cast<Eigen::Index>(row)).cast<Complex>() * x;
  h += system.D(static_cast<Eigen::Index>(row));
  const double tau_lp2 = system.tau_lp2[row];
  h *= std::exp(-jw * system.tau_d[row]) / (1.0 + jw * system.tau_lp[row]) /
       (1.0 + 2.0 * system.zeta_lp2[row] * tau_lp2 * jw - tau_lp2 * tau_lp2 * w * w);
  return h;
}

std::vector<LinearMode> Resonances(const LinearisedAxis& system) {
  Eigen::EigenSolver<Eigen::Matrix<double, kNumStates, kNumStates>> solver(system.A, false);
  std::vector<LinearMode> out;
  if (solver.info() != Eigen::Success) return out;
  for (int k = 0; k < kNumStates; ++k) {
    LinearMode mode;
    if (AsMode(solver.eigenvalues()[k], &mode)) out.push_back(mode);
  }
  Sort(&out);
  return out;
}

std::vector<LinearMode> AntiResonances(const LinearisedAxis& system, size_t row) {
  if (row >= system.channels.size()) throw std::out_of_range("AntiResonances: no such channel");
  const Eigen::Index r = static_cast<Eigen::Index>(row);
  std::vector<LinearMode> out;
  if (system.C.row(r).isZero(0.0) && system.D(r) == 0.0) return out;
  constexpr int n = kNumStates + 1;
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n), e = Eigen::MatrixXd::Zero(n, n);
  m.topLeftCorner(kNumStates, kNumStates) = system.A;
  m.topRightCorner(kNumStates, 1) = system.B;
  m.bottomLeftCorner(1, kNumStates) = system.C.row(r);
  m(kNumStates, kNumStates) = system.D(r);
  e.topLeftCorner(kNumStates, kNumStates).setIdentity();
  Eigen::GeneralizedEigenSolver<Eigen::MatrixXd> solver(m, e, false);
  if (solver.info() != Eigen::Success) return out;
  Eigen::EigenSolver<Eigen::Matrix<double, kNumStates, kNumStates>> poles(system.A, false);
  double fastest = 0.0;
  for (int j = 0; j < kNumStates; ++j) fastest = std::max(fastest, std::abs(poles.eigenvalues()[j]));
  for (int k = 0; k < n; ++k) {
    const std::complex<double> alpha = solver.alphas()[k];
    const double beta = solver.betas()[k];
    if (beta == 0.0) continue;
    const std::complex<double> s = alpha / beta;
    // Infinite zeros come out of QZ as huge finite ones.
    if (!(std::abs(s) <= kFarZero * fastest)) continue;
    LinearMode mode;
    if (!AsMode(s, &mode)) continue;
    bool cancelled = false;
    for (int j = 0; j < kNumStates; ++j) {
      cancelled |= std::abs(poles.eigenvalues()[j] - s) <= 1e-6 * std::abs(s);
    }
    if (!cancelled) out.push_back(mode);
  }
  Sort(&out);
  return out;
}

}  // namespace axis
