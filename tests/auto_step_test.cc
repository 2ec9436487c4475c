// The integration step chosen from the model (sim/auto_step.h): the paper's
// own 10 µs on the paper's model, the data period on a rigid first-order
// axis, a step that divides the output and control periods and stays
// under the bound, and a clear error where no step can.
#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "sim/auto_step.h"
#include "sim/axis_config.h"
#include "sim/preflight.h"

namespace axis {
namespace {

AxisConfig Axis(const std::string& name) {
  return LoadAxisConfig(std::string(PROJECT_SOURCE_DIR) + "/configs/axes/" + name);
}

// Whole steps in `period` (within 1e-9 relative).
bool Whole(double period, double step) {
  const double n = period / step;
  return std::abs(n - std::round(n)) <= 1e-9 * n;
}

// The X axis with the paper's full current loop (its limit 19.5 µs,
// tests/axis_model_test.cc): the paper's 10 µs, which divides the 1 ms
// output and the 5 ms control period.
TEST(AutoStepTest, ThePaperModelGetsThePaperStep) {
  const AxisConfig x = Axis("x_axis.yaml");
  const double limit = AutoStepLimit(x.structure, x.params, {});
  EXPECT_NEAR(limit / kAutoStepFraction, 1.95e-5, 0.01e-5);
  EXPECT_DOUBLE_EQ(AutoStep(limit, 1e-3, x.controller.T_s), 1e-5);
}

// A force-driven rigid axis (EMPS: M/B_a = 0.47 s, no faster mode): the
// data period itself, a hundred times the old fixed 10 µs.
TEST(AutoStepTest, ARigidFirstOrderAxisIsIntegratedAtTheDataPeriod) {
  const AxisConfig emps = Axis("emps.yaml");
  const double limit = AutoStepLimit(emps.structure, emps.params, {{"M", 10.0, 1000.0}});
  EXPECT_GT(limit, 1e-3);
  EXPECT_DOUBLE_EQ(AutoStep(limit, 1e-3, 0.0), 1e-3);
}

// The free parameters' ranges count: a stiffer gear at the upper bound of
// k_g is a faster mode, and the limit is the smallest over the ranges.
TEST(AutoStepTest, TheLimitHoldsOverTheFreeParametersRanges) {
  const AxisConfig x = Axis("x_axis.yaml");
  AxisStructure quasi = x.structure;
  quasi.current_loop = CurrentLoop::kQuasiSteady;
  const double at_start = AutoStepLimit(quasi, x.params, {});
  const double over = AutoStepLimit(quasi, x.params, {{"k_g", 5.0e5, 5.0e8}});
  EXPECT_LE(over, at_start);
  AxisParams<double> stiff = x.params;
  stiff.k_g = 5.0e8;
  EXPECT_NEAR(over, kAutoStepFraction * Rk4StabilityLimitOf(quasi, stiff).max_step,
              1e-9 * over);
}

// Any bound and periods: the step is at most the bound and divides both
// periods; a period no round step divides (1/3 ms) gets T_o/n.
TEST(AutoStepTest, TheStepDividesThePeriodsUnderTheBound) {
  for (double limit : {3e-6, 1e-5, 7.3e-5, 1.4e-4, 2e-3}) {
    for (double output : {1e-3, 2e-3, 5e-4, 1.0 / 3000.0}) {
      for (double control : {0.0, 5e-3, 1e-3}) {
        SCOPED_TRACE(std::to_string(limit) + " " + std::to_string(output) + " " +
                     std::to_string(control));
        if (control > 0.0 && !Whole(control, output) && output != 1.0 / 3000.0) continue;
        if (control > 0.0 && output == 1.0 / 3000.0) continue;
        const double h = AutoStep(limit, output, control);
        EXPECT_LE(h, limit * (1 + 1e-12));
        EXPECT_TRUE(Whole(output, h));
        if (control > 0.0) {
          EXPECT_TRUE(Whole(control, h));
        }
      }
    }
  }
  EXPECT_NEAR(AutoStep(1e-4, 1.0 / 3000.0, 0.0), 1.0 / 3000.0 / 4.0, 1e-15);
}

TEST(AutoStepTest, AControlPeriodNoStepDividesIsRefused) {
  try {
    AutoStep(1e-4, 1e-3, std::sqrt(2.0) * 1e-3);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("set simulation.step"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace axis
