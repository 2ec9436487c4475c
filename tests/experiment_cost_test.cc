// ExperimentCost (estimation/experiment_cost.h) integrates the plant with
// Jets over the entries of θ that act on it alone and applies the sensor
// front end in the full Jet: its residuals and Jacobian must be those of
// Simulate differentiated in the full Jet (an independent evaluation, the
// path every cost took before the split), and agree with central
// differences.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "estimation/experiment_cost.h"
#include "estimation/jet_widths.h"
#include "estimation/stacked_jacobian.h"
#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "tests/cost_checks.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;

// The anti-alias front-end case with its front end declared and free: the
// accelerometer sampled at the instant behind a second-order low-pass and
// a delay, the tachometer behind a first-order low-pass with a bias; the
// paper's five unknowns free beside them (10 entries: a Jet of 12 or 16
// parts, estimation/jet_widths.h; the plant alone 5).
FitJob FrontEndJob() {
  FitJob job = LoadFitJob(kRoot + "/configs/jobs/front_end/anti_alias.yaml");
  AxisConfig& m = job.problem.model;
  const int a = static_cast<int>(Channel::kA);
  const int tach = static_cast<int>(Channel::kTach);
  m.structure.accelerometer = AccelerometerSampling::kInstant;
  m.structure.sensors.lowpass2[a] = true;
  m.structure.sensors.delay[a] = true;
  m.structure.sensors.lowpass[tach] = true;
  m.structure.sensors.bias[tach] = true;
  m.params.tau_lp2[a] = 6.4e-4;
  m.params.zeta_lp2[a] = 0.6;
  m.params.tau_d[a] = 3.37e-4;  // off the 100 µs grid: no kink of the interpolation
  m.params.tau_lp[tach] = 4e-4;
  m.params.b[tach] = 0.01;
  const auto add = [&](const std::string& name, double value, double lower, double upper,
                       bool log) {
    FreeParameter f;
    f.name = name;
    f.initial = value;
    f.lower = lower;
    f.upper = upper;
    f.log = log;
    job.problem.free.push_back(f);
  };
  add("tau_lp2.a", 6.4e-4, 1e-6, 1e-2, true);
  add("zeta_lp2.a", 0.6, 0.05, 5.0, true);
  add("tau_d.a", 3.37e-4, -0.01, 0.01, false);
  add("tau_lp.tach", 4e-4, 1e-6, 1e-2, true);
  add("b.tach", 0.01, -1.0, 1.0, false);
  return job;
}

// The residuals and Jacobian (row-major, m × n) of the first experiment's
// cost at θ through Ceres (the split path).
void CostJacobian(const FitJob& job, const std::vector<double>& theta, int state_index,
                  std::vector<double>* r, std::vector<double>* jac) {
  const ParameterMap map(job.problem.model.params, job.problem.free);
  EvaluationCounter counter;
  const int n = static_cast<int>(theta.size());
  std::unique_ptr<ceres::CostFunction> cost(ExperimentCost::Create(
      job.problem.model.structure, map, job.problem.experiments[0], n, state_index, &counter));
  r->assign(cost->num_residuals(), 0.0);
  jac->assign(static_cast<size_t>(cost->num_residuals()) * n, 0.0);
  const double* params[] = {theta.data()};
  double* jacobians[] = {jac->data()};
  ASSERT_TRUE(cost->Evaluate(params, r->data(), jacobians));
}

