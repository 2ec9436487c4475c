#include "design/experiment_design.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/non_central_chi_squared.hpp>

#include "common/concurrency.h"
#include "common/format.h"
#include "discovery/candidates.h"
#include "discovery/discovery.h"
#include "estimation/at_estimate.h"
#include "estimation/experiment_cost.h"
#include "estimation/fit_result.h"
#include "estimation/stacked_jacobian.h"
#include "design/design_settings.h"
#include "estimation/estimation_problem.h"
#include "sim/channels.h"
#include "sim/config.h"
#include "io/csv.h"
#include "sim/dense_decompositions.h"
#include "sim/simulate.h"

namespace axis {
namespace {

using Clock = std::chrono::steady_clock;

// Rest before the first step of a step pair (s): the record shows the axis
// at rest, where Coulomb friction and a constant force differ.
constexpr double kRestBefore = 0.1;
constexpr double kTwoPi = 6.283185307179586;

std::string Num(double x, int digits = 4) { return FormatNumber(x, digits); }

// The family searched (see the header): levels as fractions of
// design.max_voltage, step durations as fractions of design.duration.
std::vector<DesignCandidate> Family(const DesignSettings& d) {
  std::vector<DesignCandidate> out;
  const double u = d.max_voltage;
  const double dur = d.duration;
  for (double level : {0.2, 0.4, 0.6, 0.8, 1.0}) {
    for (double fraction : {0.125, 0.25, 0.4}) {
      const double each = fraction * dur;
      DesignCandidate c;
      c.family = "steps";
      c.description = "steps +-" + Num(level * u, 3) + " V, " + Num(each, 3) + " s each way";
      c.input.kind = InputSignal::Kind::kTable;
      c.input.hold = true;
      c.input.times = {0.0, kRestBefore, kRestBefore + each, kRestBefore + 2.0 * each};
      c.input.values = {0.0, level * u, -level * u, 0.0};
      c.level = level * u;
      out.push_back(c);
    }
  }
  for (double level : {0.25, 0.5, 0.75, 1.0}) {
    for (double f : {0.5, 1.0, 2.0, 4.0}) {
      DesignCandidate c;
      c.family = "sine";
      c.description = "sine " + Num(level * u, 3) + " V, " + Num(f, 3) + " Hz";
      c.input.kind = InputSignal::Kind::kSine;
      c.input.amplitude = level * u;
      c.input.frequency = f;
      c.level = level * u;
      out.push_back(c);
    }
  }
  for (double level : {0.25, 0.5, 0.75, 1.0}) {
    for (double f1 : {5.0, 20.0}) {
      DesignCandidate c;
      c.family = "chirp";
      c.description = "chirp " + Num(level * u, 3) + " V, 0.2 -> " + Num(f1, 3) + " Hz";
      c.input.kind = InputSignal::Kind::kChirp;
      c.input.amplitude = level * u;
      c.input.f0 = 0.2;
      c.input.f1 = f1;
      c.input.sweep_time = dur;
      c.level = level * u;
      out.push_back(c);
    }
  }
  for (double level : {0.25, 0.5, 0.75, 1.0}) {
    for (double bit : {0.05, 0.1, 0.2}) {
      DesignCandidate c;
      c.family = "prbs";
      c.description = "PRBS +-" + Num(level * u, 3) + " V, bit " + Num(bit, 3) + " s";
      c.input = MakePrbs(level * u, 0.0, bit, 10, 1, dur);
      c.level = level * u;
      c.bit_time = bit;
      out.push_back(c);
    }
  }
  return out;
}

// The samples at 0, period, … up to `duration` (round-off tolerant).
long SampleCount(double duration, double period) {
  return static_cast<long>(std::floor(duration / period + 1e-9)) + 1;
}

// `shape` (m) sampled at every multiple of `period` up to `duration`: a
// reference position table read by linear interpolation, so that its CSV
// (t, x_ref at the same instants) replays it exactly.
template <typename Shape>
InputSignal SampledReference(const Shape& shape, double duration, double period) {
  InputSignal s;
  s.kind = InputSignal::Kind::kTable;
  const long n = SampleCount(duration, period);
  for (long k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * period;
    s.times.push_back(t);
    s.values.push_back(shape(t));
  }
  return s;
}

// The closed-loop family (see the header): reference positions about the
// travel's centre `c` within its half-width `half`, as sampled tables.
std::vector<DesignCandidate> ClosedLoopFamily(const DesignSettings& d, double period) {
  std::vector<DesignCandidate> out;
  const double c = 0.5 * (d.travel_low + d.travel_high);
  const double half = 0.5 * (d.travel_high - d.travel_low);
  const double dur = d.duration;
  const double dwell = 0.05 * dur;
  for (double fraction : {0.3, 0.6, 0.9}) {
    for (double move : {0.075, 0.15}) {
      // Rest, to c + D in T, dwell, to c − D in 2T, dwell, back to c in T:
      // a linearly interpolated table, then sampled.
      const double dist = fraction * half;
      const double t_move = move * dur;
      InputSignal path;
      path.kind = InputSignal::Kind::kTable;
      path.times = {0.0,
                    kRestBefore,
                    kRestBefore + t_move,
                    kRestBefore + t_move + dwell,
                    kRestBefore + 3.0 * t_move + dwell,
                    kRestBefore + 3.0 * t_move + 2.0 * dwell,
                    kRestBefore + 4.0 * t_move + 2.0 * dwell};
      path.values = {c, c, c + dist, c + dist, c - dist, c - dist, c};
      DesignCandidate m;
      m.family = "moves";
      m.description = "moves +-" + Num(dist, 3) + " m, " + Num(t_move, 3) + " s per " +
                      Num(dist, 3) + " m";
      m.input = SampledReference([&](double t) { return path.Evaluate(t); }, dur, period);
      m.level = dist;
      out.push_back(m);
    }
  }
  for (double fraction : {0.3, 0.6, 0.9}) {
    for (double f : {0.5, 1.0, 2.0, 4.0}) {
      DesignCandidate s;
      s.family = "sine";
      s.description = "sine +-" + Num(fraction * half, 3) + " m, " + Num(f, 3) + " Hz";
      s.input = SampledReference(
          [&](double t) {
            return t < kRestBefore
                       ? c
                       : c + fraction * half * std::sin(kTwoPi * f * (t - kRestBefore));
          },
          dur, period);
      s.level = fraction * half;
      out.push_back(s);
    }
  }
  for (double fraction : {0.3, 0.6, 0.9}) {
    for (double bit : {0.05, 0.1, 0.2}) {
      const InputSignal prbs = MakePrbs(fraction * half, c, bit, 10, 1, dur);
      DesignCandidate s;
      s.family = "prbs";
      s.description = "PRBS +-" + Num(fraction * half, 3) + " m, bit " + Num(bit, 3) + " s";
      s.input = SampledReference(
          [&](double t) { return t < kRestBefore ? c : prbs.Evaluate(t - kRestBefore); }, dur,
          period);
      s.level = fraction * half;
      s.bit_time = bit;
      out.push_back(s);
    }
  }
  return out;
}

// The proposed record as a fitted experiment of `job` (channels, σ, step,
// output period of its first experiment), from rest at x0; its measured
// values are zeros (only Jacobians are taken from it).
FitExperiment ProposedExperiment(const EstimationProblem& job, const InputSignal& input, double duration,
                                 double x0) {
  const FitExperiment& ref = job.experiments.front();
  FitExperiment e;
  e.name = "proposed";
  e.data_path = "(proposed)";
  if (ref.drive.closed_loop) {
    // The first experiment's controller, the candidate as its reference.
    e.drive.closed_loop = true;
    e.drive.controller = ref.drive.controller;
    e.drive.reference.kind = Reference::Kind::kTable;
    e.drive.reference.table = input;
    e.drive.has_supply = ref.drive.has_supply;  // a firmware loop's duty into volts
    e.drive.supply = ref.drive.supply;
  } else {
    e.drive.input = input;
  }
  e.options = ref.options;
  const double period = ref.options.output_period;
  const long n = SampleCount(duration, period);
  e.options.duration = period * static_cast<double>(n - 1);
  for (long k = 0; k < n; ++k) e.t.push_back(static_cast<double>(k) * period);
  e.fitted = ref.fitted;
  for (const FittedChannel& f : ref.fitted) {
    e.measured_channels.push_back(f.channel);
    e.measured.emplace_back(n, 0.0);
  }
  // At rest, the motor at the load's position in either coupling (in rigid
  // coupling what simulate-axis's ConsistentInitialState makes of the
  // written file; a motor encoder reads y2).
  e.initial_state[0] = x0;
  e.initial_state[2] = x0 / job.model.params.r_g;
  return e;
}

// Position range of `model` driven by `e`; false if the run is not finite.
bool Travel(const AxisConfig& model, const FitExperiment& e, double* lo, double* hi) {
  SimulationOptions o = e.options;
  o.channels = {Channel::kX};
  const SimulationGrid grid = MakeGrid(o, e.drive);
  const Trace<double> trace = Simulate(model.structure, model.params, e.initial_state, e.drive, o, grid);
  if (!trace.finite) return false;
  const std::vector<double>& x = trace[Channel::kX];
  *lo = std::min(*lo, *std::min_element(x.begin(), x.end()));
  *hi = std::max(*hi, *std::max_element(x.begin(), x.end()));
  return true;
}

// ‖P⊥[F, B]·d‖²: what the columns F, B cannot absorb of d.
double Unabsorbed(const Eigen::MatrixXd& f, const Eigen::MatrixXd& b, const Eigen::VectorXd& d) {
  Eigen::MatrixXd both(f.rows(), f.cols() + b.cols());
  both << f, b;
  const Eigen::MatrixXd q = Basis(both);
  return (d - q * (q.transpose() * d)).squaredNorm();
}

Eigen::MatrixXd Stack(const Eigen::MatrixXd& top, const Eigen::MatrixXd& bottom) {
  Eigen::MatrixXd out(top.rows() + bottom.rows(), top.cols());
  out << top, bottom;
  return out;
}

// Relative standard errors s·sqrt(diag (JᵀJ)⁻¹) in value units over |value|.
std::vector<double> RelativeErrors(const EstimationProblem& job, const Eigen::MatrixXd& j, double s2) {
  const ParameterMap map(job.model.params, job.free, job.ties);
  const Eigen::MatrixXd info = j.transpose() * j;
  const Eigen::MatrixXd cov = SvdPseudoInverse(info, 1e-14) * s2;
  std::vector<double> out;
  for (int k = 0; k < map.num_free(); ++k) {
    const double value = job.free[k].initial;
    const double theta = map.ToInternal(k, value);
    const double se = std::abs(map.Derivative(k, theta)) * std::sqrt(std::max(0.0, cov(k, k)));
    out.push_back(value != 0.0 ? se / std::abs(value) : std::numeric_limits<double>::infinity());
  }
  return out;
}

double LogDet(const Eigen::MatrixXd& j) {
  const Eigen::MatrixXd info = j.transpose() * j;
  const SymmetricEigen eig = SymmetricEigenOf(info);
  double out = 0.0;
  for (int k = 0; k < eig.values.size(); ++k) {
    out += std::log(std::max(eig.values[k], 1e-300));
  }
  return out;
}

double Critical(int dof, double level) {
  boost::math::chi_squared dist(dof);
  return boost::math::quantile(boost::math::complement(dist, level));
}

double Power(int dof, double noncentrality, double critical) {
  if (!(noncentrality > 0.0)) return 0.0;
  boost::math::non_central_chi_squared dist(dof, noncentrality);
  return boost::math::cdf(boost::math::complement(dist, critical));
}

// The YAML `input:` of a candidate (the experiment file's syntax,
// configs/README.md).
std::string InputYaml(const DesignCandidate& c) {
  std::ostringstream y;
  y << std::setprecision(10);
  const InputSignal& s = c.input;
  if (c.family == "steps") {
    y << "{type: table, interpolation: hold, points: [";
    for (size_t k = 0; k < s.times.size(); ++k) {
      y << (k ? ", " : "") << "[" << s.times[k] << ", " << s.values[k] << "]";
    }
    y << "]}";
  } else if (c.family == "sine") {
    y << "{type: sine, amplitude: " << s.amplitude << ", frequency: " << s.frequency << "}";
  } else if (c.family == "chirp") {
    y << "{type: chirp, amplitude: " << s.amplitude << ", f0: " << s.f0 << ", f1: " << s.f1
      << ", sweep_time: " << s.sweep_time << "}";
  } else {
    y << "{type: prbs, amplitude: " << c.level << ", bit_time: " << c.bit_time
      << ", order: 10, seed: 1}";
  }
  return y.str();
}

// The search of ProposeExperiment as a sequence of named steps, its state in
// members (as estimation/internal/fitter.h): the job at the estimates, the records'
// Jacobians, the pair to decide (else the parameters known too poorly), the
// criterion's columns, then every input of the family scored.
class ExperimentDesigner {
 public:
  // `job_in`, `result` and `progress` (may be null) must outlive it.
  ExperimentDesigner(const EstimationProblem& job_in, const FitResult& result,
                     const DesignSettings& design, const DiscoverySettings& discover,
                     std::ostream* progress)
      : job_in_(job_in), result_(result), progress_(progress), d_(design), discover_(discover) {}
  ExperimentDesigner(const ExperimentDesigner&) = delete;
  ExperimentDesigner& operator=(const ExperimentDesigner&) = delete;

