// Uncertainty beyond Gauss–Newton (estimation/uncertainty.h): likelihood-ratio
// intervals against closed forms on a quadratic and on a kinked cost, the
// scan reporting a lower point, the residual bootstrap against the
// Gauss–Newton errors on the paper job, and the job key's strict loader.
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "common/statistics.h"
#include "estimation/covariance.h"
#include "estimation/fit.h"
#include "estimation/fit_result.h"
#include "estimation/uncertainty.h"
#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "estimation/solver_settings.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;
const std::vector<double> kSteps = {0.5, 1, 1.5, 2, 3, 4, 6, 8, 12, 16};

// LikelihoodRatioIntervals at kSteps on one thread.
RatioScan Ratio(ceres::Problem* problem, std::vector<double> lower, std::vector<double> upper,
                const Eigen::MatrixXd& cov, int n_free, double t975, double residual_variance,
                std::vector<double>* theta) {
  RatioScanOptions options;
  options.basis = {std::move(lower), std::move(upper), cov, n_free, t975, residual_variance};
  options.steps = kSteps;
  options.threads = 1;
  return LikelihoodRatioIntervals(problem, options, theta);
}

// r = A·θ − b, two parameters, three residuals: a quadratic cost.
struct Linear {
  template <typename T>
  bool operator()(const T* theta, T* r) const {
    r[0] = T(2.0) * theta[0] + T(1.0) * theta[1] - T(1.0);
    r[1] = T(0.5) * theta[0] - T(3.0) * theta[1] + T(2.0);
    r[2] = T(1.0) * theta[0] + T(1.0) * theta[1];
    return true;
  }
};

// One residual with a kink at x = 0: slope 1 above, 1/4 below; and from
// x = 6 on it falls again, reaching 0 at x = 12 — a second valley; the
// second residual tilts it so that x = 12 is lower than x = 0.
struct Kinked {
  template <typename T>
  bool operator()(const T* x, T* r) const {
    if (x[0] >= T(6.0)) {
      r[0] = T(12.0) - x[0];
    } else if (x[0] >= T(0.0)) {
      r[0] = x[0];
    } else {
      r[0] = T(0.25) * x[0];
    }
    r[1] = T(0.01) * (T(1.0) - x[0] / T(12.0));
    return true;
  }
};

// On a quadratic cost the likelihood-ratio ends are θ* ± t·√C_kk, the
// Gauss–Newton interval; the scan interpolates linearly between steps 1.5
// and 2 of the parabola ½s², which puts the end at 1.954 instead of t
// (≤ 0.01 standard deviations off).
TEST(LikelihoodRatioTest, QuadraticCostGivesTheGaussNewtonInterval) {
  std::vector<double> theta = {0.0, 0.0};
  ceres::Problem problem;
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Linear, 3, 2>(new Linear),
                           nullptr, theta.data());
  ceres::Solver::Options options;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  Eigen::Matrix<double, 3, 2> a;
  a << 2.0, 1.0, 0.5, -3.0, 1.0, 1.0;
  const Eigen::MatrixXd cov = (a.transpose() * a).inverse();
  const double t = StudentTQuantile975(1000);
  const std::vector<double> lower = {-100, -100}, upper = {100, 100};
  const std::vector<double> centre = theta;
  const RatioScan scan = Ratio(&problem, lower, upper, cov, 2, t, 1.0, &theta);
  ASSERT_EQ(scan.intervals.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    const double sd = std::sqrt(cov(k, k));
    EXPECT_NEAR(scan.intervals[k].low, centre[k] - t * sd, 0.01 * sd) << k;
    EXPECT_NEAR(scan.intervals[k].high, centre[k] + t * sd, 0.01 * sd) << k;
    EXPECT_TRUE(scan.intervals[k].bounded_low);
    EXPECT_TRUE(scan.intervals[k].bounded_high);
  }
  EXPECT_EQ(theta, centre);  // left where it was
  EXPECT_GE(scan.lowest_cost, summary.final_cost - 1e-12);
}