// The same from Simulate in Jet<12> with unit seeds, every entry of θ
// differentiated through the whole simulation.
void DirectJacobian(const FitJob& job, const std::vector<double>& theta, int state_index,
                    std::vector<double>* r, std::vector<double>* jac) {
  using J = ceres::Jet<double, 12>;
  const ParameterMap map(job.problem.model.params, job.problem.free);
  const FitExperiment& e = job.problem.experiments[0];
  const int n = static_cast<int>(theta.size());
  ASSERT_LE(n, 12);
  std::vector<J> t(n);
  for (int k = 0; k < n; ++k) t[k] = J(theta[k], k);
  const AxisParams<J> p = map.Apply(t.data());
  AxisState<J> y0 = e.initial_state.cast<J>();
  if (state_index >= 0) {
    y0[0] = t[state_index];
    y0[1] = t[state_index + 1];
    y0[2] = y0[0] / p.r_g;
    y0[3] = y0[1] / p.r_g;
  }
  const SimulationGrid grid = MakeGrid(e.options, e.drive);
  const Trace<J> trace = Simulate(job.problem.model.structure, p, y0, e.drive, e.options, grid);
  ASSERT_TRUE(trace.finite);
  r->clear();
  jac->clear();
  for (const FittedChannel& f : e.fitted) {
    const std::vector<double>& measured = e.Measured(f.channel);
    for (size_t k = 0; k < measured.size(); ++k) {
      const J residual = (trace[f.channel][k] - measured[k]) * (1.0 / f.sigma);
      r->push_back(residual.a);
      for (int j = 0; j < n; ++j) jac->push_back(residual.v[j]);
    }
  }
}

// `zero_columns`: columns the residuals do not depend on at all (a
// position offset on records of velocity and acceleration, with no
// position-dependent force), checked equal rather than non-zero.
// `unused_entries`: as many entries appended to θ for the cost alone
// (other experiments' initial states, which act on nothing here), whose
// columns must be zero.
void ExpectSame(const FitJob& job, const std::vector<double>& theta, int state_index,
                const std::vector<int>& zero_columns = {}, int unused_entries = 0) {
  std::vector<double> r, wide_jac, r_direct, jac_direct;
  std::vector<double> wide = theta;
  for (int k = 0; k < unused_entries; ++k) wide.push_back(0.1 * (k + 1));
  CostJacobian(job, wide, state_index, &r, &wide_jac);
  DirectJacobian(job, theta, state_index, &r_direct, &jac_direct);
  ASSERT_EQ(r.size(), r_direct.size());
  const int n = static_cast<int>(theta.size());
  const int w = static_cast<int>(wide.size());
  std::vector<double> jac(r.size() * n);
  for (size_t i = 0; i < r.size(); ++i) {
    for (int j = 0; j < w; ++j) {
      if (j < n) {
        jac[i * n + j] = wide_jac[i * w + j];
      } else {
        ASSERT_EQ(wide_jac[i * w + j], 0.0) << "row " << i << ", unused column " << j;
      }
    }
  }
  ASSERT_EQ(jac.size(), jac_direct.size());
  // The plant's values are the same operations in either Jet, and the
  // chain rule multiplies by unit seeds: equal to the last bit but for the
  // sign of a zero. 1e-12 of each column's largest entry leaves room for a
  // compiler's reordering, far below any derivative the fit could see.
  for (int j = 0; j < n; ++j) {
    double largest = 0.0, worst = 0.0;
    for (size_t i = 0; i < r.size(); ++i) {
      largest = std::max(largest, std::abs(jac_direct[i * n + j]));
      worst = std::max(worst, std::abs(jac[i * n + j] - jac_direct[i * n + j]));
    }
    if (std::find(zero_columns.begin(), zero_columns.end(), j) == zero_columns.end()) {
      EXPECT_GT(largest, 0.0) << "column " << j;
    }
    EXPECT_LE(worst, 1e-12 * largest) << "column " << j << " (" << worst << " of " << largest
                                      << ")";
  }
  for (size_t i = 0; i < r.size(); ++i) ASSERT_EQ(r[i], r_direct[i]) << i;
}

std::vector<double> InitialTheta(const FitJob& job) {
  const ParameterMap map(job.problem.model.params, job.problem.free);
  std::vector<double> theta;
  for (int k = 0; k < map.num_free(); ++k) {
    theta.push_back(map.ToInternal(k, job.problem.free[k].initial));
  }
  return theta;
}

TEST(ExperimentCostTest, PlantInNarrowerJetsGivesTheFullJacobian) {
  const FitJob job = FrontEndJob();
  ExpectSame(job, InitialTheta(job), -1);
}

