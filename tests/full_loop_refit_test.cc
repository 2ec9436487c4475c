// The intervals of the full-loop refit (estimation/full_loop_refit.h),
// against their closed forms: the quasi-steady fit's carried to the refit's
// value (in ratio for positive values, by difference otherwise), widened by
// the ratio of the Gauss–Newton standard errors where the refit's is larger,
// never narrowed; and again when an effect is dropped after the refit.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "estimation/fit_result.h"
#include "estimation/full_loop_refit.h"

namespace axis {
namespace {

ParameterEstimate Free(const std::string& name, double value, double se, double se_gn,
                       double low, double high, const std::string& method) {
  ParameterEstimate e;
  e.name = name;
  e.value = value;
  e.free = true;
  e.std_error = se;
  e.std_error_gauss_newton = se_gn;
  e.ci95_low = low;
  e.ci95_high = high;
  e.interval_method = method;
  e.determined = true;
  return e;
}

// The quasi-steady fit: T_p (positive: carried in ratio) and a delay that
// may be negative (carried by difference), with profile intervals.
FitResult Quasi() {
  FitResult q;
  q.parameters = {Free("T_p", 0.040, 1.0e-6, 1.0e-6, 0.039998, 0.040002, "profile likelihood"),
                  Free("tau_d.a", -7e-6, 1e-6, 1e-6, -9e-6, -5e-6, "profile likelihood")};
  q.optimum_verified = true;
  q.optimum_check = "150 probes";
  q.uncertainty_method = "profile";
  q.uncertainty_note = "profile-likelihood intervals";
  return q;
}

TEST(FullLoopRefitTest, CarriedIntervalsMoveWithTheValueAndAreNeverNarrower) {
  FitResult full;
  // T_p: the full loop's Gauss–Newton scale 3 times narrower (roughness):
  // r = 1. tau_d.a: 2 times wider: r = 2.
  full.parameters = {Free("T_p", 0.041, 1e-7, 3.3e-7, 0, 0, "Gauss–Newton"),
                     Free("tau_d.a", -6e-6, 2e-6, 2e-6, 0, 0, "Gauss–Newton")};
  CarryQuasiSteadyIntervals(Quasi(), &full);
  const ParameterEstimate& tp = full.parameters[0];
  EXPECT_DOUBLE_EQ(tp.ci95_low, 0.041 * (0.039998 / 0.040));
  EXPECT_DOUBLE_EQ(tp.ci95_high, 0.041 * (0.040002 / 0.040));
  EXPECT_DOUBLE_EQ(tp.std_error, 1.0e-6);
  EXPECT_EQ(tp.interval_method, "profile likelihood, carried from the quasi-steady fit");
  const ParameterEstimate& d = full.parameters[1];
  EXPECT_NEAR(d.ci95_low, -6e-6 + 2.0 * (-9e-6 + 7e-6), 1e-18);
  EXPECT_NEAR(d.ci95_high, -6e-6 + 2.0 * (-5e-6 + 7e-6), 1e-18);
  EXPECT_DOUBLE_EQ(d.std_error, 2e-6);
  EXPECT_TRUE(full.optimum_verified);
  EXPECT_NE(full.optimum_check.find("in the quasi-steady fit: 150 probes"), std::string::npos);
  EXPECT_EQ(full.uncertainty_method, "profile");
}

// After the refit, tau_d.a is dropped: the model without it is again a
// local Gauss–Newton solve, here with T_p 4 times narrower than the carried
// interval (the square + sweep seed 5 case: 14 times). The carried interval
// stays, moved to the new value; the method names are the carried ones,
// not doubled.
TEST(FullLoopRefitTest, DroppingAnEffectKeepsTheCarriedIntervals) {
  FitResult carried;
  carried.parameters = {Free("T_p", 0.041, 1e-7, 3.3e-7, 0, 0, "Gauss–Newton"),
                        Free("tau_d.a", -6e-6, 2e-6, 2e-6, 0, 0, "Gauss–Newton")};
  CarryQuasiSteadyIntervals(Quasi(), &carried);
  FitResult without;
  without.parameters = {Free("T_p", 0.0405, 2.5e-7, 2.5e-7, 0.0404995, 0.0405005, "Gauss–Newton")};
  without.optimum_check = "not checked";
  CarryIntervalsAcrossRemoval(carried, &without);
  const ParameterEstimate& tp = without.parameters[0];
  EXPECT_DOUBLE_EQ(tp.ci95_low, 0.0405 * (carried.parameters[0].ci95_low / 0.041));
  EXPECT_DOUBLE_EQ(tp.ci95_high, 0.0405 * (carried.parameters[0].ci95_high / 0.041));
  EXPECT_DOUBLE_EQ(tp.std_error, 1.0e-6);
  EXPECT_EQ(tp.interval_method, "profile likelihood, carried from the quasi-steady fit");
  EXPECT_EQ(without.optimum_check, carried.optimum_check);
  EXPECT_EQ(without.uncertainty_note, carried.uncertainty_note);

  // Where the refit's Gauss–Newton scale is wider (ratio 3), the interval
  // widens by it.
  FitResult wider;
  wider.parameters = {Free("T_p", 0.041, 9.9e-7, 9.9e-7, 0, 0, "Gauss–Newton")};
  CarryIntervalsAcrossRemoval(carried, &wider);
  EXPECT_NEAR(wider.parameters[0].std_error, 3.0e-6, 1e-15);
  EXPECT_NEAR(std::log(wider.parameters[0].ci95_high / 0.041),
              3.0 * std::log(carried.parameters[0].ci95_high / 0.041), 1e-12);
}

}  // namespace
}  // namespace axis