// At the kink x* = 0 the Jacobian is the upper slope (σ = 1), but the cost
// below is 16 times flatter: the low end is where ½(x/4)² = ½t², x = −4t
// (to the linear interpolation between steps 6 and 8: 0.03 standard
// deviations), the high end t. The second valley at x = 12 is reported as
// a lower point.
TEST(LikelihoodRatioTest, KinkedCostFollowsTheFlatSideAndReportsTheLowerValley) {
  std::vector<double> x = {0.0};
  ceres::Problem problem;
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Kinked, 2, 1>(new Kinked),
                           nullptr, x.data());
  const double t = 1.96;
  Eigen::MatrixXd cov(1, 1);
  cov(0, 0) = 1.0;
  const RatioScan scan = Ratio(&problem, {-100}, {100}, cov, 1, t, 1.0, &x);
  ASSERT_EQ(scan.intervals.size(), 1u);
  EXPECT_NEAR(scan.intervals[0].low, -4.0 * t, 0.05);
  // Above: the first crossing is at t, but beyond the bump the cost falls
  // back below the threshold at x = 12 (and rises again by 16), so the
  // furthest crossing is past 12.
  EXPECT_GT(scan.intervals[0].high, 12.0);
  EXPECT_LT(scan.intervals[0].high, 16.0);
  EXPECT_NEAR(scan.lowest_point[0], 12.0, 1e-12);
  EXPECT_LT(scan.lowest_cost, 0.5 * 0.01 * 0.01);
}

// A not-finite covariance gives no intervals (the fit then reports
// Gauss–Newton).
TEST(LikelihoodRatioTest, NotFiniteCovarianceGivesNothing) {
  std::vector<double> x = {0.0};
  ceres::Problem problem;
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Kinked, 2, 1>(new Kinked),
                           nullptr, x.data());
  Eigen::MatrixXd cov(1, 1);
  cov(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(Ratio(&problem, {-100}, {100}, cov, 1, 1.96, 1.0, &x).intervals.empty());
}

// Exponential decay y = a·exp(−b·t) + e at 7 times, σ = 0.05: the model
// is linear in a, so the profile over b has the closed form
// P(b) = ½Σ(a*(b)·E_i − y_i)²/σ² with E_i = exp(−b·t_i), a*(b) = ΣE_i·y_i/ΣE_i².
struct Decay {
  static constexpr int kN = 7;
  static constexpr double kT[kN] = {0.0, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0};
  static constexpr double kE[kN] = {0.05, -0.08, 0.03, 0.06, -0.04, 0.02, -0.05};
  static constexpr double kSigma = 0.05;
  static double Y(int i) { return std::exp(-kT[i]) + kE[i]; }
  template <typename T>
  bool operator()(const T* theta, T* r) const {
    using std::exp;
    for (int i = 0; i < kN; ++i) {
      r[i] = (theta[0] * exp(-theta[1] * T(kT[i])) - T(Y(i))) / T(kSigma);
    }
    return true;
  }
  static double Profile(double b) {
    double ey = 0.0, ee = 0.0;
    for (int i = 0; i < kN; ++i) {
      const double e = std::exp(-b * kT[i]);
      ey += e * Y(i);
      ee += e * e;
    }
    const double a = ey / ee;
    double cost = 0.0;
    for (int i = 0; i < kN; ++i) {
      const double r = (a * std::exp(-b * kT[i]) - Y(i)) / kSigma;
      cost += 0.5 * r * r;
    }
    return cost;
  }
};

// Covariance (JᵀJ)⁻¹ of `problem` at its current point (one block of n).
Eigen::MatrixXd CovarianceAt(ceres::Problem* problem, int n) {
  ceres::CRSMatrix crs;
  problem->Evaluate(ceres::Problem::EvaluateOptions(), nullptr, nullptr, nullptr, &crs);
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r) {
    for (int k = crs.rows[r]; k < crs.rows[r + 1]; ++k) j(r, crs.cols[k]) = crs.values[k];
  }
  EXPECT_EQ(j.cols(), n);
  return (j.transpose() * j).inverse();
}