  // Runs the search once (ProposeExperiment).
  ExperimentProposal Run();

 private:
  void Begin();            // the job at the estimates, the proposal's frame
  void RecordJacobians();  // the records' own
  void FindPair();         // the pair the discovery loop would stop on
  bool Needed();           // false (with the reason) if nothing is to decide
  void ChooseCriterion();  // T for the pair, else D
  void SetUpPair();        // T: the pair's columns, steps and models
  void ScoreFamily();      // every input of the family: feasible, then scored
  void ScoreCandidate(size_t k);
  void ShowCandidate(const DesignCandidate& c) const;
  const Candidate& Named(const std::string& name) const;
  ExperimentProposal Done();  // the wall time; the proposal

  const EstimationProblem& job_in_;
  const FitResult& result_;
  std::ostream* progress_;
  const DesignSettings& d_;
  const DiscoverySettings& discover_;
  Clock::time_point start_;
  ExperimentProposal p_;
  EstimationProblem job_;       // at the estimates
  double s2_ = 0.0;  // the residual variance (at least 1e-300)

  Eigen::VectorXd r_;
  Eigen::MatrixXd jf_;  // the records' Jacobian of the free parameters
  int m_ = 0;           // its rows

  std::vector<Candidate> candidates_;
  Ranking ranking_;
  double level_ = 0.0;
  const Score* score_a_ = nullptr;  // the pair, in ranking_.scores
  const Score* score_b_ = nullptr;
  bool t_design_ = false;
  double worst_ = 0.0;  // the largest finite relative standard error now

