// Tests of the axes of issue 58 against closed forms: the voltage drive of
// MODEL.md §4 (a DC motor's first-order speed response to a voltage step),
// the pendulum load (its small-oscillation period with the drive off), the
// drive enable, the smart servo's firmware loop (FirmwareLaw's gains, and
// the angle at which its P loop holds the pendulum against gravity), the
// Stribeck shape exponent (autodiff against central differences), the
// units of a rotary axis, and the loaders' refusals.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <ceres/jet.h>
#include <unsupported/Eigen/MatrixFunctions>
#include <gtest/gtest.h>

#include "discovery/candidates.h"
#include "estimation/estimation_problem.h"
#include "io/yaml_util.h"
#include "sim/axis_config.h"
#include "sim/axis_config_yaml.h"
#include "sim/axis_model.h"
#include "sim/channels.h"
#include "sim/controller.h"
#include "sim/drive_config.h"
#include "sim/experiment_config.h"
#include "sim/preflight.h"
#include "sim/simulate.h"

namespace axis {
namespace {

constexpr double kTwoPi = 6.283185307179586476925;

// A rotary voltage-driven joint on one shaft (r_g = 1): the XL330's
// order of magnitude (configs/axes/xl330_pendulum.yaml), no friction.
AxisStructure RotaryStructure(LoadTerm load) {
  AxisStructure s;
  s.amplifier = Amplifier::kVoltageDrive;
  s.coupling = Coupling::kRigid;
  s.motion = Motion::kRotary;
  s.load = load;
  return s;
}

AxisParams<double> RotaryParams() {
  AxisParams<double> p;
  p.r_g = 1.0;
  p.J_m = 1.8e-3;
  p.B_m = 0.0;
  p.K_tau = 0.39;
  p.K_e = 0.39;
  p.R = 4.0;
  p.M = 2.0e-4;
  p.B_a = 3.0e-3;
  p.m_p = 0.49;
  p.l_p = 0.1;
  p.theta_p = 0.03;
  return p;
}

// The one shaft's inertia and viscous damping without a pendulum (r_g = 1,
// MODEL.md §4 rigid: J = J_m + r_g²·M, B = B_m + r_g²·B_a).
double ShaftInertia(const AxisParams<double>& p) { return p.J_m + p.M; }
double ShaftDamping(const AxisParams<double>& p) { return p.B_m + p.B_a; }

Trace<double> Simulated(const AxisStructure& s, const AxisParams<double>& p, const AxisState<double>& y0,
                        const Drive& drive, double duration, double step, double output_period,
                        std::vector<Channel> channels) {
  SimulationOptions o;
  o.duration = duration;
  o.step = step;
  o.output_period = output_period;
  o.channels = std::move(channels);
  const SimulationGrid grid = MakeGrid(o, drive);
  return Simulate(s, p, y0, drive, o, grid);
}

InputSignal Constant(double value) {
  InputSignal u;
  u.offset = value;
  return u;
}

// A DC motor on a voltage U: J·ω' = K_τ·(U − K_e·ω)/R − B·ω, so ω(t) =
// ω_ss·(1 − exp(−t/τ)) with ω_ss = K_τ·U/(K_τ·K_e + R·B), τ = J·R/(K_τ·K_e
// + R·B). RK4 at 0.1 ms against τ ≈ 49 ms: error O((h/τ)⁴), far below
// 1e-9 of ω_ss.
TEST(VoltageDriveTest, SpeedFollowsTheMotorsFirstOrderStepResponse) {
  const AxisStructure s = RotaryStructure(LoadTerm::kNone);
  const AxisParams<double> p = RotaryParams();
  Drive drive;
  drive.input = Constant(6.0);
  const Trace<double> trace = Simulated(s, p, AxisState<double>::Zero(), drive, 0.5, 1e-4, 1e-3,
                                  {Channel::kV, Channel::kI, Channel::kVm});
  const double J = ShaftInertia(p);
  const double B = ShaftDamping(p);
  const double k = p.K_tau * p.K_e + p.R * B;
  const double omega_ss = p.K_tau * 6.0 / k;
  const double tau = J * p.R / k;
  ASSERT_TRUE(trace.finite);
  for (size_t j = 0; j < trace.t.size(); j += 50) {
    const double t = trace.t[j];
    const double omega = omega_ss * (1.0 - std::exp(-t / tau));
    EXPECT_NEAR(trace[Channel::kV][j], omega, 1e-9 * omega_ss) << "t = " << t;
    EXPECT_NEAR(trace[Channel::kI][j], (6.0 - p.K_e * omega) / p.R, 1e-9 * 6.0 / p.R);
    EXPECT_DOUBLE_EQ(trace[Channel::kVm][j], 6.0);
  }
}

// The armature circuit of an inductive winding (MODEL.md §4, `inductance:
// true`) with K_e = 0: L·i' = U − R·i alone, so i(t) = U/R·(1 − e^{−Rt/L})
// whatever the shaft does. L/R = 0.5 ms at a 10 µs step: RK4's global error
// O((h·R/L)⁴/120) ≈ 1e-9 of U/R, so 1e-7 of it is far above it. From
// t_off = 2.455 ms the drive is off (enable 0, read at each step's start,
// so from the step at 2.46 ms): from the next sample on no current is read
// and no torque acts, so the shaft coasts, ω(t) = ω(t_1)·e^{−B(t − t_1)/J}
// from that sample t_1 = 2.5 ms (J/B = 0.67 s: RK4's error far below 1e-9
// of ω). The stability limit's eigenvalue is the winding's −R/L exactly
// (its row of the state Jacobian holds only the diagonal when K_e = 0) and
// its bound 2.785/|λ| (Rk4StabilityLimitOf, sim/preflight.h).
TEST(VoltageDriveTest, InductiveWindingsCurrentRisesWithItsTimeConstant) {
  AxisStructure s = RotaryStructure(LoadTerm::kNone);
  s.inductance = true;
  AxisParams<double> p = RotaryParams();
  p.K_e = 0.0;
  p.L = 2.0e-3;
  constexpr double kOff = 2.455e-3;
  constexpr double kFirstOff = 2.5e-3;  // the first sample after the switch
  Drive drive;
  drive.input = Constant(6.0);
  drive.has_enable = true;
  drive.enable.kind = InputSignal::Kind::kStep;
  drive.enable.offset = 1.0;
  drive.enable.start = kOff;
  drive.enable.amplitude = -1.0;
  const Trace<double> trace = Simulated(s, p, AxisState<double>::Zero(), drive, 5e-3, 1e-5, 1e-4,
                                        {Channel::kI, Channel::kV});
  ASSERT_TRUE(trace.finite);
  const double i_ss = 6.0 / p.R;
  const double J = ShaftInertia(p);
  const double B = ShaftDamping(p);
  double omega_off = 0.0;
  for (size_t j = 0; j < trace.t.size(); ++j) {
    const double t = trace.t[j];
    if (t < kOff) {
      EXPECT_NEAR(trace[Channel::kI][j], i_ss * (1.0 - std::exp(-p.R * t / p.L)), 1e-7 * i_ss)
          << "t = " << t;
      continue;
    }
    EXPECT_EQ(trace[Channel::kI][j], 0.0) << "t = " << t;
    if (omega_off == 0.0) omega_off = trace[Channel::kV][j];
    EXPECT_NEAR(trace[Channel::kV][j], omega_off * std::exp(-B * (t - kFirstOff) / J),
                1e-9 * omega_off)
        << "t = " << t;
  }
  ASSERT_GT(omega_off, 0.0);
  const Rk4StabilityLimit limit = Rk4StabilityLimitOf(s, p);
  EXPECT_NEAR(limit.eigenvalue.real(), -p.R / p.L, 1e-9 * p.R / p.L);
  EXPECT_NEAR(limit.max_step * p.R / p.L, 2.7853, 1e-3);
  // Without the inductance the current is at (U − K_e·ω)/R at once and the
  // winding sets no step limit.
  s.inductance = false;
  EXPECT_GT(Rk4StabilityLimitOf(s, p).max_step, 100.0 * p.L / p.R);
}

// The inductive DC motor of RotaryParams `p` under a constant U (V) as the
// linear system x' = A·x + b in x = (ω, i): A and the steady state x_ss.
struct LinearMotor {
  Eigen::Matrix2d a;
  Eigen::Vector2d x_ss;
};
LinearMotor InductiveMotor(const AxisParams<double>& p, double u) {
  LinearMotor m;
  m.a << -ShaftDamping(p) / ShaftInertia(p), p.K_tau / ShaftInertia(p), -p.K_e / p.L,
      -p.R / p.L;
  m.x_ss = -m.a.partialPivLu().solve(Eigen::Vector2d(0.0, u / p.L));
  return m;
}

// The rotary DC motor with an inductive winding (L/R = 12.5 ms) under a
// constant 6 V: its structure, parameters and drive.
struct InductiveSetup {
  AxisStructure s;
  AxisParams<double> p;
  Drive drive;
};
InductiveSetup InductiveMotorAt6V() {
  InductiveSetup m{RotaryStructure(LoadTerm::kNone), RotaryParams(), Drive()};
  m.s.inductance = true;
  m.p.L = 0.05;
  m.drive.input = Constant(6.0);
  return m;
}

// The inductive DC motor is linear in x = (ω, i): J·ω' = K_τ·i − B·ω,
// L·i' = U − R·i − K_e·ω, so x(t) = x_ss + e^{At}·(x(0) − x_ss), against
// Eigen's matrix exponential (unsupported/MatrixFunctions, Padé with
// scaling and squaring: an independent route). L/R = 12.5 ms beside a
// mechanical 49 ms: the current starts at 0 (the neglected form's at U/R)
// and settles at (U − K_e·ω_ss)/R, the neglected form's steady value. RK4
// at 0.1 ms: error O((h/τ)⁴) ≈ 1e-9 of the scales, so 1e-7 of ω_ss and of
// U/R.
TEST(VoltageDriveTest, InductiveMotorFollowsTheMatrixExponential) {
  auto [s, p, drive] = InductiveMotorAt6V();
  const Trace<double> trace = Simulated(s, p, AxisState<double>::Zero(), drive, 0.4, 1e-4, 1e-3,
                                        {Channel::kV, Channel::kI});
  ASSERT_TRUE(trace.finite);
  const auto [a, x_ss] = InductiveMotor(p, 6.0);
  EXPECT_NEAR(x_ss[1], (6.0 - p.K_e * x_ss[0]) / p.R, 1e-12);
  EXPECT_EQ(trace[Channel::kI][0], 0.0);
  for (size_t j = 0; j < trace.t.size(); ++j) {
    const Eigen::Matrix2d e = (a * trace.t[j]).exp();
    const Eigen::Vector2d x = x_ss - e * x_ss;
    EXPECT_NEAR(trace[Channel::kV][j], x[0], 1e-7 * x_ss[0]) << "t = " << trace.t[j];
    EXPECT_NEAR(trace[Channel::kI][j], x[1], 1e-7 * 6.0 / p.R) << "t = " << trace.t[j];
  }
}

// A record taken in motion (SimulationOptions::settled_current, MODEL.md
// §4): the winding current starts at (U − K_e·ω(0))/R and (ω, i) then
// follows x_ss + e^{At}·(x(0) − x_ss) as above (same step and tolerance);
// without the option it starts at 0, and with the drive off at 0 too.
TEST(VoltageDriveTest, ARecordInMotionStartsItsCurrentSettled) {
  auto [s, p, drive] = InductiveMotorAt6V();
  AxisState<double> y0 = AxisState<double>::Zero();
  y0[1] = y0[3] = 5.0;  // rad/s, r_g = 1
  SimulationOptions o;
  o.duration = 0.2;
  o.step = 1e-4;
  o.output_period = 1e-3;
  o.channels = {Channel::kV, Channel::kI};
  o.settled_current = true;
  const Trace<double> trace = Simulate(s, p, y0, drive, o, MakeGrid(o, drive));
  ASSERT_TRUE(trace.finite);
  const double i0 = (6.0 - p.K_e * 5.0) / p.R;
  EXPECT_NEAR(trace[Channel::kI][0], i0, 1e-12);
  const auto [a, x_ss] = InductiveMotor(p, 6.0);
  const Eigen::Vector2d x0(5.0, i0);
  for (size_t j = 0; j < trace.t.size(); ++j) {
    const Eigen::Vector2d x = x_ss + (a * trace.t[j]).exp() * (x0 - x_ss);
    EXPECT_NEAR(trace[Channel::kV][j], x[0], 1e-7 * x_ss[0]) << "t = " << trace.t[j];
    EXPECT_NEAR(trace[Channel::kI][j], x[1], 1e-7 * 6.0 / p.R) << "t = " << trace.t[j];
  }
  o.settled_current = false;
  EXPECT_EQ(Simulate(s, p, y0, drive, o, MakeGrid(o, drive))[Channel::kI][0], 0.0);
  o.settled_current = true;
  drive.has_enable = true;
  drive.enable = Constant(0.0);
  EXPECT_EQ(Simulate(s, p, y0, drive, o, MakeGrid(o, drive))[Channel::kI][0], 0.0);
}

// Drive off: a pendulum with no friction swings about x = −θ_p with period
// 2π·√(J/(m_p·g·l_p)), J = J_m + r_g²·(M + m_p·l_p²) (MODEL.md §4). From
// 0.01 rad the amplitude's correction to the period is A²/16 ≈ 6e-6; the
// zero crossings of the simulated swing (linear between 0.1 ms samples)
// give it within 1e-4 of the period.
TEST(PendulumTest, SwingsFreelyWithTheSmallOscillationPeriodWhenTheDriveIsOff) {
  const AxisStructure s = RotaryStructure(LoadTerm::kPendulum);
  AxisParams<double> p = RotaryParams();
  p.B_a = 0.0;
  Drive drive;
  drive.input = Constant(5.0);  // ignored: the drive is off
  drive.has_enable = true;
  drive.enable = Constant(0.0);
  AxisState<double> y0 = AxisState<double>::Zero();
  y0[0] = -p.theta_p + 0.01;
  y0[2] = y0[0];
  const Trace<double> trace = Simulated(s, p, y0, drive, 3.0, 1e-4, 1e-4, {Channel::kX, Channel::kI});
  ASSERT_TRUE(trace.finite);
  const double J = p.J_m + p.M + p.m_p * p.l_p * p.l_p;
  const double period = kTwoPi * std::sqrt(J / (p.m_p * kStandardGravity * p.l_p));
  std::vector<double> crossings;  // downward crossings of the rest angle
  const std::vector<double>& x = trace[Channel::kX];
  for (size_t j = 1; j < x.size(); ++j) {
    const double a = x[j - 1] + p.theta_p, b = x[j] + p.theta_p;
    if (a > 0.0 && b <= 0.0) crossings.push_back(trace.t[j - 1] + (trace.t[j] - trace.t[j - 1]) * a / (a - b));
    EXPECT_EQ(trace[Channel::kI][j], 0.0);
  }
  ASSERT_GE(crossings.size(), 3u);
  const double measured = (crossings.back() - crossings.front()) / (crossings.size() - 1);
  EXPECT_NEAR(measured, period, 1e-4 * period);
}

// The same pendulum with the drive on at U = 0: the shorted motor brakes it
// (K_τ·K_e/R of damping), so it loses amplitude the drive-off run keeps.
TEST(PendulumTest, TheDriveOnAtZeroVoltsBrakesWhatTheDriveOffLetsSwing) {
  const AxisStructure s = RotaryStructure(LoadTerm::kPendulum);
  AxisParams<double> p = RotaryParams();
  p.B_a = 0.0;
  AxisState<double> y0 = AxisState<double>::Zero();
  y0[0] = -p.theta_p + 0.2;
  y0[2] = y0[0];
  const auto amplitude_at_end = [&](bool on) {
    Drive drive;
    drive.input = Constant(0.0);
    drive.has_enable = true;
    drive.enable = Constant(on ? 1.0 : 0.0);
    const Trace<double> trace = Simulated(s, p, y0, drive, 2.0, 1e-4, 1e-3, {Channel::kX});
    double peak = 0.0;
    for (size_t j = trace.t.size() / 2; j < trace.t.size(); ++j) {
      peak = std::max(peak, std::abs(trace[Channel::kX][j] + p.theta_p));
    }
    return peak;
  };
  const double off = amplitude_at_end(false);
  const double on = amplitude_at_end(true);
  EXPECT_NEAR(off, 0.2, 0.01);  // energy kept (RK4's loss is far below this)
  // Damped by c = K_τ·K_e/R: from rest at 0.2 rad the swing stays inside
  // 0.2·√(1 + (σ/ω_d)²)·exp(−σ·t), σ = c/(2J) (the linearised oscillator;
  // σ/ω_d ≈ 0.33 here, the factor below 1.06, taken as 1.1), so after 1 s
  // below 0.22·exp(−σ·1 s), a fifteenth of the undamped 0.2.
  const double J = p.J_m + p.M + p.m_p * p.l_p * p.l_p;
  const double c = p.K_tau * p.K_e / p.R;
  const double sigma = c / (2.0 * J);  // 1/s
  EXPECT_LT(on, 0.2 * 1.1 * std::exp(-sigma * 1.0));
}

// FirmwareLaw: the firmware's gains in duty per rad (sim/controller.h).
TEST(ServoFirmwareTest, GainsAreTheFirmwaresInDutyPerRadian) {
  ServoFirmware f;
  f.kp = 800.0;
  f.ki = 100.0;
  f.kd = 40.0;
  f.kp_divisor = 256.0;
  f.pwm_full_scale = 885.0;
  f.pwm_limit = 442.5;
  f.counts_per_rev = 4096.0;
  const ControllerConfig c = FirmwareLaw(f, 0.002, 1);
  const double counts_per_rad = 4096.0 / kTwoPi;
  EXPECT_DOUBLE_EQ(c.G_p, 800.0 / 256.0 * counts_per_rad / 885.0);
  EXPECT_DOUBLE_EQ(c.G_i, 100.0 / 65536.0 * counts_per_rad / 885.0 / 0.002);
  EXPECT_DOUBLE_EQ(c.G_v, 40.0 / 16.0 * counts_per_rad / 885.0 * 0.002);
  EXPECT_DOUBLE_EQ(c.U_max, 0.5);
  EXPECT_EQ(c.G_ff, 0.0);
  EXPECT_EQ(c.delay_samples, 1);
  EXPECT_DOUBLE_EQ(c.load_quantum, kTwoPi / 4096.0);
  f.quantized = false;
  EXPECT_EQ(FirmwareLaw(f, 0.002, 0).load_quantum, 0.0);
}

// The firmware's P loop holding the pendulum at a goal of 0.5 rad: at rest
// the motor's torque K_τ·V_in·G_p·e/R balances m_p·g·l_p·sin(x + θ_p) with
// e = 0.5 − x. The equation is solved by bisection; the simulation settles
// there (friction-free but damped by B_a and the back-EMF) within 1e-6 rad.
TEST(ServoFirmwareTest, ThePLoopHoldsThePendulumWhereMotorTorqueBalancesGravity) {
  const AxisStructure s = RotaryStructure(LoadTerm::kPendulum);
  const AxisParams<double> p = RotaryParams();
  ServoFirmware f;
  f.kp = 400.0;
  f.kp_divisor = 256.0;
  f.quantized = false;
  const double supply = 7.4;
  Drive drive;
  drive.closed_loop = true;
  drive.controller = FirmwareLaw(f, 0.001, 0);
  drive.reference.kind = Reference::Kind::kTable;
  drive.reference.table = Constant(0.5);
  drive.has_supply = true;
  drive.supply = Constant(supply);
  AxisState<double> y0 = AxisState<double>::Zero();
  y0[0] = y0[2] = -p.theta_p;
  const Trace<double> trace = Simulated(s, p, y0, drive, 6.0, 1e-4, 1e-3, {Channel::kX, Channel::kU});
  ASSERT_TRUE(trace.finite);
  const double gain = p.K_tau * supply * drive.controller.G_p / p.R;  // N·m/rad
  const double weight = p.m_p * kStandardGravity * p.l_p;
  double lo = -p.theta_p, hi = 0.5;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (gain * (0.5 - mid) > weight * std::sin(mid + p.theta_p) ? lo : hi) = mid;
  }
  EXPECT_NEAR(trace[Channel::kX].back(), lo, 1e-6);
  // u is the voltage on the motor: duty·V_in, the duty G_p·e.
  EXPECT_NEAR(trace[Channel::kU].back(), supply * drive.controller.G_p * (0.5 - lo), 1e-5);
}

// The Stribeck shape exp(−|v/v_st|^δ): δ = 2 is the Gaussian, δ = 1 the
// exponential; its derivative in δ by ceres::Jet matches a central
// difference (h = 1e-6: truncation O(h²) ≈ 1e-12, rounding ≈ 1e-10).
TEST(StribeckShapeTest, ExponentShapesTheDecayAndDifferentiates) {
  AxisStructure s;
  s.effects.stribeck = true;
  AxisParams<double> p;
  p.v_st = 0.02;
  const double v = 0.013;
  const auto shape = [&](double delta) {
    AxisParams<double> q = p;
    q.delta_st = delta;
    return internal::StribeckShape(q, MakeAxisCoefficients(s, q), v);
  };
  EXPECT_DOUBLE_EQ(shape(2.0), std::exp(-(v / p.v_st) * (v / p.v_st)));
  EXPECT_NEAR(shape(1.0), std::exp(-v / p.v_st), 1e-15);
  using J1 = ceres::Jet<double, 1>;
  AxisParams<J1> pj = p.cast<J1>();
  pj.delta_st = J1(1.5, 0);
  const J1 j = internal::StribeckShape(pj, MakeAxisCoefficients(s, pj), J1(v));
  const double h = 1e-6;
  EXPECT_NEAR(j.a, shape(1.5), 1e-15);
  EXPECT_NEAR(j.v[0], (shape(1.5 + h) - shape(1.5 - h)) / (2.0 * h), 1e-9);
  // At rest the shape is 1 with a zero (not NaN) derivative.
  const J1 rest = internal::StribeckShape(pj, MakeAxisCoefficients(s, pj), J1(0.0));
  EXPECT_EQ(rest.a, 1.0);
  EXPECT_EQ(rest.v[0], 0.0);
}

TEST(RotaryUnitsTest, TheLoadsQuantitiesTurnIntoAnglesTorquesAndInertias) {
  EXPECT_EQ(RotaryLoadUnit("N*s/m"), "N*m*s/rad");
  EXPECT_EQ(RotaryLoadUnit("m/s^2"), "rad/s^2");
  EXPECT_EQ(RotaryLoadUnit("N*s^2/m^2"), "N*m*s^2/rad^2");
  EXPECT_EQ(RotaryLoadUnit("kg"), "kg*m^2");
  EXPECT_EQ(ChannelUnit(Channel::kX, true), "rad");
  EXPECT_EQ(ChannelUnit(Channel::kForce, true), "N*m");
  EXPECT_EQ(ChannelUnit(Channel::kI, true), "A");
  EXPECT_EQ(ChannelUnit(Channel::kX, false), "m");
  EXPECT_EQ(ParamUnit("M", Motion::kRotary), "kg*m^2");
  EXPECT_EQ(ParamUnit("B_a", Motion::kRotary), "N*m*s/rad");
  EXPECT_EQ(ParamUnit("F_c", Motion::kRotary), "N*m");
  EXPECT_EQ(ParamUnit("v_eps", Motion::kRotary), "rad/s");
  EXPECT_EQ(ParamUnit("r_g", Motion::kRotary), "rad/rad");
  EXPECT_EQ(ParamUnit("b.x", Motion::kRotary), "rad");
  // The motor's, the drive's and the pendulum's do not change.
  EXPECT_EQ(ParamUnit("J_m", Motion::kRotary), "kg*m^2");
  EXPECT_EQ(ParamUnit("K_tau", Motion::kRotary), "N*m/A");
  EXPECT_EQ(ParamUnit("l_p", Motion::kRotary), "m");
  EXPECT_EQ(ParamUnit("B_a", Motion::kLinear), "N*s/m");
}

// load_friction (MODEL.md §7): μ_d·|F| where the motor drives the load
// (F·v > 0), μ_b·|F| where the load drives the motor, opposing the motion,
// F = K_τ·i/r_g; at v ≫ v_ε, sgn_ε(v) = ±1 to 1e-15.
TEST(LoadFrictionTest, EachDirectionHasItsCoefficient) {
  AxisStructure s = RotaryStructure(LoadTerm::kNone);
  s.effects.load_friction = true;
  AxisParams<double> p = RotaryParams();
  p.mu_d = 0.2;
  p.mu_b = 0.05;
  p.v_eps = 1e-3;
  const AxisCoefficients<double> c = MakeAxisCoefficients(s, p);
  const double i = 0.8, force = p.K_tau * i / p.r_g;
  EXPECT_NEAR(internal::LoadDependentFriction(p, c, 0.1, i), 0.2 * force, 1e-15);
  EXPECT_NEAR(internal::LoadDependentFriction(p, c, -0.1, i), -0.05 * force, 1e-15);
  EXPECT_NEAR(internal::LoadDependentFriction(p, c, -0.1, -i), -0.2 * force, 1e-15);
  EXPECT_NEAR(internal::LoadDependentFriction(p, c, 0.1, -i), 0.05 * force, 1e-15);
  EXPECT_EQ(internal::LoadDependentFriction(p, c, 0.1, 0.0), 0.0);
  // In the derivative: the load's acceleration loses exactly that force
  // over the inertia (rigid, voltage drive: i = (U − K_e·ω)/R).
  AxisState<double> y = AxisState<double>::Zero();
  y[1] = y[3] = 0.1;
  AxisState<double> on, off;
  AxisDerivative(s, p, y, 5.0, &on);
  AxisStructure without = s;
  without.effects.load_friction = false;
  AxisDerivative(without, p, y, 5.0, &off);
  const double i_now = (5.0 - p.K_e * 0.1) / p.R;
  const double J = ShaftInertia(p);
  EXPECT_NEAR(on[1] - off[1], -0.2 * p.K_tau * i_now / J, 1e-12);
}

// A rotary load that turns more than a revolution in its records is offered
// no spring (discovery/candidates.cc); one that swings within it is.
TEST(RotaryCandidatesTest, NoSpringOnAShaftThatTurns) {
  EstimationProblem job;
  job.model.structure = RotaryStructure(LoadTerm::kNone);
  FitExperiment e;
  e.measured_channels = {Channel::kX};
  e.measured = {{0.0, 2.0, 7.0}};
  job.experiments = {e};
  const auto has = [](const std::vector<Candidate>& list, const std::string& name) {
    for (const Candidate& c : list) {
      if (c.name == name) return true;
    }
    return false;
  };
  EXPECT_FALSE(has(ListCandidates(job, {}), "spring"));
  EXPECT_TRUE(has(ListCandidates(job, {}), "load_friction"));
  job.experiments[0].measured = {{-0.5, 0.0, 1.0}};
  EXPECT_TRUE(has(ListCandidates(job, {}), "spring"));
  job.model.structure.motion = Motion::kLinear;
  job.experiments[0].measured = {{0.0, 2.0, 7.0}};
  EXPECT_TRUE(has(ListCandidates(job, {}), "spring"));
}

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// The message ParseAxisConfig throws for `text`, "" if it loads.
std::string ConfigError(const std::string& text) {
  return ErrorOf([&] { ParseAxisConfig(YAML::Load(text), "t.yaml"); });
}

const char* kPendulumConfig =
    "name: t\nmotion: rotary\namplifier: voltage_drive\ncoupling: rigid\nload: pendulum\n"
    "parameters: {r_g: 1, J_m: 0.002, B_m: 0, K_tau: 0.4, K_e: 0.4, R: 4, M: 1.0e-6, B_a: 0.003, "
    "m_p: 0.5, l_p: 0.1}\n";

TEST(RotaryConfigTest, APendulumNeedsARotaryAxisAndItsMassAndLength) {
  const AxisConfig ok = ParseAxisConfig(YAML::Load(kPendulumConfig), "t.yaml");
  EXPECT_EQ(ok.structure.motion, Motion::kRotary);
  EXPECT_EQ(ok.structure.load, LoadTerm::kPendulum);
  EXPECT_EQ(ok.structure.amplifier, Amplifier::kVoltageDrive);
  std::string linear = kPendulumConfig;
  linear.replace(linear.find("rotary"), 6, "linear");
  EXPECT_NE(ConfigError(linear)
                .find("key 'load': expected motion: rotary with a pendulum"),
            std::string::npos);
  std::string no_length = kPendulumConfig;
  no_length.replace(no_length.find(", l_p: 0.1"), 10, "");
  EXPECT_NE(ConfigError(no_length)
                .find("parameters.l_p': expected a value"),
            std::string::npos);
  std::string no_resistance = kPendulumConfig;
  no_resistance.replace(no_resistance.find("R: 4"), 4, "R: 0");
  EXPECT_NE(ConfigError(no_resistance)
                .find("parameter 'R': expected a winding resistance > 0"),
            std::string::npos);
}

// `inductance: true` makes L a parameter the config must give, survives
// the round trip, and is refused beside any amplifier but the voltage drive.
TEST(RotaryConfigTest, AnInductiveWindingNeedsItsInductanceAndAVoltageDrive) {
  const std::string inductive = std::string(kPendulumConfig) + "inductance: true\n";
  EXPECT_NE(ConfigError(inductive).find("parameters.L': expected a value"), std::string::npos);
  std::string with_l = inductive;
  with_l.replace(with_l.find("R: 4"), 4, "R: 4, L: 0.002");
  const AxisConfig c = ParseAxisConfig(YAML::Load(with_l), "t.yaml");
  EXPECT_TRUE(c.structure.inductance);
  EXPECT_EQ(c.params.L, 0.002);
  EXPECT_FALSE(ParseAxisConfig(YAML::Load(kPendulumConfig), "t.yaml").structure.inductance);
  const AxisConfig back = ParseAxisConfig(YAML::Load(AxisConfigToYaml(c)), "back.yaml");
  EXPECT_TRUE(back.structure.inductance);
  EXPECT_EQ(back.params.L, 0.002);
  // Switched on by a job's `configuration:`, the inductance needs its
  // value there: the model config was not asked for L.
  AxisConfig off = ParseAxisConfig(YAML::Load(kPendulumConfig), "t.yaml");
  YamlMap bare(YAML::Load("{configuration: {inductance: true}}"), "j.yaml", "");
  EXPECT_NE(ErrorOf([&] { ParseModelOverrides(bare, &off); })
                .find("key 'configuration.inductance': expected set: {L:"),
            std::string::npos);
  YamlMap given(YAML::Load("{configuration: {inductance: true}, set: {L: 0.003}}"), "j.yaml", "");
  ParseModelOverrides(given, &off);
  EXPECT_TRUE(off.structure.inductance);
  EXPECT_EQ(off.params.L, 0.003);
  AxisConfig source = c;
  YamlMap root(YAML::Load("{configuration: {amplifier: force_source}}"), "j.yaml", "");
  EXPECT_NE(ErrorOf([&] { ParseModelOverrides(root, &source); })
                .find("key 'inductance': expected false with an amplifier other than "
                      "voltage_drive"),
            std::string::npos);
}

TEST(RotaryConfigTest, TheFirmwareLoopsKeysAreItsOwn) {
  const std::string with_firmware =
      std::string(kPendulumConfig) +
      "controller: {type: servo_firmware, kp: 100, kp_divisor: 256, quantized: false}\n";
  const AxisConfig c = ParseAxisConfig(YAML::Load(with_firmware), "t.yaml");
  ASSERT_TRUE(c.has_controller);
  EXPECT_TRUE(c.controller.firmware.enabled);
  EXPECT_DOUBLE_EQ(c.controller.G_p, 100.0 / 256.0 * 4096.0 / kTwoPi / 885.0);
  // An experiment's override keeps the type and changes the gain.
  YamlMap override_map(YAML::Load("{kp: 800}"), "e.yaml", "controller.");
  const ControllerConfig e = ParseController(override_map, c.controller);
  EXPECT_DOUBLE_EQ(e.G_p, 8.0 * c.controller.G_p);
  const std::string mixed = std::string(kPendulumConfig) +
                            "controller: {type: servo_firmware, kp: 100, G_p: 3}\n";
  EXPECT_NE(ConfigError(mixed)
                .find("controller.G_p': expected the firmware's keys"),
            std::string::npos);
}

// model_discovered.yaml and the Python bindings write a model back: the
// rotary motion, the pendulum, the voltage drive and the firmware loop
// (its own keys, so that an experiment's {kp: ...} still re-derives it)
// survive the round trip.
TEST(RotaryConfigTest, AModelWrittenBackLoadsAsTheSameAxis) {
  const std::string text =
      std::string(kPendulumConfig) +
      "controller: {type: servo_firmware, kp: 100, kp_divisor: 256, pwm_limit: 500, "
      "quantized: false, T_s: 0.002}\n";
  const AxisConfig a = ParseAxisConfig(YAML::Load(text), "t.yaml");
  const AxisConfig b = ParseAxisConfig(YAML::Load(AxisConfigToYaml(a)), "back.yaml");
  EXPECT_EQ(b.structure.motion, Motion::kRotary);
  EXPECT_EQ(b.structure.load, LoadTerm::kPendulum);
  EXPECT_EQ(b.structure.amplifier, Amplifier::kVoltageDrive);
  EXPECT_EQ(b.params.m_p, a.params.m_p);
  EXPECT_EQ(b.params.l_p, a.params.l_p);
  ASSERT_TRUE(b.controller.firmware.enabled);
  EXPECT_EQ(b.controller.G_p, a.controller.G_p);
  EXPECT_EQ(b.controller.U_max, 500.0 / 885.0);
  EXPECT_EQ(b.controller.T_s, 0.002);
  // An override keeps the model's PWM limit.
  YamlMap override_map(YAML::Load("{kp: 800}"), "e.yaml", "controller.");
  EXPECT_EQ(ParseController(override_map, b.controller).U_max, 500.0 / 885.0);
}

// An experiment or job may turn a linear model's load into a rotary
// joint's pendulum with `configuration:` (ParseModelOverrides).
TEST(RotaryConfigTest, ConfigurationOverridesMotionAndLoad) {
  AxisConfig c = ParseAxisConfig(YAML::Load(kPendulumConfig), "t.yaml");
  c.structure.motion = Motion::kLinear;
  c.structure.load = LoadTerm::kNone;
  YamlMap root(YAML::Load("{configuration: {motion: rotary, load: pendulum}}"), "j.yaml", "");
  ParseModelOverrides(root, &c);
  EXPECT_EQ(c.structure.motion, Motion::kRotary);
  EXPECT_EQ(c.structure.load, LoadTerm::kPendulum);
}

// A firmware loop's duty cycle needs a supply to become volts, a voltage
// drive to apply them and a rotary shaft for its counts; a supply needs
// such a loop. Each refused naming the key, before anything runs.
TEST(RotaryConfigTest, TheFirmwareLoopNeedsItsSupplyAndDrive) {
  const std::string model = ::testing::TempDir() + "firmware_model.yaml";
  {
    std::ofstream out(model);
    out << kPendulumConfig
        << "controller: {type: servo_firmware, kp: 100, kp_divisor: 256, quantized: false}\n";
  }
  // A trapezoid move on that model with `extra` keys: the loader's message.
  const auto experiment_error = [&](const std::string& extra) {
    return ErrorOf([&] {
      ParseExperiment(YAML::Load("model: " + model +
                                 "\nduration: 0.1\nstep: 1.0e-3\nchannels: [x]\n"
                                 "reference: {type: trapezoid, distance: 0.5, velocity: 1, "
                                 "acceleration: 5}\n" + extra),
                      "e.yaml", ::testing::TempDir());
    });
  };
  EXPECT_NE(experiment_error("").find("key 'supply': expected the drive's supply voltage"),
            std::string::npos);
  EXPECT_EQ(experiment_error("supply: 7.4\n"), "");
  EXPECT_NE(experiment_error("supply: 7.4\ncontroller: {type: sampled_position}\n")
                .find("key 'supply': expected a supply only with controller type: servo_firmware"),
            std::string::npos);
  // A supply that reaches 0 V, as a signal or as a recorded column.
  EXPECT_NE(experiment_error("supply: {type: sine, offset: 1, amplitude: 2, frequency: 1}\n")
                .find("key 'supply': expected a supply voltage > 0 V throughout, got a least "
                      "value of -1 V"),
            std::string::npos);
  const std::string csv = ::testing::TempDir() + "supply.csv";
  std::ofstream(csv) << "t,vin\n0,7.4\n0.05,0\n0.1,7.3\n";
  EXPECT_NE(experiment_error("supply: {type: column, file: " + csv +
                             ", time: t, column: vin}\n")
                .find("key 'supply': expected a supply voltage > 0 V throughout, got 0 V at "
                      "t = 0.05 s"),
            std::string::npos);
  EXPECT_EQ(experiment_error("supply: {type: sine, offset: 7, amplitude: 0.5, frequency: 1}\n"),
            "");
}

}  // namespace
}  // namespace axis