ceres::Solver::Options RefitOptions() {
  ceres::Solver::Options o;
  o.function_tolerance = 1e-12;
  o.parameter_tolerance = 1e-12;
  o.gradient_tolerance = 1e-14;
  return o;
}

// ProfileLikelihoodIntervals with RefitOptions and the given settings.
ProfileScan Profile(ceres::Problem* problem, std::vector<double> lower,
                    std::vector<double> upper, const Eigen::MatrixXd& cov, int n_free,
                    double t975, double residual_variance, double lowest_allowed,
                    bool stop_at_lower, std::vector<double>* theta) {
  ProfileOptions options;
  options.basis = {std::move(lower), std::move(upper), cov, n_free, t975, residual_variance};
  options.solver = RefitOptions();
  options.lowest_allowed = lowest_allowed;
  options.stop_at_lower = stop_at_lower;
  return ProfileLikelihoodIntervals(problem, options, theta);
}

// On a quadratic cost the profile is the parabola itself: its ends are
// θ* ± t·√C_kk, the Gauss–Newton interval (regula falsi on √rise is exact
// on a line; 1e-6 standard deviations for the solver's tolerances).
TEST(ProfileTest, QuadraticCostGivesTheGaussNewtonInterval) {
  std::vector<double> theta = {0.0, 0.0};
  ceres::Problem problem;
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Linear, 3, 2>(new Linear),
                           nullptr, theta.data());
  ceres::Solver::Summary summary;
  ceres::Solve(RefitOptions(), &problem, &summary);
  const Eigen::MatrixXd cov = CovarianceAt(&problem, 2);
  const double t = StudentTQuantile975(1000);
  const std::vector<double> centre = theta;
  const ProfileScan scan = Profile(
      &problem, {-100, -100}, {100, 100}, cov, 2, t, 1.0,
      summary.final_cost - 1e-9, true, &theta);
  ASSERT_EQ(scan.intervals.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    const double sd = std::sqrt(cov(k, k));
    EXPECT_NEAR(scan.intervals[k].low, centre[k] - t * sd, 1e-6 * sd) << k;
    EXPECT_NEAR(scan.intervals[k].high, centre[k] + t * sd, 1e-6 * sd) << k;
    EXPECT_TRUE(scan.intervals[k].bounded_low);
    EXPECT_TRUE(scan.intervals[k].bounded_high);
  }
  EXPECT_EQ(theta, centre);
  EXPECT_FALSE(problem.HasManifold(theta.data()));
  EXPECT_GT(scan.solves, 0);
}

// Exponential decay: the interval of b against the closed-form profile,
// located by bisection. The ends are found to within 5 % of the threshold
// in rise, i.e. ≈ 2.5 % of the half-width in b; the Gauss–Newton ends
// differ from the profile's by more than that (checked), so the test tells
// the profile from the curvature.
TEST(ProfileTest, ExponentialDecayMatchesTheClosedFormProfile) {
  std::vector<double> theta = {1.0, 1.0};
  ceres::Problem problem;
  problem.AddResidualBlock(
      new ceres::AutoDiffCostFunction<Decay, Decay::kN, 2>(new Decay), nullptr,
      theta.data());
  ceres::Solver::Summary summary;
  ceres::Solve(RefitOptions(), &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable());
  const Eigen::MatrixXd cov = CovarianceAt(&problem, 2);
  const double t = 1.96;
  const double b_star = theta[1], c0 = summary.final_cost;
  const double threshold = 0.5 * t * t;
  EXPECT_NEAR(Decay::Profile(b_star), c0, 1e-9);
  const auto crossing = [&](double far) {
    double in = b_star, out = far;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (in + out);
      (Decay::Profile(mid) - c0 > threshold ? out : in) = mid;
    }
    return 0.5 * (in + out);
  };
  const double low = crossing(b_star - 0.99 * b_star), high = crossing(3.0 * b_star);
  ASSERT_GT(Decay::Profile(3.0 * b_star) - c0, threshold);
  const ProfileScan scan = Profile(
      &problem, {-100, 1e-3}, {100, 100}, cov, 2, t, 1.0,
      c0 - 1e-9, true, &theta);
  ASSERT_EQ(scan.intervals.size(), 2u);
  const double half = 0.5 * (high - low), sd = std::sqrt(cov(1, 1));
  std::cout << "profile of b: [" << low << ", " << high << "], tool ["
            << scan.intervals[1].low << ", " << scan.intervals[1].high
            << "], Gauss–Newton [" << b_star - t * sd << ", " << b_star + t * sd << "]\n";
  EXPECT_NEAR(scan.intervals[1].low, low, 0.025 * half);
  EXPECT_NEAR(scan.intervals[1].high, high, 0.025 * half);
  EXPECT_GT(std::max(std::abs(b_star - t * sd - low), std::abs(b_star + t * sd - high)),
            0.05 * half);
}

