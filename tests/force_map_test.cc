// The force map of MODEL.md §7 (issue 15): the natural cubic spline
// (sim/force_map.h) against the conditions that define it, its term in the
// model differentiated by Jets against finite differences, the config
// format, and the fit's roughness penalty (discovery/force_map.h).
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "estimation/experiment_cost.h"
#include "estimation/roughness_cost.h"
#include "run/fit_job.h"
#include "sim/axis_model.h"
#include "sim/config.h"
#include "sim/force_map.h"
#include "sim/preflight.h"
#include "io/yaml_util.h"

namespace axis {
namespace {

using Values = std::array<double, kMaxForceMapKnots>;

double Spline(const std::vector<double>& knots, const Values& values, double z) {
  Values m{};
  ForceMapSecondDerivatives(knots, values, &m);
  return ForceMapValue(knots, values, m, z);
}

// Non-uniform knots and values with curvature.
const std::vector<double> kKnots = {-0.3, -0.2, -0.05, 0.0, 0.12, 0.3, 0.31, 0.5};
Values SomeValues() {
  Values v{};
  const double f[] = {3.0, -1.0, 4.0, 1.5, -5.0, 9.0, 2.0, -6.0};
  for (int k = 0; k < 8; ++k) v[k] = f[k];
  return v;
}

TEST(ForceMapSplineTest, InterpolatesAndIsANaturalCubicSpline) {
  const Values v = SomeValues();
  const int n = static_cast<int>(kKnots.size());
  for (int k = 0; k < n; ++k) EXPECT_NEAR(Spline(kKnots, v, kKnots[k]), v[k], 1e-12) << k;
  // The spline is one cubic per interval: the cubic through four points
  // inside an interval gives its value and derivatives at the interval's
  // ends exactly (up to rounding). Left and right of every inner knot they
  // must agree up to f'' (C²), and f'' must vanish at both ends.
  const auto cubic_at = [&](double t, double direction, double delta) {
    Eigen::Matrix4d a;
    Eigen::Vector4d f;
    for (int i = 0; i < 4; ++i) {
      const double s = direction * delta * (i + 1);
      a.row(i) << 1.0, s, s * s, s * s * s;
      f[i] = Spline(kKnots, v, t + s);
    }
    const Eigen::Vector4d c = a.colPivHouseholderQr().solve(f);
    return Eigen::Vector3d(c[0], c[1], 2.0 * c[2]);  // f, f', f'' at t
  };
  for (int k = 1; k + 1 < n; ++k) {
    const double delta = 0.2 * std::min(kKnots[k] - kKnots[k - 1], kKnots[k + 1] - kKnots[k]);
    const Eigen::Vector3d left = cubic_at(kKnots[k], -1.0, delta);
    const Eigen::Vector3d right = cubic_at(kKnots[k], 1.0, delta);
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(left[d], right[d], 1e-6 * (1 + std::abs(left[d]))) << "knot " << k << " f^(" << d << ")";
    }
  }
  const double first = 0.2 * (kKnots[1] - kKnots[0]);
  const double last = 0.2 * (kKnots[n - 1] - kKnots[n - 2]);
  EXPECT_NEAR(cubic_at(kKnots.front(), 1.0, first)[2], 0.0, 1e-6);
  EXPECT_NEAR(cubic_at(kKnots.back(), -1.0, last)[2], 0.0, 1e-6);
  // Held at the end values outside the knots.
  EXPECT_EQ(Spline(kKnots, v, -1.0), v[0]);
  EXPECT_EQ(Spline(kKnots, v, 2.0), v[n - 1]);
}

TEST(ForceMapSplineTest, ReproducesAStraightLineExactly) {
  Values v{};
  for (size_t k = 0; k < kKnots.size(); ++k) v[k] = 2.0 - 7.0 * kKnots[k];
  for (double z = -0.3; z <= 0.5; z += 0.0137) {
    EXPECT_NEAR(Spline(kKnots, v, z), 2.0 - 7.0 * z, 1e-12) << z;
  }
}

TEST(ForceMapSplineTest, KnotsAreChecked) {
  EXPECT_TRUE(ForceMapKnotsProblem({0, 1, 2, 3}).ok());
  EXPECT_EQ(ForceMapKnotsProblem({0, 1, 2}).got, "3");
  EXPECT_EQ(ForceMapKnotsProblem({0, 1, 1, 3}).expected, "strictly increasing knots");
  EXPECT_EQ(ForceMapKnotsProblem({0, 1, NAN, 3}).expected, "finite knots");
  EXPECT_FALSE(ForceMapKnotsProblem(std::vector<double>(kMaxForceMapKnots + 1, 0.0)).ok());
}

// The map's force in AxisDerivative: Jet derivatives with respect to the
// values and to the state against central differences.
TEST(ForceMapModelTest, JetDerivativesMatchFiniteDifferences) {
  for (int form = 0; form < 3; ++form) {
    AxisStructure s;
    s.coupling = Coupling::kRigid;
    s.amplifier = Amplifier::kForceSource;
    s.force_map.enabled = true;
    s.force_map.variable = form == 2 ? ForceMapVariable::kV : ForceMapVariable::kX;
    s.force_map.friction = form == 1;
    s.force_map.knots = form == 2 ? std::vector<double>{-0.4, -0.1, 0.0, 0.2, 0.45}
                                  : std::vector<double>{-0.3, 0.0, 0.05, 0.2, 0.4};
    AxisParams<double> p;
    p.g_F = 10.0;
    p.v_eps = 0.01;
    const double values[] = {5.0, -3.0, 8.0, 1.0, -2.0};
    for (int k = 0; k < 5; ++k) p.f_map[k] = values[k];
    AxisState<double> y = AxisState<double>::Zero();
    y[0] = 0.031;
    y[1] = 0.013;
    // Jet<6>: values 0..4 and x.
    using J = ceres::Jet<double, 6>;
    AxisParams<J> pj = p.cast<J>();
    for (int k = 0; k < 5; ++k) pj.f_map[k].v[k] = 1.0;
    AxisState<J> yj = y.cast<J>();
    yj[0].v[5] = 1.0;
    AxisState<J> dyj;
    AxisDerivative(s, pj, yj, J(1.0), &dyj);
    const auto accel = [&](const AxisParams<double>& q, const AxisState<double>& state) {
      AxisState<double> dy;
      AxisDerivative(s, q, state, 1.0, &dy);
      return dy[1];
    };
    const double h = 1e-6;
    for (int k = 0; k < 5; ++k) {
      AxisParams<double> plus = p, minus = p;
      plus.f_map[k] += h;
      minus.f_map[k] -= h;
      const double fd = (accel(plus, y) - accel(minus, y)) / (2 * h);
      EXPECT_NEAR(dyj[1].v[k], fd, 1e-7) << "form " << form << " value " << k;
    }
    AxisState<double> yp = y, ym = y;
    yp[0] += h;
    ym[0] -= h;
    const double fd = (accel(p, yp) - accel(p, ym)) / (2 * h);
    EXPECT_NEAR(dyj[1].v[5], fd, 1e-6 * (1 + std::abs(fd))) << "form " << form;
    EXPECT_NEAR(dyj[1].a, accel(p, y), 1e-12);
  }
}

// A learned friction below zero at rest (f(v) falling through v = 0) makes
// the rest state a growing real mode; the RK4 step check must not demand a
// vanishing step for it (it did: 3.8e-21 s for a map fitted on the friction
// patch case).
TEST(ForceMapModelTest, GrowingRealModeSetsNoStepLimit) {
  AxisStructure s;
  s.coupling = Coupling::kRigid;
  s.amplifier = Amplifier::kForceSource;
  s.force_map = {true, ForceMapVariable::kV, false, {-0.2, -0.05, 0.05, 0.2}};
  AxisParams<double> p;
  p.g_F = 10.0;
  p.B_a = 0.0;
  const double values[] = {10.0, 5.0, -5.0, -10.0};  // slope −100 N·s/m at rest
  for (int k = 0; k < 4; ++k) p.f_map[k] = values[k];
  const Rk4StabilityLimit limit = Rk4StabilityLimitOf(s, p);
  EXPECT_FALSE(limit.max_step < 1.0) << limit.max_step;  // +inf: nothing limits it
}

AxisConfig ConfigWithMap(const std::string& map_yaml) {
  const std::string text =
      "name: m\namplifier: force_source\ncoupling: rigid\nparameters: {M: 10, g_F: 5, B_a: 0, "
      "r_g: 1}\neffects:\n  force_map: " +
      map_yaml + "\n";
  return ParseAxisConfig(ParseYamlText(text, "map.yaml"), "map.yaml");
}

TEST(ForceMapConfigTest, RoundTripsThroughTheModelConfig) {
  const AxisConfig c = ConfigWithMap(
      "{variable: x, friction: true, knots: [0, 0.1, 0.2, 0.4], values: [1, -2.5, 3, 0.25]}");
  ASSERT_TRUE(c.structure.force_map.enabled);
  EXPECT_TRUE(c.structure.force_map.friction);
  EXPECT_EQ(c.structure.force_map.variable, ForceMapVariable::kX);
  EXPECT_EQ(c.structure.force_map.knots, (std::vector<double>{0, 0.1, 0.2, 0.4}));
  EXPECT_EQ(c.params.f_map[1], -2.5);
  EXPECT_EQ(EnabledEffectNames(c.structure), (std::vector<std::string>{"force_map.x_friction"}));
  const AxisConfig back =
      ParseAxisConfig(ParseYamlText(AxisConfigToYaml(c), "back.yaml"), "back.yaml");
  EXPECT_EQ(back.structure.force_map.knots, c.structure.force_map.knots);
  EXPECT_EQ(back.structure.force_map.friction, true);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(back.params.f_map[k], c.params.f_map[k]);
}

TEST(ForceMapConfigTest, BadMapsNameTheKey) {
  const auto message = [](const std::string& yaml) {
    try {
      ConfigWithMap(yaml);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("{variable: x, knots: [0, 1, 2, 3], values: [1, 2, 3]}")
                .find("effects.force_map.values"),
            std::string::npos);
  EXPECT_NE(message("{variable: x, knots: [0, 2, 1, 3], values: [1, 2, 3, 4]}")
                .find("strictly increasing"),
            std::string::npos);
  EXPECT_NE(message("{variable: v, friction: true, knots: [0, 1, 2, 3], values: [1, 2, 3, 4]}")
                .find("effects.force_map.friction"),
            std::string::npos);
  EXPECT_NE(message("{variable: y, knots: [0, 1, 2, 3], values: [1, 2, 3, 4]}")
                .find("effects.force_map.variable"),
            std::string::npos);
  EXPECT_NE(message("{variable: x, knots: [0, 1, 2, 3], values: [1, 2, 3, 4], wrong: 1}")
                .find("wrong"),
            std::string::npos);
}

TEST(RoughnessPenaltyTest, SecondDifferencesOnUniformKnots) {
  const Eigen::MatrixXd d = SecondDifferences({0.0, 0.5, 1.0, 1.5, 2.0});
  ASSERT_EQ(d.rows(), 3);
  for (int j = 0; j < 3; ++j) {
    EXPECT_NEAR(d(j, j), 1.0, 1e-12);
    EXPECT_NEAR(d(j, j + 1), -2.0, 1e-12);
    EXPECT_NEAR(d(j, j + 2), 1.0, 1e-12);
  }
  // A straight line has no roughness on any knots.
  const Eigen::MatrixXd dn = SecondDifferences(kKnots);
  Eigen::VectorXd line(kKnots.size());
  for (size_t k = 0; k < kKnots.size(); ++k) line[k] = 3.0 + 2.0 * kKnots[k];
  EXPECT_LT((dn * line).norm(), 1e-12);
}

TEST(RoughnessPenaltyTest, ConfoundedComponentsFollowTheFreeParameters) {
  ForceMap v_map{true, ForceMapVariable::kV, false, {-1, 0, 1, 2}};
  EXPECT_EQ(ConfoundedComponents(v_map, {"V_L"}).rows(), 0);
  EXPECT_EQ(ConfoundedComponents(v_map, {"B_a"}).rows(), 1);
  EXPECT_EQ(ConfoundedComponents(v_map, {"B_a", "F_0"}).rows(), 2);
  ForceMap friction{true, ForceMapVariable::kX, true, {-1, 0, 1, 2}};
  EXPECT_EQ(ConfoundedComponents(friction, {"B_a"}).rows(), 0);
  const Eigen::MatrixXd c = ConfoundedComponents(friction, {"F_c"});
  ASSERT_EQ(c.rows(), 1);
  EXPECT_NEAR(c.row(0).norm(), 1.0, 1e-12);
  EXPECT_NEAR(c(0, 0), c(0, 3), 1e-12);
  const Eigen::MatrixXd both = ConfoundedComponents(v_map, {"B_a", "F_0"});
  EXPECT_NEAR(both.row(0).dot(both.row(1)), 0.0, 1e-12);  // uniform knots: orthogonal
}

TEST(RoughnessPenaltyTest, JacobianMatchesFiniteDifferences) {
  AxisParams<double> base;
  base.f_map[2] = 4.0;  // fixed
  std::vector<FreeParameter> free(4);
  const char* names[] = {"B_a", "f_map.0", "f_map.1", "f_map.3"};
  for (int k = 0; k < 4; ++k) {
    free[k].name = names[k];
    free[k].scale = k == 2 ? 3.0 : 1.0;
    free[k].log = k == 0;
    free[k].lower = -1e6;
    free[k].upper = 1e6;
  }
  free[0].lower = 1.0;
  const ParameterMap map(base, free);
  const ForceMap f{true, ForceMapVariable::kV, false, {-0.2, 0.0, 0.1, 0.3}};
  std::unique_ptr<ceres::CostFunction> cost(RoughnessCost::Create(f, map, 4, 2.0, 50.0));
  ASSERT_NE(cost, nullptr);
  EXPECT_EQ(cost->num_residuals(), 3);  // two second differences, the slope (B_a free)
  const double theta[] = {std::log(200.0), 1.5, -0.7, 2.0};
  const double* params[] = {theta};
  std::vector<double> r(3), jac(3 * 4);
  double* jacobians[] = {jac.data()};
  ASSERT_TRUE(cost->Evaluate(params, r.data(), jacobians));
  for (int k = 0; k < 4; ++k) {
    double plus[4], minus[4];
    std::copy(theta, theta + 4, plus);
    std::copy(theta, theta + 4, minus);
    plus[k] += 1e-6;
    minus[k] -= 1e-6;
    std::vector<double> rp(3), rm(3);
    const double* pp[] = {plus};
    const double* pm[] = {minus};
    ASSERT_TRUE(cost->Evaluate(pp, rp.data(), nullptr));
    ASSERT_TRUE(cost->Evaluate(pm, rm.data(), nullptr));
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(jac[i * 4 + k], (rp[i] - rm[i]) / 2e-6, 1e-6) << i << "," << k;
    }
  }
  // Nothing free of the map: no cost.
  const ParameterMap none(base, {free[0]});
  EXPECT_EQ(RoughnessCost::Create(f, none, 1, 2.0, 50.0), nullptr);
}

}  // namespace
}  // namespace axis