  Candidate ca_, cb_;
  Eigen::MatrixXd ja_old_, jb_old_;
  Eigen::VectorXd beta_a_, beta_b_;  // the score steps (T)
  EstimationProblem job_a_, job_b_;             // the current model plus a, plus b (T)

  std::vector<DesignCandidate> family_;
  size_t best_ = 0;  // family_.size() while none is feasible
  std::mutex best_mutex_;  // guards best_ and p_.rel_se_predicted in ScoreFamily
};

ExperimentProposal ExperimentDesigner::Run() {
  start_ = Clock::now();
  Begin();
  RecordJacobians();
  FindPair();
  if (!Needed()) return Done();
  ChooseCriterion();
  ScoreFamily();
  if (best_ == family_.size()) {
    p_.reason += "; no input of the family keeps the axis inside design.travel [" +
                 Num(d_.travel_low) + ", " + Num(d_.travel_high) + "] m";
    return Done();
  }
  p_.proposed = true;
  p_.best = family_[best_];
  return Done();
}

void ExperimentDesigner::Begin() {
  if (job_in_.experiments.empty()) {
    throw std::invalid_argument(job_in_.path + ": design: expected a job with a fitted "
                                "experiment, got none");
  }
  job_ = AtEstimate(job_in_, result_);
  p_.duration = d_.duration;
  p_.start_x = 0.5 * (d_.travel_low + d_.travel_high);
  p_.closed_loop = job_.experiments.front().drive.closed_loop;
  s2_ = std::max(result_.residual_variance, 1e-300);
}

void ExperimentDesigner::RecordJacobians() {
  StackedJacobian(job_, &r_, &jf_);
  m_ = static_cast<int>(r_.size());
}

// What to decide: a pair the data cannot tell apart, else a parameter known
// too poorly.
void ExperimentDesigner::FindPair() {
  candidates_ = ListCandidates(job_, discover_.candidates);
  ranking_ = RankCandidates(job_, candidates_, discover_.alpha);
  level_ = discover_.alpha / std::max<size_t>(1, candidates_.size());
  // The pair the loop stops on (discovery/internal/discovery_loop.cc DiscoveryLoop): the most
  // significant candidate with an indistinguishable twin of at most its
  // size, and that twin; not front-end terms of one channel, which the loop
  // refits together (SameChannelFrontEnd).
  for (const Score& s : ranking_.scores) {
    if (!(s.p_value < level_)) break;
    for (const auto& [a, b] : ranking_.indistinguishable) {
      const std::string other = a == s.name ? b : (b == s.name ? a : "");
      if (other.empty() || SameChannelFrontEnd(s.name, other)) continue;
      for (const Score& t : ranking_.scores) {
        if (t.name == other && t.dof <= s.dof) score_b_ = &t;
      }
    }
    if (score_b_ != nullptr) {
      score_a_ = &s;
      break;
    }
  }
}

bool ExperimentDesigner::Needed() {
  std::vector<double> rel_now = RelativeErrors(job_, jf_, s2_);
  for (const FreeParameter& f : job_.free) p_.names.push_back(f.name);
  p_.rel_se_now = rel_now;
  t_design_ = score_a_ != nullptr && score_b_ != nullptr;
  // Parameters at zero (an offset, a phase) have no relative error.
  double worst = 0.0;
  for (double x : rel_now) {
    if (std::isfinite(x)) worst = std::max(worst, x);
  }
  if (!t_design_ && !(d_.rel_se > 0.0 && worst > d_.rel_se)) {
    p_.reason = "no experiment needed: no pair of candidates the loop would stop on";
    p_.reason += d_.rel_se > 0.0 ? ", and every relative standard error is at most " +
                                       Num(d_.rel_se, 3) + " (largest " + Num(worst, 3) + ")"
                                 : " (design.rel_se not set)";
    return false;
  }
  worst_ = worst;
  return true;
}

void ExperimentDesigner::ChooseCriterion() {
  job_a_ = job_;
  job_b_ = job_;
  if (t_design_) {
    SetUpPair();
  } else {
    p_.criterion = "D-optimal";
    p_.reason = "a relative standard error above design.rel_se " + Num(d_.rel_se, 3) +
                " (largest " + Num(worst_, 3) + ")";
  }
}

void ExperimentDesigner::SetUpPair() {
  p_.criterion = "T-optimal";
  p_.a = score_a_->name;
  p_.b = score_b_->name;
  p_.dof_a = score_a_->dof;
  p_.dof_b = score_b_->dof;
  p_.critical_a = Critical(p_.dof_a, level_);
  p_.critical_b = Critical(p_.dof_b, level_);
  ca_ = Named(p_.a);
  cb_ = Named(p_.b);
  ja_old_ = CandidateColumns(job_, ca_, m_);
  jb_old_ = CandidateColumns(job_, cb_, m_);
  beta_a_ = Eigen::Map<const Eigen::VectorXd>(score_a_->step.data(), p_.dof_a);
  beta_b_ = Eigen::Map<const Eigen::VectorXd>(score_b_->step.data(), p_.dof_b);
  p_.chi2_a_given_b_now = Unabsorbed(jf_, jb_old_, ja_old_ * beta_a_);
  p_.chi2_b_given_a_now = Unabsorbed(jf_, ja_old_, jb_old_ * beta_b_);
  AddEffect(ca_, *score_a_, 0, &job_a_);
  AddEffect(cb_, *score_b_, 0, &job_b_);
  p_.reason = p_.a + " and " + p_.b + " cannot be told apart on the records";
}

const Candidate& ExperimentDesigner::Named(const std::string& name) const {
  return *std::find_if(candidates_.begin(), candidates_.end(),
                       [&](const Candidate& c) { return c.name == name; });
}

void ExperimentDesigner::ScoreFamily() {
  const FitExperiment& first = job_.experiments.front();
  family_ = first.drive.closed_loop ? ClosedLoopFamily(d_, first.options.output_period)
                                    : Family(d_);
  best_ = family_.size();
  // Each input's simulations and Jacobian are its own: the inputs are
  // scored side by side on the job's threads, and the best is the same
  // whatever the order they end in (ScoreCandidate).
  ForEachConcurrently(family_.size(), job_.solver.threads,
                      [this](size_t k) { ScoreCandidate(k); });
  for (const DesignCandidate& c : family_) ShowCandidate(c);
  p_.candidates = family_;
}

// Feasible if the axis stays inside design.travel in every model simulated
// and the proposal's Jacobian can be taken; then its criterion, and the
// best so far: the highest finite criterion, of equal ones the first in
// the family (best_mutex_: the inputs are scored concurrently).
void ExperimentDesigner::ScoreCandidate(size_t k) {
  DesignCandidate& c = family_[k];
  const FitExperiment e = ProposedExperiment(job_, c.input, d_.duration, p_.start_x);
  c.x_min = std::numeric_limits<double>::infinity();
  c.x_max = -std::numeric_limits<double>::infinity();
  bool finite = Travel(job_.model, e, &c.x_min, &c.x_max);
  if (t_design_) {
    finite = finite && Travel(job_a_.model, e, &c.x_min, &c.x_max) &&
             Travel(job_b_.model, e, &c.x_min, &c.x_max);
  }
  c.feasible = finite && c.x_min >= d_.travel_low && c.x_max <= d_.travel_high;
  if (!c.feasible) return;
  EstimationProblem proposed = job_;
  proposed.experiments = {e};
  Eigen::VectorXd re;
  Eigen::MatrixXd je;
  try {
    StackedJacobian(proposed, &re, &je);
  } catch (const std::runtime_error&) {
    c.feasible = false;
  }
  if (!c.feasible) return;
  const Eigen::MatrixXd f = Stack(jf_, je);
  if (t_design_) {
    const int me = static_cast<int>(re.size());
    const Eigen::MatrixXd ja = Stack(ja_old_, CandidateColumns(proposed, ca_, me));
    const Eigen::MatrixXd jb = Stack(jb_old_, CandidateColumns(proposed, cb_, me));
    c.chi2_a_given_b = Unabsorbed(f, jb, ja * beta_a_);
    c.chi2_b_given_a = Unabsorbed(f, ja, jb * beta_b_);
    c.criterion = std::min(c.chi2_a_given_b, c.chi2_b_given_a);
  } else {
    c.criterion = LogDet(f);
  }
  if (!std::isfinite(c.criterion)) return;
  const std::lock_guard<std::mutex> lock(best_mutex_);
  if (best_ == family_.size() || c.criterion > family_[best_].criterion ||
      (c.criterion == family_[best_].criterion && k < best_)) {
    best_ = k;
    if (!t_design_) p_.rel_se_predicted = RelativeErrors(job_, f, s2_);
  }
}

void ExperimentDesigner::ShowCandidate(const DesignCandidate& c) const {
  if (progress_) {
    *progress_ << "design: " << c.description << ": "
               << (c.feasible ? "criterion " + Num(c.criterion) : "infeasible") << ", x in ["
               << Num(c.x_min) << ", " << Num(c.x_max) << "] m\n";
  }
}

ExperimentProposal ExperimentDesigner::Done() {
  p_.seconds = std::chrono::duration<double>(Clock::now() - start_).count();
  return p_;
}

}  // namespace

ExperimentProposal ProposeExperiment(const EstimationProblem& job_in, const FitResult& result,
                                     const DesignSettings& design,
                                     const DiscoverySettings& discover, std::ostream* progress) {
  return ExperimentDesigner(job_in, result, design, discover, progress).Run();
}

std::string FormatProposal(const ExperimentProposal& p) {
  std::ostringstream out;
  out << "Next experiment (" << (p.criterion.empty() ? "none" : p.criterion) << "): " << p.reason
      << "\n";
  if (!p.criterion.empty() && p.criterion == "T-optimal") {
    out << "  on the records: chi2 of " << p.a << " beyond " << p.b << " "
        << Num(p.chi2_a_given_b_now) << ", of " << p.b << " beyond " << p.a << " "
        << Num(p.chi2_b_given_a_now) << " (critical " << Num(p.critical_a) << ", "
        << Num(p.critical_b) << ")\n";
  }
  if (!p.proposed) {
    out << "  (" << Num(p.seconds, 3) << " s)\n";
    return out.str();
  }
  int feasible = 0;
  for (const DesignCandidate& c : p.candidates) feasible += c.feasible;
  out << "  proposed: " << p.best.description << ", " << Num(p.duration, 3)
      << " s from rest at x = " << Num(p.start_x) << " m (x predicted in [" << Num(p.best.x_min)
      << ", " << Num(p.best.x_max) << "] m); best of " << feasible << " feasible inputs of "
      << p.candidates.size() << " (" << Num(p.seconds, 3) << " s)\n";
  if (p.criterion == "T-optimal") {
    out << "  predicted with it: chi2 of " << p.a << " beyond " << p.b << " if " << p.a
        << " is true " << Num(p.best.chi2_a_given_b) << " (power "
        << Num(Power(p.dof_a, p.best.chi2_a_given_b, p.critical_a), 3) << "), of " << p.b
        << " beyond " << p.a << " if " << p.b << " is true " << Num(p.best.chi2_b_given_a)
        << " (power " << Num(Power(p.dof_b, p.best.chi2_b_given_a, p.critical_b), 3) << ")\n";
  } else {
    out << "  relative standard errors now -> predicted with it:\n";
    for (size_t k = 0; k < p.names.size(); ++k) {
      out << "    " << std::left << std::setw(10) << p.names[k] << std::right << " "
          << Num(p.rel_se_now[k], 3) << " -> " << Num(p.rel_se_predicted[k], 3) << "\n";
    }
  }
  out << "  files: experiment_proposed.yaml (simulate-axis), experiment_proposed_input.csv "
      << (p.closed_loop ? "(t, x_ref: the reference position to run on the machine)"
                        : "(t, u to run on the machine)")
      << ", experiment_proposed_model.yaml\n";
  return out.str();
}

nlohmann::json ProposalToJson(const ExperimentProposal& p) {
  nlohmann::json j = {{"proposed", p.proposed},
                      {"reason", p.reason},
                      {"criterion", p.criterion},
                      {"closed_loop", p.closed_loop},
                      {"seconds", JsonNumber(p.seconds)}};
  if (p.criterion == "T-optimal") {
    j["pair"] = {p.a, p.b};
    j["critical"] = {JsonNumber(p.critical_a), JsonNumber(p.critical_b)};
    j["chi2_now"] = {JsonNumber(p.chi2_a_given_b_now), JsonNumber(p.chi2_b_given_a_now)};
  }
  if (p.proposed) {
    j["input"] = p.best.description;
    j["family"] = p.best.family;
    j["duration"] = JsonNumber(p.duration);
    j["start_x"] = JsonNumber(p.start_x);
    j["x_range"] = {JsonNumber(p.best.x_min), JsonNumber(p.best.x_max)};
    if (p.criterion == "T-optimal") {
      j["chi2_predicted"] = {JsonNumber(p.best.chi2_a_given_b), JsonNumber(p.best.chi2_b_given_a)};
      j["power"] = {JsonNumber(Power(p.dof_a, p.best.chi2_a_given_b, p.critical_a)),
                    JsonNumber(Power(p.dof_b, p.best.chi2_b_given_a, p.critical_b))};
    } else {
      nlohmann::json rows = nlohmann::json::array();
      for (size_t k = 0; k < p.names.size(); ++k) {
        rows.push_back({{"name", p.names[k]},
                        {"rel_se_now", JsonNumber(p.rel_se_now[k])},
                        {"rel_se_predicted", JsonNumber(p.rel_se_predicted[k])}});
      }
      j["parameters"] = rows;
    }
  }
  nlohmann::json tried = nlohmann::json::array();
  for (const DesignCandidate& c : p.candidates) {
    tried.push_back({{"input", c.description},
                     {"feasible", c.feasible},
                     {"criterion", JsonNumber(c.criterion)},
                     {"x_range", {JsonNumber(c.x_min), JsonNumber(c.x_max)}}});
  }
  j["candidates"] = tried;
  return j;
}

void WriteProposal(const std::string& dir, const EstimationProblem& job_in, const std::string& title,
                   const FitResult& result, const ExperimentProposal& p) {
  if (!p.proposed) return;
  EstimationProblem job = AtEstimate(job_in, result);
  AxisConfig model = job.model;
  model.name = job.model.name + "_fitted";
  model.source = "fit-params on " + title + " (the estimates the design was made at)";
  const FitExperiment& ref = job.experiments.front();
  const bool closed_loop = ref.drive.closed_loop;
  if (closed_loop) {
    // The controller the design simulated (the first experiment's).
    model.has_controller = true;
    model.controller = ref.drive.controller;
  }
  // The record as the design simulated it: its start state and time grid.
  const FitExperiment e = ProposedExperiment(job, p.best.input, p.duration, p.start_x);
  std::ostringstream state, sigmas, extra_channels, columns;
  state << std::setprecision(10) << "{";
  for (int k = 0, n = 0; k < kNumStates; ++k) {
    if (e.initial_state[k] != 0.0) state << (n++ ? ", " : "") << "y" << k << ": " << e.initial_state[k];
  }
  state << "}";
  sigmas << std::setprecision(10);  // "a: 0.02, tach: 0.005": noise and fit σ
  for (size_t k = 0; k < ref.fitted.size(); ++k) {
    const char* name = ChannelName(ref.fitted[k].channel);
    sigmas << (k ? ", " : "") << name << ": " << ref.fitted[k].sigma;
    if (ref.fitted[k].channel != Channel::kU && ref.fitted[k].channel != Channel::kX) {
      extra_channels << ", " << name;
      columns << ", " << name << ": " << name;  // the job's channels: map
    }
  }
  std::ostringstream y;
  y << std::setprecision(10);
  y << "# Written by fit-params (design:): the next experiment, " << p.criterion << ".\n"
    << "# " << p.reason << ".\n"
    << "description: \"" << p.best.description << "\"\n"
    << "model: experiment_proposed_model.yaml\n"
    << "duration: " << p.duration << "\n"
    << "step: " << ref.options.step << "\n"
    << "output_rate: " << 1.0 / ref.options.output_period << "\n"
    << "channels: [u, x" << extra_channels.str() << "]\n"
    << "noise: {" << sigmas.str() << "}\n"
    << "seed: 1\n"
    << "initial_state: " << state.str() << "\n";
  if (closed_loop) {
    y << "reference: {type: column, file: experiment_proposed_input.csv, column: x_ref}\n";
  } else {
    y << "input: " << InputYaml(p.best) << "\n";
  }
  // The job entry that fits the recorded run (the same start).
  y << "# To fit the recorded run, add to the job's experiments:\n"
    << "#   - name: proposed\n"
    << "#     data: <the recorded CSV: t, the channels above"
    << (closed_loop ? " and the reference x_ref" : "") << ">\n"
    << "#     channels: {u: u, x: x" << columns.str() << "}\n";
  if (closed_loop) {
    y << "#     reference: {column: x_ref, interpolation: linear}\n";
  } else {
    y << "#     input: {column: u"
      << (p.best.family == "steps" || p.best.family == "prbs" ? ", interpolation: hold" : "")
      << "}\n";
  }
  y << "#     initial_state: " << state.str() << "\n"
    << "#     fit: {" << sigmas.str() << "}\n";
  WriteFileAtomic(dir + "/experiment_proposed_model.yaml",
                  "# Written by fit-params (design:): the fitted model the next experiment\n"
                  "# was designed at.\n" +
                      AxisConfigToYaml(model));
  WriteFileAtomic(dir + "/experiment_proposed.yaml", y.str());
  std::ostringstream csv;
  csv << std::setprecision(12) << (closed_loop ? "t,x_ref\n" : "t,u\n");
  for (double t : e.t) csv << t << "," << p.best.input.Evaluate(t) << "\n";
  WriteFileAtomic(dir + "/experiment_proposed_input.csv", csv.str());
}

}  // namespace axis