// r0 = g(x) with two valleys: |x| near 0 and |x − 8| + 0.5 from x = 4 on;
// r1 = y − x/2 (y follows x). The profile over x is ½g(x)²; its 95 % set
// (½g² ≤ ½·1.96²) is [−1.96, 1.96] ∪ [6.54, 9.46].
struct Valleys {
  template <typename T>
  bool operator()(const T* theta, T* r) const {
    const T& x = theta[0];
    if (x < T(4.0)) {
      r[0] = x < T(0.0) ? -x : x;
    } else {
      r[0] = (x < T(8.0) ? T(8.0) - x : x - T(8.0)) + T(0.5);
    }
    r[1] = theta[1] - T(0.5) * x;
    return true;
  }
};

// The profile crosses a bump (above the threshold at 3.5) into a second
// valley still below it (at 7.06): the interval is the hull of the set, its
// high end at 9.46 (g is linear there, so regula falsi on √rise is exact to
// the solver's tolerance); the low end stays at −1.96.
TEST(ProfileTest, SecondValleyBelowTheThresholdWidensTheInterval) {
  std::vector<double> theta = {0.0, 0.0};
  ceres::Problem problem;
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Valleys, 2, 2>(new Valleys),
                           nullptr, theta.data());
  // Gauss–Newton covariance at (0, 0) from the right-hand slope, scaled so
  // that √C_xx = 0.9: the probed points are 1.76, 3.53, 7.06 and 14.1.
  Eigen::Matrix2d jtj;
  jtj << 1.25, -0.5, -0.5, 1.0;
  const Eigen::MatrixXd cov = 0.81 * jtj.inverse();
  const ProfileScan scan = Profile(
      &problem, {-100, -100}, {100, 100}, cov, 1, 1.96, 1.0, -1e-9,
      true, &theta);
  ASSERT_EQ(scan.intervals.size(), 1u);
  EXPECT_NEAR(scan.intervals[0].low, -1.96, 1e-6);
  EXPECT_NEAR(scan.intervals[0].high, 8.0 + 1.96 - 0.5, 1e-6);
  EXPECT_TRUE(scan.intervals[0].bounded_high);
}

// r0 = x/3, so the profile over x is ½(x/3)², its 95 % set [−5.88, 5.88];
// r1 holds y at 0 for x < 3 and at 10 for x > 5; for 3 ≤ x ≤ 5 it has two
// minima, y = 10 (r1 = 0) and a local one at y = 0 (½r1² = 1.5, zero
// gradient: a refit started at y = 0 stays there).
struct LocalMinimum {
  template <typename T>
  bool operator()(const T* theta, T* r) const {
    using std::sqrt;
    const T& x = theta[0];
    const T& y = theta[1];
    r[0] = x / T(3.0);
    if (x < T(3.0)) {
      r[1] = y;
    } else if (x > T(5.0) || y >= T(5.0)) {
      r[1] = y - T(10.0);
    } else {
      r[1] = sqrt(y * y + T(3.0));
    }
    return true;
  }
};

