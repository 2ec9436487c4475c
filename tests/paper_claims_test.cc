// The paper's claims (MODEL.md §8) reproduced from the committed experiment
// files: Fig. 4 (10 V step of the nonlinear X axis) and Fig. 5 (1 m move
// through the digital position controller). Fig. 3 and the steady-state gain
// are in linear_model_test.cc.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "sim/config.h"
#include "sim/experiment.h"

namespace axis {
namespace {

std::string ConfigPath(const std::string& name) {
  return std::string(PROJECT_SOURCE_DIR) + "/configs/experiments/" + name;
}

// Index of the first sample with v ≥ level.
size_t FirstReaching(const std::vector<double>& v, double level) {
  for (size_t k = 0; k < v.size(); ++k) {
    if (v[k] >= level) return k;
  }
  return v.size();
}

class Fig4Test : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    experiment_ = new ExperimentConfig(LoadExperiment(ConfigPath("x_step_10V.yaml")));
    trace_ = new Trace<double>(RunExperiment(*experiment_));
  }
  static void TearDownTestSuite() {
    delete experiment_;
    delete trace_;
  }
  static ExperimentConfig* experiment_;
  static Trace<double>* trace_;
};
ExperimentConfig* Fig4Test::experiment_ = nullptr;
Trace<double>* Fig4Test::trace_ = nullptr;

// Fig. 4: during the rise the preamp output sits at its limit V_L and the
// current loop holds i at K_i·V_L less the back-EMF share, i.e. the
// quasi-static solution of eq. 3 with V_m = K_a·(V_L − i/K_i):
//   i = (K_a·V_L − K_e·ω)/(K_a/K_i + R).
TEST_F(Fig4Test, CurrentSitsAtTheLimitDuringTheRise) {
  const AxisParams<double>& p = experiment_->model.params;
  const auto& v = (*trace_)[Channel::kV];
  const auto& vc = (*trace_)[Channel::kVc];
  const auto& i = (*trace_)[Channel::kI];
  const auto& omega = (*trace_)[Channel::kOmega];
  const size_t rise_end = FirstReaching(v, 1.0);
  ASSERT_LT(rise_end, v.size()) << "velocity never reached 1 m/s";
  size_t at_limit = 0;
  for (size_t k = 0; k < rise_end; ++k) {
    const double expected =
        (p.K_a * p.V_L - p.K_e * omega[k]) / (p.K_a / p.K_i + p.R);
    // 3 % of K_i·V_L: the tolerance; the quasi-static formula is
    // exact up to the L·di/dt term, which is ~1e-4 A once the 7 µs current
    // transient has passed.
    if (std::abs(vc[k]) >= p.V_L * (1 - 1e-12) &&
        std::abs(i[k] - expected) <= 0.03 * p.K_i * p.V_L) {
      ++at_limit;
    }
  }
  const double fraction = static_cast<double>(at_limit) / rise_end;
  RecordProperty("rise_time_s", std::to_string(trace_->t[rise_end]));
  RecordProperty("fraction_at_limit", std::to_string(fraction));
  EXPECT_GE(fraction, 0.70);
  // The rise takes about 0.6 s: from rest to 1 m/s under 408 N against
  // 172 kg of reflected mass and 222 N·s/m of damping.
  EXPECT_NEAR(trace_->t[rise_end], 0.63, 0.05);
}

TEST_F(Fig4Test, VelocityEndsAtOneMetrePerSecond) {
  // 10 V × 0.09995 m/s per V (MODEL.md §3); 0.5 % is the tolerance.
  EXPECT_NEAR((*trace_)[Channel::kV].back(), 1.0, 0.005);
}

TEST_F(Fig4Test, GearForceRingsAfterTheRiseAndDecays) {
  const auto& v = (*trace_)[Channel::kV];
  const auto& fg = (*trace_)[Channel::kFg];
  const std::vector<double>& t = trace_->t;
  const size_t rise_end = FirstReaching(v, 1.0);
  // Steady state: the gear carries the arm friction B_a·v = 200 N.
  const double fg_final = fg.back();
  EXPECT_NEAR(fg_final, experiment_->model.params.B_a * v.back(), 1.0);
  const auto window = [&](double from, double to, int* sign_changes) {
    double peak = 0.0;
    int changes = 0;
    double previous = 0.0;
    for (size_t k = rise_end; k < t.size(); ++k) {
      const double dt = t[k] - t[rise_end];
      if (dt < from || dt >= to) continue;
      const double d = fg[k] - fg_final;
      peak = std::max(peak, std::abs(d));
      if (previous != 0.0 && d * previous < 0.0) ++changes;
      if (d != 0.0) previous = d;
    }
    if (sign_changes) *sign_changes = changes;
    return peak;
  };
  int changes = 0;
  const double early = window(0.0, 0.1, nullptr);
  window(0.0, 0.3, &changes);
  const double late = window(0.2, 0.3, nullptr);
  const double end = window(0.7, 0.85, nullptr);
  RecordProperty("ringing_peak_N", std::to_string(early));
  // Ringing: several oscillations about the final force (~25 Hz seen).
  EXPECT_GE(changes, 4);
  EXPECT_GT(early, 100.0);
  // Decay: the late envelope is well below the early one, and the force is
  // settled at the end of the run.
  EXPECT_LT(late, 0.5 * early);
  EXPECT_LT(end, 0.02 * early);
}

// Fig. 5: a programmed 1 m move at 0.9 m/s takes about 1.5–2 s; here it must
// be within 1 mm of its target, and stay there, before 2 s.
TEST(Fig5Test, OneMetreMoveEndsWithinOneMillimetreInTwoSeconds) {
  const ExperimentConfig e = LoadExperiment(ConfigPath("x_move_1m.yaml"));
  const Trace<double> trace = RunExperiment(e);
  const auto& x = trace[Channel::kX];
  ASSERT_EQ(e.drive.reference.distance, 1.0);
  double settled_at = -1.0;
  for (size_t k = x.size(); k-- > 0;) {
    if (std::abs(x[k] - 1.0) > 1e-3) {
      settled_at = k + 1 < x.size() ? trace.t[k + 1] : -1.0;
      break;
    }
  }
  RecordProperty("settled_at_s", std::to_string(settled_at));
  ASSERT_GT(settled_at, 0.0) << "never within 1 mm of the target";
  EXPECT_LE(settled_at, 2.0);
  // The move cannot be faster than the track itself (about 1.57 s).
  EXPECT_GE(settled_at, 1.4);
  // The drive cannot follow the 2 m/s² track at speed (its current limit
  // leaves about 1.3 m/s² at 0.8 m/s), so the controller output runs into
  // its ±U_max clamp and never beyond it.
  const auto& u = trace[Channel::kU];
  const double u_peak = *std::max_element(u.begin(), u.end());
  EXPECT_EQ(u_peak, e.drive.controller.U_max);
}

}  // namespace
}  // namespace axis
