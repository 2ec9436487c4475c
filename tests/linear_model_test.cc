// Tests of sim/linear_model.h and the paper's Fig. 3 claims (MODEL.md §4, §8):
// the RK4 simulator in the linear `current_source` + `rigid` configuration
// agrees with the closed-form step response for T_p = 4.74 s and 0.195 s, and
// the fast case settles within 0.03 s with a current peak above 40 × 8.1 A.
//
// Input level: the paper's Fig. 3 step height is not legible in what survives.
// We use U0 = 10 V, the paper's standard step ("1 m/sec for 10 volts", Fig. 4).
// It is consistent with the current claim: the peak is ≈ 1031 A, i.e. 127 ×
// the 8.1 A limit (> 40 ×); a 40 × peak would need only U0 ≥ ≈ 3.2 V. (1031 A
// is also ≈ 40 × 25.8 A, so the paper's "40 times the rated peak current" may
// refer to a ≈ 25 A motor rating rather than to I_s = 8.1 A.)
#include <cmath>
#include <complex>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "sim/axis_model.h"
#include "sim/linear_model.h"
#include "sim/simulate.h"

namespace axis {
namespace {

constexpr double kU0 = 10.0;  // step height (V), see the file comment

// The linear system of MODEL.md §4 as AxisParams: no limits, F_s = 0, H = 0.
AxisParams<double> LinearParams(double T_p) {
  AxisParams<double> p;
  p.T_p = T_p;
  p.V_L = std::numeric_limits<double>::infinity();
  p.H = 0.0;
  p.F_s = 0.0;
  return p;
}

AxisStructure LinearStructure() {
  AxisStructure s;
  s.amplifier = Amplifier::kCurrentSource;
  s.coupling = Coupling::kRigid;
  return s;
}

Drive StepDrive(double height) {
  Drive d;
  d.input.kind = InputSignal::Kind::kStep;
  d.input.amplitude = height;
  return d;
}

// An independent closed form of the step response: the modal solution of the
// reduced (ω, y4, y5) system, whose matrix A_r is invertible, with
// θ(t) = ∫ω. For x_r' = A_r·x_r + b (b = B_r·U0), x_r(0) = 0:
//   x_r(t) = A_r⁻¹·(e^{A_r t} − I)·b,
//   ∫x_r  = A_r⁻²·(e^{A_r t} − I)·b − A_r⁻¹·b·t,
// with e^{A_r t} = V·diag(e^{λ_k t})·V⁻¹ from the eigendecomposition.
Eigen::Vector4d ModalStepResponse(const LinearAxis& sys, double U0,
                                  double t) {
  const Eigen::Matrix3d ar = sys.A.bottomRightCorner<3, 3>();
  const Eigen::Vector3d b = sys.B.tail<3>() * U0;
  Eigen::EigenSolver<Eigen::Matrix3d> es(ar);
  const Eigen::Matrix3cd v = es.eigenvectors();
  const Eigen::Vector3cd lambda = es.eigenvalues();
  Eigen::Vector3cd e;
  for (int k = 0; k < 3; ++k) e[k] = std::exp(lambda[k] * t);
  const Eigen::Matrix3cd vinv = v.inverse();
  const Eigen::Matrix3cd expm = v * e.asDiagonal() * vinv;
  const Eigen::Matrix3cd ar_inv = ar.cast<std::complex<double>>().inverse();
  const Eigen::Vector3cd bc = b.cast<std::complex<double>>();
  const Eigen::Matrix3cd eye = Eigen::Matrix3cd::Identity();
  const Eigen::Vector3cd xr = ar_inv * (expm - eye) * bc;
  const Eigen::Vector3cd ixr =
      ar_inv * ar_inv * (expm - eye) * bc - ar_inv * bc * t;
  return Eigen::Vector4d(ixr[0].real(), xr[0].real(), xr[1].real(),
                         xr[2].real());
}

TEST(MakeLinearAxisTest, MatrixEntriesAreTheEquationsOfModelSection4) {
  const AxisParams<double> p;
  const LinearAxis sys = MakeLinearAxis(p);
  const double J = 0.000847 + 0.00573 * 0.00573 * 146.0;
  const double B = 0.000733 + 0.00573 * 0.00573 * 200.0;
  const double pre = 1.0 / (0.04 * 0.000159);
  Eigen::Matrix4d a;
  a << 0, 1, 0, 0,                                            //
      0, -B / J, 0.289 * 3.0 / J, 0.289 * 3.0 * 0.00705 / J,  //
      0, 0, 0, 1,                                             //
      0, -870.0 * 0.0668 * pre, -pre, -(0.04 + 0.000159) * pre;
  // Entries reach 1e7; 1e-15 relative is a few roundings of the same terms.
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      EXPECT_NEAR(sys.A(r, c), a(r, c), 1e-15 * std::abs(a(r, c)))
          << "A(" << r << ", " << c << ")";
    }
  }
  EXPECT_EQ(sys.B(0), 0.0);
  EXPECT_EQ(sys.B(1), 0.0);
  EXPECT_EQ(sys.B(2), 0.0);
  // Same: a product and a quotient, 1e-15 relative.
  EXPECT_NEAR(sys.B(3), 1014.0 * pre, 1e-15 * 1014.0 * pre);
}