// With √C_xx = 1 the probed points are 1.96, 3.92, 7.84: at 3.92 the refits
// from the point below and from the estimate (both y = 0) stop in the local
// minimum, rise 0.85 + 1.5 > 1.92; the one from the solved point at 7.84
// (y = 10) finds the profile, 0.85, so the end lies between 3.92 and 7.84,
// at 5.88 (√rise is linear in x there, so regula falsi is exact to the
// solver's tolerance), not below 3.92.
TEST(ProfileTest, RefitStuckInALocalMinimumIsRetriedFromOutside) {
  std::vector<double> theta = {0.0, 0.0};
  ceres::Problem problem;
  problem.AddResidualBlock(
      new ceres::AutoDiffCostFunction<LocalMinimum, 2, 2>(new LocalMinimum), nullptr,
      theta.data());
  const Eigen::MatrixXd cov = Eigen::Matrix2d::Identity();
  const ProfileScan scan = Profile(
      &problem, {-100, -100}, {100, 100}, cov, 1, 1.96, 1.0, -1e-9,
      true, &theta);
  ASSERT_EQ(scan.intervals.size(), 1u);
  EXPECT_NEAR(scan.intervals[0].low, -3.0 * 1.96, 1e-6);
  EXPECT_NEAR(scan.intervals[0].high, 3.0 * 1.96, 1e-6);
  EXPECT_TRUE(scan.intervals[0].bounded_low);
  EXPECT_TRUE(scan.intervals[0].bounded_high);
}

// A refit that ends below the estimate's cost (here the estimate's second
// entry is one standard deviation off its optimum) stops the search with no
// intervals and hands back the lower point; without the stop the intervals
// are computed and the lower point is still reported.
TEST(ProfileTest, LowerCostStopsTheSearch) {
  std::vector<double> theta = {0.0, 0.0};
  ceres::Problem problem;
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Linear, 3, 2>(new Linear),
                           nullptr, theta.data());
  ceres::Solver::Summary summary;
  ceres::Solve(RefitOptions(), &problem, &summary);
  const Eigen::MatrixXd cov = CovarianceAt(&problem, 2);
  theta[1] += std::sqrt(cov(1, 1));
  const double c0 = CostAt(&problem, theta, 1, &theta);
  const ProfileScan stopped = Profile(
      &problem, {-100, -100}, {100, 100}, cov, 2, 1.96, 1.0,
      c0 - 1e-6, true, &theta);
  EXPECT_TRUE(stopped.intervals.empty());
  EXPECT_LT(stopped.lowest_cost, c0 - 1e-6);
  EXPECT_NEAR(CostAt(&problem, stopped.lowest_point, 1, &theta), stopped.lowest_cost, 1e-12);
  const ProfileScan full = Profile(
      &problem, {-100, -100}, {100, 100}, cov, 2, 1.96, 1.0,
      c0 - 1e-6, false, &theta);
  EXPECT_EQ(full.intervals.size(), 2u);
  EXPECT_LT(full.lowest_cost, c0 - 1e-6);
  EXPECT_FALSE(problem.HasManifold(theta.data()));
}

std::string PaperJobYaml(const std::string& extra) {
  std::ostringstream y;
  y << "model: " << kRoot << "/configs/axes/x_axis.yaml\n"
    << "free:\n"
    << "  V_L: {initial: 3.0, lower: 0.5, upper: 20}\n"
    << "  B_a: {initial: 175, lower: 10, upper: 2000}\n"
    << "  b_g: {initial: 1700, lower: 100, upper: 20000}\n"
    << "  k_g: {initial: 4.4e6, lower: 5.0e5, upper: 5.0e7}\n"
    << "  T_p: {initial: 0.045, lower: 0.005, upper: 1.0}\n"
    << "experiments:\n";
  for (const char* name : {"x_step_10V", "x_step_4V"}) {
    y << "  - name: " << name << "\n"
      << "    data: " << kRoot << "/testdata/" << name << ".csv\n"
      << "    channels: {u: u, a: a, tach: tach}\n"
      << "    input: {column: u}\n"
      << "    fit: {a: 0.02, tach: 0.005}\n"
      << "    window: [0, 0.3]\n";
  }
  y << "solver: {threads: 2}\n" << extra;
  return y.str();
}