// The job's initial θ with this experiment's (y0, y1) appended, their
// index in *state.
std::vector<double> ThetaWithInitialState(const FitJob& job, int* state) {
  std::vector<double> theta = InitialTheta(job);
  theta.push_back(1e-4);   // y0 of this experiment
  theta.push_back(-2e-3);  // y1
  *state = static_cast<int>(theta.size()) - 2;
  return theta;
}

// With the experiment's (y0, y1) in θ the plant has 7 entries (Jet<8>) of
// 12, and an entry of another experiment's state acts on nothing here.
TEST(ExperimentCostTest, EstimatedInitialStateIsPartOfThePlant) {
  const FitJob job = FrontEndJob();
  int state = 0;
  const std::vector<double> theta = ThetaWithInitialState(job, &state);
  ExpectSame(job, theta, state, {state});
}

// A θ wider than the widest Jet (jet_widths.h): Ceres differentiates it in
// passes of kMaxJetWidth entries, the plant in its narrower Jet in each
// (7 entries: Jet<8>), its derivatives lifted to the pass's seeds.
TEST(ExperimentCostTest, AThetaWiderThanTheWidestJetIsDifferentiatedInPasses) {
  const FitJob job = FrontEndJob();
  int state = 0;
  const std::vector<double> theta = ThetaWithInitialState(job, &state);
  const int unused = kMaxJetWidth + 1 - static_cast<int>(theta.size());
  ASSERT_GT(unused, 0);
  ExpectSame(job, theta, state, {state}, unused);
}

// The sensor parameters alone free: the plant in double.
TEST(ExperimentCostTest, SensorParametersAloneIntegrateThePlantInDouble) {
  FitJob job = FrontEndJob();
  job.problem.free.erase(job.problem.free.begin(), job.problem.free.begin() + 5);
  ExpectSame(job, InitialTheta(job), -1);
}

// And the sensor columns, formed in the front end alone after the split,
// against central differences (cost_checks.h). The plant's columns are the
// full Jet's (above); on these records they cross preamp limits and
// backlash contacts, which central differences do not resolve
// (tests/fit_test.cc checks them on a smooth window).
TEST(ExperimentCostTest, SensorColumnsMatchCentralDifferences) {
  const FitJob job = FrontEndJob();
  const std::vector<testing_files::ColumnCheck> checks =
      testing_files::CheckJobJacobian(job, 1e-6);
  for (size_t k = 5; k < checks.size(); ++k) {
    // Central differences of step 1e-6 in θ: truncation O(h²) and rounding
    // O(ε/h) ≈ 1e-10 relative; the filters are linear in the signal and
    // smooth in τ, ζ and b, and the delay is off the grid's points (no kink
    // of the interpolation within ±h): 1e-4 of the column norm.
    EXPECT_LE(checks[k].error_norm, 1e-4 * checks[k].difference_norm)
        << job.problem.free[k].name << ": " << checks[k].error_norm << " of "
        << checks[k].difference_norm;
  }
}

