// RK4 across switching surfaces (sim/switched_rk4.h): the saltation rule on a
// case with a closed form, and the Jacobian of a fit cost over a whole PRBS
// record (many backlash contacts) against central differences of the cost.
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "sim/experiment.h"
#include "sim/switched_rk4.h"
#include "tests/cost_checks.h"
#include "tests/test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;
using Jet1 = ceres::Jet<double, 1>;

// ẏ = a for y < c, ẏ = b for y ≥ c, y(0) = 0: the event is at τ = c/a and
// y(T) = c + b·(T − c/a), so ∂y(T)/∂a = b·c/a² exactly (a pathwise
// derivative gives τ = c/a instead: it misses the moving event).
struct TwoSlopes {
  Jet1 a, b;
  double c;
  template <typename S>
  S Slope(int mode) const {
    if constexpr (std::is_same<S, double>::value) {
      return mode == 0 ? a.a : b.a;
    } else {
      return mode == 0 ? a : b;
    }
  }
  template <typename S>
  void Derivative(double, const Eigen::Matrix<S, 1, 1>&, int mode,
                  Eigen::Matrix<S, 1, 1>* dy) const {
    (*dy)[0] = Slope<S>(mode);
  }
  void EventDerivative(double, const EventTimeState<1>&, int mode,
                       EventTimeState<1>* dy) const {
    (*dy)[0] = EventTimeJet(Slope<double>(mode));
  }
  bool StepOwnEventSensitivity(int, int) const { return step_own; }
  bool step_own = true;
  double GuardRate(const Eigen::Matrix<double, 1, 1>& dy, int from, int to) const {
    return to > from ? dy[0] : -dy[0];
  }
  static constexpr int kFamilies = 1;
  int Mode(const Eigen::Matrix<double, 1, 1>& y) const { return y[0] >= c ? 1 : 0; }
  int Toward(int from, int to, int) const {
    return to == from ? from : to > from ? from + 1 : from - 1;
  }
  template <typename S>
  S Guard(const Eigen::Matrix<S, 1, 1>& y, int from, int to) const {
    return to > from ? S(y[0] - c) : S(c - y[0]);
  }
};

TEST(SwitchedRk4Test, SaltationMatchesTheClosedForm) {
  // Both event-time rules: with constant slopes the step's own sensitivity
  // is the flow's saltation.
  for (const bool step_own : {false, true}) {
    TwoSlopes system{Jet1(2.0, 0), Jet1(5.0), 0.3, step_own};
    Eigen::Matrix<Jet1, 1, 1> y;
    y[0] = Jet1(0.0);
    int mode = 0;
    const double h = 0.0137;  // the event falls inside a step
    for (int n = 0; n < 36; ++n) mode = Rk4SwitchedStep(system, n * h, h, mode, &y);
    const double t_end = 36 * h;
    EXPECT_EQ(mode, 1);
    // Constant slopes: RK4 is exact on each piece, so only the event
    // location (1e-12·h) limits the agreement.
    EXPECT_NEAR(y[0].a, 0.3 + 5.0 * (t_end - 0.3 / 2.0), 1e-12);
    EXPECT_NEAR(y[0].v[0], 5.0 * 0.3 / 4.0, 1e-12) << "step_own " << step_own;
  }
}

// TwoSlopes with the event level c a differentiated parameter.
struct GuardedTwoSlopes : TwoSlopes {
  Jet1 c_jet;
  template <typename S>
  S Guard(const Eigen::Matrix<S, 1, 1>& y, int from, int to) const {
    if constexpr (std::is_same<S, double>::value) {
      return to > from ? y[0] - c : c - y[0];
    } else {
      return to > from ? S(y[0] - c_jet) : S(c_jet - y[0]);
    }
  }
};

TEST(SwitchedRk4Test, EventParameterInTheGuard) {
  // ∂y(T)/∂c with the guard's own parameter: y(T) = c + b·(T − c/a), so
  // ∂y/∂c = 1 − b/a.
  GuardedTwoSlopes system;
  system.a = Jet1(2.0);
  system.b = Jet1(5.0);
  system.c = 0.3;
  system.c_jet = Jet1(0.3, 0);
  Eigen::Matrix<Jet1, 1, 1> y;
  y[0] = Jet1(0.0);
  int mode = 0;
  const double h = 0.0137;
  for (int n = 0; n < 36; ++n) mode = Rk4SwitchedStep(system, n * h, h, mode, &y);
  EXPECT_NEAR(y[0].v[0], 1.0 - 5.0 / 2.0, 1e-12);
}

