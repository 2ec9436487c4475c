// estimation/internal/optimistic_solve.h: trial points in double, the
// sensitivity guard only for a run that needs it.
#include "estimation/internal/optimistic_solve.h"

#include <vector>

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "estimation/experiment_cost.h"

namespace axis {
namespace {

// r = θ − 3, whose Jacobian cannot be evaluated past θ = `wall` (as an
// ExperimentCost's cannot where a sensitivity blows up); a residual-only
// evaluation with the counter's guard on fails there too (the guard's
// one-direction Jet sees the same), with it off it succeeds. Counts the
// residual-only evaluations of each kind.
class WalledLine : public ceres::SizedCostFunction<1, 1> {
 public:
  WalledLine(const EvaluationCounter* counter, double wall) : counter_(counter), wall_(wall) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double x = parameters[0][0];
    if (jacobians == nullptr) {
      ++(counter_->guard ? guarded : plain);
      if (counter_->guard && x > wall_) return false;
      residuals[0] = x - 3.0;
      return true;
    }
    if (x > wall_) return false;
    residuals[0] = x - 3.0;
    if (jacobians[0] != nullptr) jacobians[0][0] = 1.0;
    return true;
  }
  mutable int guarded = 0, plain = 0;

 private:
  const EvaluationCounter* counter_;
  double wall_;
};

ceres::Solver::Options Options() {
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_QR;
  o.logging_type = ceres::SILENT;
  o.max_num_iterations = 100;
  return o;
}

struct Line {
  explicit Line(double wall) : cost(new WalledLine(&counter, wall)) {
    problem.AddResidualBlock(cost, nullptr, &theta);
  }
  EvaluationCounter counter;
  WalledLine* cost;  // owned by the problem
  ceres::Problem problem;
  double theta = 0.0;
};

// Nothing in the way: one run, every trial point in double, the minimum.
TEST(OptimisticSolveTest, ARunThatNeedsNoGuardRunsOnceInDouble) {
  Line line(1e300);
  ceres::Solver::Summary summary;
  SolveOptimistically(Options(), &line.problem, &line.theta, 1, &line.counter, &summary);
  EXPECT_TRUE(summary.IsSolutionUsable()) << summary.message;
  // Levenberg–Marquardt's damped steps stop at Ceres' default tolerances
  // (function_tolerance 1e-6 of a cost already ~1e-16 here): 1e-8 short.
  EXPECT_NEAR(line.theta, 3.0, 1e-6);
  EXPECT_GT(line.cost->plain, 0);
  EXPECT_EQ(line.cost->guarded, 0);
  EXPECT_TRUE(line.counter.guard) << "the guard is left as it was";
}

// The first step lands past the wall: in double it is accepted and the
// Jacobian there fails, which ends Ceres' run in FAILURE; the run again
// with the guard rejects that step, shrinks the trust region and ends
// usable below the wall, as a guarded run alone would (compared), the
// summary counting both runs' Jacobians.
TEST(OptimisticSolveTest, AFailedRunIsRepeatedWithTheGuard) {
  Line alone(2.5);
  ceres::Solver::Summary guarded_alone;
  ceres::Solve(Options(), &alone.problem, &guarded_alone);
  ASSERT_TRUE(guarded_alone.IsSolutionUsable()) << guarded_alone.message;

  Line line(2.5);
  ceres::Solver::Summary summary;
  SolveOptimistically(Options(), &line.problem, &line.theta, 1, &line.counter, &summary);
  EXPECT_TRUE(summary.IsSolutionUsable()) << summary.message;
  EXPECT_LE(line.theta, 2.5);
  EXPECT_EQ(line.theta, alone.theta) << "the guarded run, from the same start";
  EXPECT_EQ(summary.final_cost, guarded_alone.final_cost);
  EXPECT_GT(line.cost->plain, 0);
  EXPECT_GT(line.cost->guarded, 0);
  EXPECT_GT(summary.num_jacobian_evaluations, guarded_alone.num_jacobian_evaluations)
      << "the failed run's Jacobians count too";
  EXPECT_TRUE(line.counter.guard);
}

// With the guard off already (a caller probing in double) or no counter:
// one plain run, which here fails, and the guard stays as it was.
TEST(OptimisticSolveTest, WithoutAGuardToLiftItIsOnePlainRun) {
  Line line(2.5);
  line.counter.guard = false;
  ceres::Solver::Summary summary;
  SolveOptimistically(Options(), &line.problem, &line.theta, 1, &line.counter, &summary);
  EXPECT_FALSE(summary.IsSolutionUsable());
  EXPECT_EQ(line.cost->guarded, 0);
  EXPECT_FALSE(line.counter.guard);

  Line none(2.5);
  SolveOptimistically(Options(), &none.problem, &none.theta, 1, nullptr, &summary);
  EXPECT_TRUE(summary.IsSolutionUsable()) << "the counter's guard is on: guarded";
  EXPECT_EQ(none.cost->plain, 0);
}

}  // namespace
}  // namespace axis