// The cost remembers its last Jacobian (estimation/internal/last_jacobian_memo.h):
// a second evaluation at the same θ and σ simulates nothing and returns the
// same numbers bit for bit; another θ, or a per-sample σ changed in place,
// simulates again, and the residuals then follow the new σ; residual-only
// evaluations always simulate.
TEST(ExperimentCostTest, RepeatedJacobianAtTheSamePointComesFromMemory) {
  const FitJob job = FrontEndJob();
  const ParameterMap map(job.problem.model.params, job.problem.free);
  const FitExperiment& e = job.problem.experiments[0];
  std::vector<double> theta = InitialTheta(job);
  const int n = static_cast<int>(theta.size());
  SampleSigmas sigma(e.fitted.size());
  EvaluationCounter counter;
  std::unique_ptr<ceres::CostFunction> cost(ExperimentCost::Create(
      job.problem.model.structure, map, e, n, -1, &counter, &sigma));
  const size_t m = static_cast<size_t>(cost->num_residuals());
  const auto evaluate = [&](std::vector<double>* r, std::vector<double>* jac) {
    r->assign(m, 0.0);
    jac->assign(m * n, 0.0);
    const double* params[] = {theta.data()};
    double* jacobians[] = {jac->data()};
    return cost->Evaluate(params, r->data(), jacobians);
  };
  std::vector<double> r1, j1, r2, j2;
  ASSERT_TRUE(evaluate(&r1, &j1));
  EXPECT_EQ(counter.jacobians.load(), 1);
  ASSERT_TRUE(evaluate(&r2, &j2));
  EXPECT_EQ(counter.jacobians.load(), 1);
  EXPECT_EQ(r1, r2);
  EXPECT_EQ(j1, j2);
  // Residual-only: simulated (the guard's one-direction Jet), the memory kept.
  std::vector<double> r_only(m);
  const double* params[] = {theta.data()};
  ASSERT_TRUE(cost->Evaluate(params, r_only.data(), nullptr));
  EXPECT_EQ(counter.simulations.load(), 1);
  ASSERT_TRUE(evaluate(&r2, &j2));
  EXPECT_EQ(counter.jacobians.load(), 1);
  // Another point.
  theta[0] += 1e-3;
  ASSERT_TRUE(evaluate(&r2, &j2));
  EXPECT_EQ(counter.jacobians.load(), 2);
  EXPECT_NE(r1, r2);
  theta[0] -= 1e-3;
  ASSERT_TRUE(evaluate(&r2, &j2));
  EXPECT_EQ(counter.jacobians.load(), 3);
  EXPECT_EQ(r1, r2);
  // The first channel's σ doubled in place for every sample: evaluated
  // again, its residuals and their rows halved (the weights are 1/σ_k).
  const FittedChannel& first = e.fitted[0];
  const size_t rows = e.Measured(first.channel).size();
  sigma[0].assign(rows, 2.0 * first.sigma);
  ASSERT_TRUE(evaluate(&r2, &j2));
  EXPECT_EQ(counter.jacobians.load(), 4);
  for (size_t k = 0; k < rows; k += 97) {
    EXPECT_DOUBLE_EQ(r2[k], 0.5 * r1[k]) << k;
    EXPECT_DOUBLE_EQ(j2[k * n], 0.5 * j1[k * n]) << k;
  }
  EXPECT_EQ(r2[rows], r1[rows]);  // the next channel's unchanged
}

// The stacked Jacobian simulates the records side by side on
// job.solver.threads threads, each into its own rows: on one thread and on
// two it is the same, bit for bit, and its rows are each record's own
// Jacobian (the job alone with that record) in record order.
TEST(StackedJacobianTest, SideBySideIsTheSameAsOneAfterTheOther) {
  FitJob job = FrontEndJob();
  ASSERT_GE(job.problem.experiments.size(), 2u);
  job.problem.solver.threads = 1;
  Eigen::VectorXd r1, r2;
  Eigen::MatrixXd j1, j2;
  StackedJacobian(job.problem, &r1, &j1);
  job.problem.solver.threads = 2;
  StackedJacobian(job.problem, &r2, &j2);
  ASSERT_EQ(r1.size(), r2.size());
  ASSERT_EQ(j1.rows(), j2.rows());
  ASSERT_EQ(j1.cols(), j2.cols());
  EXPECT_TRUE((r1.array() == r2.array()).all());
  EXPECT_TRUE((j1.array() == j2.array()).all());
  Eigen::Index row = 0;
  for (const FitExperiment& e : job.problem.experiments) {
    EstimationProblem alone = job.problem;
    alone.experiments = {e};
    Eigen::VectorXd r;
    Eigen::MatrixXd j;
    StackedJacobian(alone, &r, &j);
    EXPECT_TRUE((r.array() == r2.segment(row, r.size()).array()).all()) << e.name;
    EXPECT_TRUE((j.array() == j2.middleRows(row, j.rows()).array()).all()) << e.name;
    row += r.size();
  }
  EXPECT_EQ(row, r2.size());
}

}  // namespace
}  // namespace axis