// MakeLinearAxis is the linearisation of the full model (sim/axis_model.h) in
// the current_source + rigid configuration with V_L = ∞: the two are written
// independently, so this checks both. Every parameter is moved off its
// default by its own factor so that a mixed-up or hard-coded parameter shows.
TEST(MakeLinearAxisTest, IsTheJacobianOfTheAxisModel) {
  AxisParams<double> p;
  int index = 0;
  VisitParams(
      [&index](const char*, const char*, double& value) {
        value *= 1.0 + 0.037 * (++index);
      },
      p);
  p.V_L = std::numeric_limits<double>::infinity();
  p.H = 0.0;
  p.F_s = 0.0;
  const LinearAxis sys = MakeLinearAxis(p);
  using J8 = ceres::Jet<double, 8>;  // 7 states and U
  AxisState<J8> y;
  for (int k = 0; k < kNumStates; ++k) y[k] = J8(0.0, k);
  AxisState<J8> dy;
  AxisDerivative(LinearStructure(), p.cast<J8>(), y, J8(0.0, 7), &dy);
  // Rows θ', ω', y4', y5' are dy[2..5]; columns θ and ω act through the
  // load states x = r_g·θ and v = r_g·ω (rigid coupling), y4 and y5 directly.
  const int row_of[4] = {2, 3, 4, 5};
  const int col_of[4] = {0, 1, 4, 5};
  const double col_scale[4] = {p.r_g, p.r_g, 1.0, 1.0};
  for (int r = 0; r < 4; ++r) {
    const double row_scale = sys.A.row(r).cwiseAbs().maxCoeff();
    for (int c = 0; c < 4; ++c) {
      // Same products and quotients in another order: 1e-13 of the row.
      EXPECT_NEAR(sys.A(r, c), col_scale[c] * dy[row_of[r]].v[col_of[c]],
                  1e-13 * row_scale)
          << "A(" << r << ", " << c << ")";
    }
    EXPECT_NEAR(sys.B(r), dy[row_of[r]].v[7], 1e-13 * std::abs(sys.B(r)))
        << "B(" << r << ")";
  }
}

TEST(MakeLinearAxisTest, RejectsNonPositiveInertiaMassOrTimeConstants) {
  for (int which = 0; which < 5; ++which) {
    AxisParams<double> p;
    if (which == 0) p.J_m = 0.0;
    if (which == 1) p.M = -1.0;
    if (which == 2) p.T_p = 0.0;
    if (which == 3) p.T_r = -1e-4;
    if (which == 4) p.T_p = std::numeric_limits<double>::quiet_NaN();
    try {
      MakeLinearAxis(p);
      ADD_FAILURE() << "no exception for case " << which;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind(
                    "expected positive J_m, M, T_p, T_r, got", 0),
                0u)
          << e.what();
    }
  }
}

TEST(LinearStepResponseTest, StartsAtRestAndMatchesTheModalSolution) {
  for (double T_p : {4.74, 0.195, 0.04}) {
    const LinearAxis sys = MakeLinearAxis(LinearParams(T_p));
    EXPECT_EQ(LinearStepResponse(sys, kU0, 0.0), Eigen::Vector4d::Zero());
    for (double t : {1e-4, 1e-3, 0.01, 0.05, 0.2, 0.8, 3.0}) {
      const Eigen::Vector4d x = LinearStepResponse(sys, kU0, t);
      const Eigen::Vector4d ref = ModalStepResponse(sys, kU0, t);
      const double scale = std::max(1.0, ref.cwiseAbs().maxCoeff());
      for (int k = 0; k < 4; ++k) {
        // Two independent double evaluations of the same function: the
        // balanced Padé exponential is within ≈ 3e-13·(t/s) of a 50-digit
        // reference (below); the modal form loses up to ≈ 3e-10 of the scale
        // on y5 (the eigenvector matrix and A_r⁻¹ are ill-conditioned,
        // |A_r| ≈ 1e7). 2e-9 of the state's scale leaves margin.
        EXPECT_NEAR(x[k], ref[k], 2e-9 * scale)
            << "T_p = " << T_p << ", t = " << t << ", state " << k;
      }
    }
  }
}