FitJob Job(const std::string& extra) {
  return ParseFitJob(YAML::Load(PaperJobYaml(extra)), "job.yaml", kRoot);
}

// CovarianceOfJacobian (the R-SVD) against the normal equations solved
// independently: on a paper-sized Jacobian (1204 × 5, singular values
// within a factor of about 10) (JᵀJ)⁻¹ by Cholesky (LDLT); both round at
// about κ(JᵀJ)·1e-16 ≈ 1e-14 of the largest entry, so 1e-10 of it is far
// above their difference. With a column repeated (rank 5 of 6) the
// pseudo-inverse over JᵀJ's non-zero eigenvalues (SelfAdjointEigenSolver):
// a plain inverse would be far off or not finite there. And a Jacobian
// with fewer rows than columns takes the SVD of J itself.
Eigen::MatrixXd SmoothJacobian(int rows, int cols) {
  Eigen::MatrixXd j(rows, cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      j(r, c) = (c + 1.0) * std::sin(0.013 * (r + 1) * (c + 1)) + (r % cols == c ? 1.0 : 0.0);
    }
  }
  return j;
}

Eigen::MatrixXd PseudoInverseOf(const Eigen::MatrixXd& jtj) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(jtj);
  const double largest = eig.eigenvalues().maxCoeff();
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(jtj.rows());
  for (Eigen::Index i = 0; i < jtj.rows(); ++i) {
    if (eig.eigenvalues()[i] > 1e-12 * largest) inverse[i] = 1.0 / eig.eigenvalues()[i];
  }
  return eig.eigenvectors() * inverse.asDiagonal() * eig.eigenvectors().transpose();
}

TEST(CovarianceTest, RSvdAgreesWithTheNormalEquations) {
  const Eigen::MatrixXd j = SmoothJacobian(1204, 5);
  const Eigen::MatrixXd jtj = j.transpose() * j;
  const Eigen::MatrixXd expected = jtj.ldlt().solve(Eigen::MatrixXd::Identity(5, 5));
  const Eigen::MatrixXd got = CovarianceOfJacobian(j);
  EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff());
}

TEST(CovarianceTest, RankDeficientJacobianGivesThePseudoInverse) {
  Eigen::MatrixXd j(1204, 6);
  j << SmoothJacobian(1204, 5), SmoothJacobian(1204, 5).col(2);
  const Eigen::MatrixXd expected = PseudoInverseOf(j.transpose() * j);
  const Eigen::MatrixXd got = CovarianceOfJacobian(j);
  ASSERT_TRUE(got.allFinite());
  EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-8 * expected.cwiseAbs().maxCoeff());
  // The repeated pair shares its variance: columns 2 and 5 alike.
  EXPECT_NEAR(got(2, 2), got(5, 5), 1e-8 * expected.cwiseAbs().maxCoeff());
}

// The threshold itself: J = U·diag(s)·Vᵀ with U, V orthonormal (QR of
// fixed pseudo-random matrices) and s = (1, 0.5, 0.1, 3e-7, 5e-8). The
// singular value 3e-7 lies above √kMinReciprocalCondition = 1e-7 of the
// largest and counts (1/s² ≈ 1.1e13), 5e-8 lies below and is dropped (it
// would add 4e14). Rounding moves each singular value by about 1e-16, so
// 3e-7's 1/s² by about 1e-9 relative: 1e-6 of the largest entry holds.
TEST(CovarianceTest, SingularValuesBelowTheThresholdAreDropped) {
  const auto orthonormal = [](int rows, int cols, double seed) {
    Eigen::MatrixXd a(rows, cols);
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) a(r, c) = std::sin(seed * (r + 1) + 1.7 * (c + 1) * (r + 3));
    }
    return Eigen::MatrixXd(Eigen::HouseholderQR<Eigen::MatrixXd>(a).householderQ() *
                           Eigen::MatrixXd::Identity(rows, cols));
  };
  const Eigen::MatrixXd u = orthonormal(300, 5, 0.37);
  const Eigen::MatrixXd v = orthonormal(5, 5, 1.13);
  Eigen::VectorXd s(5);
  s << 1.0, 0.5, 0.1, 3e-7, 5e-8;
  const Eigen::MatrixXd j = u * s.asDiagonal() * v.transpose();
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(5, 5);
  for (int i = 0; i < 4; ++i) expected += v.col(i) * v.col(i).transpose() / (s[i] * s[i]);
  const Eigen::MatrixXd got = CovarianceOfJacobian(j);
  EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-6 * expected.cwiseAbs().maxCoeff());
}

