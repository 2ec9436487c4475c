// EffectWald (discovery/discovery.h), the significance test of an effect in the
// final model against its off value, against hand-computed Wald statistics.
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/statistics.h"
#include "discovery/discovery.h"
#include "estimation/fit_result.h"

namespace axis {
namespace {

// A fit with free F_0, F_st, F_c, A_cog, phi_cog and fixed T_c, with the
// correlation matrix given; std_errors as listed.
FitResult MakeFit() {
  FitResult fit;
  const auto add = [&](const std::string& name, double value, double se, bool free) {
    ParameterEstimate e;
    e.name = name;
    e.value = value;
    e.std_error = free ? se : std::nan("");
    e.free = free;
    fit.parameters.push_back(e);
    if (free) fit.free_names.push_back(name);
  };
  add("F_0", 0.003, 0.004, true);
  add("F_st", 40.0, 2.0, true);
  add("F_c", 30.0, 1.0, true);
  add("A_cog", 0.02, 0.001, true);
  add("phi_cog", 0.7, 0.1, true);
  add("T_c", 0.5, 0.0, false);
  fit.correlation = Eigen::MatrixXd::Identity(5, 5);
  fit.correlation(1, 2) = fit.correlation(2, 1) = 0.5;  // F_st, F_c
  fit.correlation(3, 4) = fit.correlation(4, 3) = 0.6;  // A_cog, phi_cog
  return fit;
}

TEST(EffectWaldTest, OneParameterAgainstZero) {
  // F_0 = 0.003 ± 0.004 N: χ² = 0.75² (the stand-in), p = erfc(0.75/√2).
  const EffectSignificance w = EffectWald("load_offset", MakeFit());
  EXPECT_EQ(w.effect, "load_offset");
  EXPECT_EQ(w.dof, 1);
  EXPECT_NEAR(w.chi2, 0.5625, 1e-12);
  EXPECT_NEAR(w.p_value, std::erfc(0.75 / std::sqrt(2.0)), 1e-12);
}

TEST(EffectWaldTest, StribeckAgainstCoulomb) {
  // d = F_st − F_c = 10 N, var = 2² + 1² − 2·0.5·2·1 = 3 N².
  const EffectSignificance w = EffectWald("stribeck", MakeFit());
  EXPECT_EQ(w.dof, 1);
  EXPECT_NEAR(w.chi2, 100.0 / 3.0, 1e-9);
  EXPECT_NEAR(w.p_value, ChiSquaredSurvival(100.0 / 3.0, 1), 1e-15);
}

TEST(EffectWaldTest, CoggingBothQuadratures) {
  // var(A | φ) = 1e-6 − (0.6·1e-3·0.1)²/0.1² = 6.4e-7; χ² = 0.02²/6.4e-7 = 625
  // on 2 dof, p = exp(−625/2).
  const EffectSignificance w = EffectWald("cogging", MakeFit());
  EXPECT_EQ(w.dof, 2);
  EXPECT_NEAR(w.chi2, 625.0, 1e-6);
  EXPECT_NEAR(std::log(w.p_value), -312.5, 1e-6);
}

TEST(EffectWaldTest, StribeckShapeAgainstTheGaussian) {
  // δ = 1.4 ± 0.2 against the Gaussian 2: χ² = (0.6/0.2)² = 9, p = erfc(3/√2).
  FitResult fit;
  ParameterEstimate e;
  e.name = "delta_st";
  e.value = 1.4;
  e.std_error = 0.2;
  e.free = true;
  fit.parameters.push_back(e);
  fit.free_names.push_back(e.name);
  fit.correlation = Eigen::MatrixXd::Identity(1, 1);
  const EffectSignificance w = EffectWald("stribeck_shape", fit);
  EXPECT_EQ(w.dof, 1);
  EXPECT_NEAR(w.chi2, 9.0, 1e-9);
  EXPECT_NEAR(w.p_value, std::erfc(3.0 / std::sqrt(2.0)), 1e-12);
}

TEST(EffectWaldTest, FixedOrMissingParameterIsNotSignificant) {
  EXPECT_TRUE(std::isnan(EffectWald("motor_coulomb", MakeFit()).p_value));  // T_c fixed
  EXPECT_TRUE(std::isnan(EffectWald("sensor_bias.a", MakeFit()).p_value));  // absent
}

TEST(EffectWaldTest, UnknownEffectIsAnError) {
  EXPECT_THROW(EffectWald("friction", MakeFit()), std::invalid_argument);
  EXPECT_THROW(EffectWald("sensor_delay", MakeFit()), std::invalid_argument);  // no channel
  EXPECT_THROW(EffectWald("coulomb.a", MakeFit()), std::invalid_argument);
  EXPECT_THROW(EffectWald("sensor_delay.q", MakeFit()), std::invalid_argument);
}

}  // namespace
}  // namespace axis