// Reference values from mpmath.expm at 50 significant digits applied to the
// augmented matrix built from the same double A and B (printed with 17
// digits), U0 = 10 V.
TEST(LinearStepResponseTest, MatchesFiftyDigitReference) {
  struct Case {
    double T_p, t;
    double x[4];
  };
  const Case cases[] = {
      {4.74, 0.8,
       {139.41980569946915, 174.97735520413955, 1.5151171012978348,
        -6.4351353519230922}},
      {0.195, 0.05,
       {8.6982203113424628, 174.4531296289298, 1.5204813226327658,
        0.21114369833061537}},
      {0.04, 0.05,
       {8.7022555008877575, 174.46090499394077, 1.5559061358683371,
        -13.421944563665483}},
      {0.04, 3.0,
       {523.33970359356015, 174.45335562368397, 1.4687845739833112, 0.0}},
  };
  for (const Case& c : cases) {
    const LinearAxis sys = MakeLinearAxis(LinearParams(c.T_p));
    const Eigen::Vector4d x = LinearStepResponse(sys, kU0, c.t);
    const double scale =
        Eigen::Vector4d(c.x[0], c.x[1], c.x[2], c.x[3]).cwiseAbs().maxCoeff();
    for (int k = 0; k < 4; ++k) {
      // Measured ≤ 1e-12 of the scale (the error grows ≈ 3e-13 per second of
      // t through the squarings); 5e-12 leaves margin across compilers.
      EXPECT_NEAR(x[k], c.x[k], 5e-12 * scale)
          << "T_p = " << c.T_p << ", t = " << c.t << ", state " << k;
    }
  }
}

TEST(LinearStepResponseTest, SatisfiesTheDifferentialEquation) {
  const LinearAxis sys = MakeLinearAxis(LinearParams(0.195));
  for (double t : {2e-3, 0.01, 0.05}) {
    const double dt = 1e-7;
    const Eigen::Vector4d dx = (LinearStepResponse(sys, kU0, t + dt) -
                                LinearStepResponse(sys, kU0, t - dt)) /
                               (2.0 * dt);
    const Eigen::Vector4d f =
        sys.A * LinearStepResponse(sys, kU0, t) + sys.B * kU0;
    for (int k = 0; k < 4; ++k) {
      // Central difference: truncation ≈ dt²·|x'''|/6 ≤ 1e-14·(6000)²·|x'|
      // ≈ 4e-7 relative; round-off of the two exponentials ≈ 1e-13·|x|/dt
      // ≤ 1e-2 (|y5| ≤ 1e4 V/s) against |f| ≥ 2.5e3; 1e-5 of the scale
      // covers both.
      const double scale = std::max(1.0, f.cwiseAbs().maxCoeff());
      EXPECT_NEAR(dx[k], f[k], 1e-5 * scale) << "t = " << t << ", state " << k;
    }
  }
}

TEST(SteadyStateGainTest, PaperGainOfOneMetrePerSecondForTenVolts) {
  const AxisParams<double> p;  // K_1 = 1014, K_2 = 870
  const double gain = SteadyStateGain(p);
  // Independent: ω_ss/U = −(A_r⁻¹·B_r)[ω] from the reduced linear system.
  const LinearAxis sys = MakeLinearAxis(p);
  const Eigen::Matrix3d ar = sys.A.bottomRightCorner<3, 3>();
  const double dc = -(ar.inverse() * sys.B.tail<3>())[0];
  // The same rational function evaluated two ways: 1e-12 relative.
  EXPECT_NEAR(gain, dc, 1e-12 * dc);
  // Paper / MODEL.md §3: 0.09995 m/s per volt; 0.5 % is the tolerance asked
  // for the paper's rounded "1 m/sec for 10 volts" (we get 0.099961).
  const double v_per_volt = gain * p.r_g;
  std::cout << "steady-state gain r_g*omega/U = " << v_per_volt
            << " m/s per V\n";
  EXPECT_NEAR(v_per_volt, 0.09995, 0.005 * 0.09995);
  // And the long-time limit of the closed form is that gain: at T_p = 0.04 s
  // the slowest non-zero pole is −154/s, so by t = 5 s the transient is gone;
  // the tolerance is the exponential's ≈ 3e-13/s drift times 5 s, with margin.
  const double omega_end = LinearStepResponse(sys, kU0, 5.0)[1];
  EXPECT_NEAR(omega_end, gain * kU0, 1e-11 * gain * kU0);
}

struct Fig3Result {
  double max_v_diff = 0.0;   // m/s
  double max_i_diff = 0.0;   // A
  double peak_current = 0.0; // A, simulated
  double settling = 0.0;     // s, 2 % band, from the simulation
};

