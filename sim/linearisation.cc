#include "sim/linearisation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "sim/dense_decompositions.h"
#include "sim/simulate.h"

namespace axis {
namespace {

constexpr double kTwoPi = 6.28318530717958647692;
// C·A^k·B below this fraction of |C·A^k|·|B| counts as zero (the relative
// degree's test; the structural zeros are exact).
constexpr double kMarkov = 1e-12;
using Jet = ceres::Jet<double, kNumStates + 1>;  // 7 states and the input

void Sort(std::vector<LinearMode>* modes) {
  std::sort(modes->begin(), modes->end(),
            [](const LinearMode& a, const LinearMode& b) { return a.frequency < b.frequency; });
}

// The root as a mode if it is a lightly damped one with Im s > 0.
// A zero within this fraction of the largest pole's magnitude is at the
// origin (round-off of a zero at s = 0).
constexpr double kOriginCluster = 1e-6;

bool AsMode(std::complex<double> s, LinearMode* mode) {
  const double w = std::abs(s);
  if (!(s.imag() > 0.0) || !std::isfinite(w) || w == 0.0) return false;
  mode->root = s;
  mode->frequency = w / kTwoPi;
  mode->damping = -s.real() / w;
  return std::abs(mode->damping) < kLightDamping;
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
  bool solved = false;
  const StateEigenvalueVector poles = StateEigenvalues(system.A, &solved);
  std::vector<LinearMode> out;
  if (!solved) return out;
  for (int k = 0; k < kNumStates; ++k) {
    LinearMode mode;
    if (AsMode(poles[k], &mode)) out.push_back(mode);
  }
  Sort(&out);
  return out;
}

std::vector<LinearMode> AntiResonances(const LinearisedAxis& system, size_t row) {
  if (row >= system.channels.size()) throw std::out_of_range("AntiResonances: no such channel");
  using Matrix = Eigen::Matrix<double, kNumStates, kNumStates>;
  const Eigen::Matrix<double, 1, kNumStates> c = system.C.row(static_cast<Eigen::Index>(row));
  const double d = system.D(static_cast<Eigen::Index>(row));
  std::vector<LinearMode> out;
  // The zero dynamics: the feedback u = −(C·A^(r−1)·B)⁻¹·C·A^r·x that
  // holds y ≡ 0, on the subspace where C·A^k·x = 0 for k < r (invariant
  // under it; its r other eigenvalues are 0, and numerically a cluster
  // about 0 that would pass for slow zeros).
  Eigen::MatrixXd zero_dynamics;
  if (d != 0.0) {
    zero_dynamics = system.A - system.B * c / d;
  } else {
    Eigen::MatrixXd rows(0, kNumStates);
    Eigen::Matrix<double, 1, kNumStates> w = c;  // C·A^k
    int k = 0;
    for (; k < kNumStates; ++k) {
      const double g = w.dot(system.B);
      if (g != 0.0 && std::abs(g) > kMarkov * w.norm() * system.B.norm()) break;
      rows.conservativeResize(k + 1, kNumStates);
      rows.row(k) = w / w.norm();
      w = w * system.A;
    }
    if (k == kNumStates) return out;  // the channel's response is identically 0
    const Matrix closed = system.A - system.B * (w * system.A) / w.dot(system.B);
    rows.conservativeResize(k + 1, kNumStates);  // C·A^k for k < r = k + 1
    rows.row(k) = w / w.norm();
    const Eigen::MatrixXd null = SvdOf(rows, false, true).v.rightCols(kNumStates - rows.rows());
    zero_dynamics = null.transpose() * closed * null;
  }
  Eigen::EigenSolver<Eigen::MatrixXd> zeros(zero_dynamics, false);
  bool solved = false;
  const StateEigenvalueVector poles = StateEigenvalues(system.A, &solved);
  if (zeros.info() != Eigen::Success || !solved) return out;
  // Zeros at the origin (a differentiating channel, e.g. the acceleration
  // of a position state) come out as a round-off cluster about 0 that would
  // pass for a slow, undamped pair: numerically 0 against the poles' scale.
  double scale = 0.0;
  for (int j = 0; j < kNumStates; ++j) scale = std::max(scale, std::abs(poles[j]));
  for (Eigen::Index k = 0; k < zeros.eigenvalues().size(); ++k) {
    const std::complex<double> s = zeros.eigenvalues()[k];
    LinearMode mode;
    if (std::abs(s) <= kOriginCluster * scale || !AsMode(s, &mode)) continue;
    bool cancelled = false;
    for (int j = 0; j < kNumStates; ++j) {
      cancelled |= std::abs(poles[j] - s) <= 1e-6 * std::abs(s);
    }
    if (!cancelled) out.push_back(mode);
  }
  Sort(&out);
  return out;
}

}  // namespace axis