TEST(CovarianceTest, WideJacobianAndZeroJacobian) {
  const Eigen::MatrixXd j = SmoothJacobian(3, 5);  // rank 3 of 5
  const Eigen::MatrixXd expected = PseudoInverseOf(j.transpose() * j);
  const Eigen::MatrixXd got = CovarianceOfJacobian(j);
  EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-8 * expected.cwiseAbs().maxCoeff());
  EXPECT_FALSE(CovarianceOfJacobian(Eigen::MatrixXd::Zero(10, 2)).allFinite());
  Eigen::MatrixXd not_finite = SmoothJacobian(20, 3);
  not_finite(7, 1) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(CovarianceOfJacobian(not_finite).allFinite());
}

// Residual bootstrap on the paper's step records (noisy, white residuals,
// first 0.3 s): 8 refits. The bootstrap standard deviation estimates the
// same spread as Gauss–Newton on this smooth record; with 8 replicates its
// ratio to the truth lies in [0.45, 1.5] with 98 % probability (√(χ²₇/7)),
// so each parameter's bootstrap error must be within a factor [0.4, 2] of
// the Gauss–Newton one, and the percentile interval must contain the
// estimate.
TEST(BootstrapTest, PaperStepRecordsAgreeWithGaussNewton) {
  FitJob job =
      Job("uncertainty: {method: likelihood_ratio, bootstrap: 8, block: 1, seed: 3}\n");
  job.problem.solver.progress = false;
  FitResult result = FitParameters(job.problem);
  ASSERT_TRUE(std::isfinite(result.final_cost));
  EXPECT_EQ(result.uncertainty_method, "likelihood_ratio");
  ResidualBootstrap(job.problem, &result, nullptr);
  EXPECT_EQ(result.bootstrap_replicates, 8);
  for (const ParameterEstimate& p : result.parameters) {
    if (!p.free) continue;
    SCOPED_TRACE(p.name);
    const double ratio = p.std_error_bootstrap / p.std_error_gauss_newton;
    EXPECT_GT(ratio, 0.4);
    EXPECT_LT(ratio, 2.0);
    EXPECT_LE(p.bootstrap_low, p.value + 3.0 * p.std_error_gauss_newton);
    EXPECT_GE(p.bootstrap_high, p.value - 3.0 * p.std_error_gauss_newton);
    // On this smooth record the likelihood-ratio interval is the
    // Gauss–Newton one to the scan's interpolation (1 %) and the cost's
    // third-order terms.
    EXPECT_NEAR(p.std_error / p.std_error_gauss_newton, 1.0, 0.05);
  }
}

TEST(UncertaintyKeyTest, StrictLoader) {
  EXPECT_EQ(Job("").problem.uncertainty.method, UncertaintySettings::Method::kProfile);
  EXPECT_EQ(Job("uncertainty: {method: gauss_newton}\n").problem.uncertainty.method,
            UncertaintySettings::Method::kGaussNewton);
  EXPECT_EQ(Job("uncertainty: {method: likelihood_ratio}\n").problem.uncertainty.method,
            UncertaintySettings::Method::kLikelihoodRatio);
  EXPECT_EQ(Job("uncertainty: {method: profile}\n").problem.uncertainty.method,
            UncertaintySettings::Method::kProfile);
  for (const std::string bad :
       {"uncertainty: {method: profile_likelihood}\n", "uncertainty: {bootstrap: -1}\n",
        "uncertainty: {block: 0}\n", "uncertainty: {replicates: 3}\n"}) {
    try {
      Job(bad);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("uncertainty."), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace axis