// Runs the RK4 simulator (h = 10 µs, samples every 0.1 ms) and compares with
// the closed form at every sample.
Fig3Result RunFig3(double T_p, double duration) {
  const AxisParams<double> p = LinearParams(T_p);
  const LinearAxis sys = MakeLinearAxis(p);
  const Drive drive = StepDrive(kU0);
  SimulationOptions options;
  options.duration = duration;
  options.step = 1e-5;
  options.output_period = 1e-4;  // 10 kHz, finer than the 1 kHz asked
  options.channels = {Channel::kV, Channel::kI};
  const SimulationGrid grid = MakeGrid(options, drive);
  const Trace<double> trace =
      Simulate(LinearStructure(), p, AxisState<double>::Zero().eval(), drive,
               options, grid);
  EXPECT_TRUE(trace.finite);
  const double v_ss = SteadyStateGain(p) * p.r_g * kU0;
  Fig3Result r;
  for (size_t k = 0; k < trace.t.size(); ++k) {
    const Eigen::Vector4d x = LinearStepResponse(sys, kU0, trace.t[k]);
    const double v = p.r_g * x[1];
    const double i = p.K_i * (x[2] + p.T_z * x[3]);
    r.max_v_diff = std::max(r.max_v_diff, std::abs(v - trace[Channel::kV][k]));
    r.max_i_diff = std::max(r.max_i_diff, std::abs(i - trace[Channel::kI][k]));
    r.peak_current = std::max(r.peak_current, trace[Channel::kI][k]);
    if (std::abs(trace[Channel::kV][k] - v_ss) > 0.02 * v_ss) {
      r.settling = trace.t[k] + options.output_period;
    }
  }
  return r;
}

// Fig. 3 top: T_p = 4.74 s over 0–0.8 s.
TEST(Fig3Test, SlowPreampRk4MatchesClosedForm) {
  const Fig3Result r = RunFig3(4.74, 0.8);
  std::cout << "Fig. 3 T_p = 4.74 s: max |v_rk4 - v_exact| = " << r.max_v_diff
            << " m/s, max |i_rk4 - i_exact| = " << r.max_i_diff
            << " A, current peak = " << r.peak_current << " A\n";
  ::testing::Test::RecordProperty("fig3_slow_max_v_diff",
                                  std::to_string(r.max_v_diff));
  // The agreement asked for Fig. 3 (MODEL.md §8): 1e-6 m/s, 1 ppm of the
  // 1 m/s steady state; RK4 at |h·λ|max = 0.063 gives ≈ 1e-10 (measured).
  EXPECT_LT(r.max_v_diff, 1e-6);
}

// Fig. 3 bottom: T_p = 0.195 s over 0–0.1 s.
TEST(Fig3Test, FastPreampRk4MatchesClosedFormSettlesAndNeedsHugeCurrent) {
  const Fig3Result r = RunFig3(0.195, 0.1);
  std::cout << "Fig. 3 T_p = 0.195 s: max |v_rk4 - v_exact| = " << r.max_v_diff
            << " m/s, max |i_rk4 - i_exact| = " << r.max_i_diff
            << " A, 2 % settling time = " << r.settling
            << " s, current peak = " << r.peak_current << " A = "
            << r.peak_current / 8.1 << " x 8.1 A\n";
  ::testing::Test::RecordProperty("fig3_fast_max_v_diff",
                                  std::to_string(r.max_v_diff));
  ::testing::Test::RecordProperty("fig3_fast_settling_s",
                                  std::to_string(r.settling));
  ::testing::Test::RecordProperty("fig3_fast_peak_current_A",
                                  std::to_string(r.peak_current));
  // 1e-6 m/s as above (measured ≈ 2.4e-9).
  EXPECT_LT(r.max_v_diff, 1e-6);
  // Settling: the first t_s with |v(t) − v_ss| ≤ 2 % of v_ss for every later
  // sample (0.1 ms grid); the paper says "within about 0.03 s".
  EXPECT_LE(r.settling, 0.03);
  // "For all later t" beyond the simulated window: the closed form stays in
  // the band up to 2 s (checked every 1 ms).
  const AxisParams<double> p = LinearParams(0.195);
  const LinearAxis sys = MakeLinearAxis(p);
  const double v_ss = SteadyStateGain(p) * p.r_g * kU0;
  for (double t = 0.03; t <= 2.0; t += 1e-3) {
    const double v = p.r_g * LinearStepResponse(sys, kU0, t)[1];
    ASSERT_LE(std::abs(v - v_ss), 0.02 * v_ss) << "t = " << t;
  }
  // Current peak more than 40 × the 8.1 A limit (paper, MODEL.md §8).
  EXPECT_GT(r.peak_current, 40.0 * 8.1);
}

}  // namespace
}  // namespace axis