// Two independent switches, y0' = 1 → 3 at y0 = c0 and y1' = 2 → 7 at
// y1 = c1, both crossed inside one step in either order: the events are at
// τ0 = c0 and τ1 = c1/2, and the earlier must be taken first, else the
// other coordinate is integrated on its old slope past its own event.
// Mode = 2·(y0 ≥ c0) + (y1 ≥ c1).
struct TwoSwitches {
  double c0, c1;
  static constexpr int kFamilies = 2;
  template <typename S>
  void Derivative(double, const Eigen::Matrix<S, 2, 1>&, int mode,
                  Eigen::Matrix<S, 2, 1>* dy) const {
    (*dy)[0] = S(mode / 2 == 0 ? 1.0 : 3.0);
    (*dy)[1] = S(mode % 2 == 0 ? 2.0 : 7.0);
  }
  void EventDerivative(double t, const EventTimeState<2>& y, int mode,
                       EventTimeState<2>* dy) const {
    Derivative(t, y, mode, dy);
  }
  bool StepOwnEventSensitivity(int, int) const { return true; }
  double GuardRate(const Eigen::Vector2d& dy, int from, int to) const {
    const double rate = (from ^ to) == 2 ? dy[0] : dy[1];
    return to > from ? rate : -rate;
  }
  int Mode(const Eigen::Matrix<double, 2, 1>& y) const {
    return 2 * (y[0] >= c0 ? 1 : 0) + (y[1] >= c1 ? 1 : 0);
  }
  int Toward(int from, int to, int family) const {
    const int bit = family == 0 ? 2 : 1;
    return (from & bit) == (to & bit) ? from : (from ^ bit);
  }
  template <typename S>
  S Guard(const Eigen::Matrix<S, 2, 1>& y, int from, int to) const {
    const S g = (from ^ to) == 2 ? S(y[0] - c0) : S(y[1] - c1);
    return to > from ? g : S(-g);
  }
};

TEST(SwitchedRk4Test, TwoFamiliesSwitchingInOneStepTakeTheEarlierEventFirst) {
  const double h = 0.01;
  // Events at t = 0.0043 then 0.0061, and the reverse order.
  for (const auto& [c0, c1] : {std::pair{0.0043, 2 * 0.0061}, std::pair{0.0061, 2 * 0.0043}}) {
    TwoSwitches system{c0, c1};
    Eigen::Vector2d y = Eigen::Vector2d::Zero();
    int mode = 0;
    for (int n = 0; n < 3; ++n) mode = Rk4SwitchedStep(system, n * h, h, mode, &y);
    const double t_end = 3 * h;
    EXPECT_EQ(mode, 3);
    // Constant slopes on each piece: exact up to the event location.
    EXPECT_NEAR(y[0], c0 + 3.0 * (t_end - c0), 1e-12);
    EXPECT_NEAR(y[1], c1 + 7.0 * (t_end - c1 / 2.0), 1e-12);
  }
}

// The paper's five unknowns on a 1 s PRBS record (12 reversals, about 200
// backlash contacts), at a point 5 % off the truth: the Jet Jacobian of the
// whole cost against central differences of the cost itself, the
// gradient g = Jᵀr and each column of J. A step of 1e-7 in log parameters
// moves contact times by ~1e-8 s, far below the 10 µs step, so the
// differences see the event terms; their truncation and round-off
// (~1e-9 relative on a cost of ~1e6) bound the agreement at ~1e-5.
// `model_yaml`: job keys added to the job (the current-loop model and step).
void CheckPrbsCostJacobian(const std::string& model_yaml) {
  SimulateAxisOptions sim;
  sim.experiment_path = kRoot + "/configs/experiments/x_prbs.yaml";
  sim.out_path = axis::testing_files::TestTempDir() + "x_prbs.csv";
  sim.no_noise = true;
  SimulateAxis(sim);
  const std::string job_path = testing_files::WriteTemp("x_prbs_job.yaml",
      "model: " + kRoot + "/configs/axes/x_axis.yaml\n"
      "free:\n"
      "  V_L: {initial: 2.835, lower: 0.5, upper: 20}\n"
      "  B_a: {initial: 190, lower: 10, upper: 2000}\n"
      "  b_g: {initial: 1575, lower: 100, upper: 20000}\n"
      "  k_g: {initial: 4.75e6, lower: 5.0e5, upper: 5.0e7}\n"
      "  T_p: {initial: 0.042, lower: 0.005, upper: 1.0}\n"
      "experiments:\n"
      "  - name: prbs\n"
      "    data: " + sim.out_path + "\n"
      "    window: [0, 1.0]\n"
      "    channels: {u: u, a: a, tach: tach}\n"
      "    input: {column: u, interpolation: hold}\n"
      "    fit: {a: 0.02, tach: 0.005}\n" + model_yaml);
  const FitJob job = LoadFitJob(job_path);
  const std::vector<testing_files::ColumnCheck> checks =
      testing_files::CheckJobJacobian(job, 1e-7);
  for (int k = 0; k < 5; ++k) {
    const testing_files::ColumnCheck& c = checks[k];
    EXPECT_LT(c.error_norm / c.difference_norm, 1e-4) << job.problem.free[k].name;
    EXPECT_NEAR(c.gradient, c.difference_gradient, 1e-4 * std::abs(c.difference_gradient))
        << job.problem.free[k].name;
  }
}

// Under the full current loop the preamp limits are events too, with the
// step's own event-time rule (the flow's saltation alone left columns 0.3–
// 1.7 % off here).
TEST(SwitchedRk4Test, CostJacobianOverAPrbsRecordMatchesCentralDifferences) {
  CheckPrbsCostJacobian("");
}

// As above with the quasi-steady current loop at 50 µs (the discovery and
// coverage jobs' model): the preamp limits of eq. 2 are events too, each
// reversal crossing both, and their saltation terms (the guard carries V_L
// and T_z) must be in the Jacobian.
TEST(SwitchedRk4Test, QuasiSteadyCostJacobianOverAPrbsRecordMatchesCentralDifferences) {
  CheckPrbsCostJacobian("configuration: {current_loop: quasi_steady}\nsimulation: {step: 5.0e-5}\n");
}

}  // namespace
}  // namespace axis
