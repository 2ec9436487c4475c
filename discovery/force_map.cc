#include "discovery/force_map.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <Eigen/Dense>

#include "common/format.h"
#include "common/gnuplot.h"
#include "discovery/diagnostics.h"
#include "discovery/discovery.h"
#include "discovery/screen.h"
#include "estimation/at_estimate.h"
#include "estimation/experiment_cost.h"
#include "estimation/fit.h"
#include "estimation/fit_control.h"
#include "estimation/fit_result.h"
#include "estimation/optimum_check.h"
#include "estimation/roughness_cost.h"
#include "estimation/shared_level.h"
#include "estimation/stacked_jacobian.h"
#include "job/discovery_settings.h"
#include "job/fit_job.h"
#include "sim/csv.h"
#include "sim/simulate.h"

namespace axis {
namespace {

using Clock = std::chrono::steady_clock;

// Bounds (N) of a map value in the refits: wide enough never to bind for a
// servo axis (its forces are far below), finite for Ceres' bounds.
constexpr double kForceBound = 1.0e6;

// The two-sided 95 % point of the normal distribution: the pointwise band
// of the map (its Bayesian posterior is Gaussian given s²).
constexpr double kZ975 = 1.959963984540054;

// Points of the reported curve over the knots' range.
constexpr int kCurvePoints = 201;

// The λ grid, in units of the mean information per knot (the diagonal of
// JᵀJ over the map's values): from practically unpenalised (10⁻⁶) to a map
// held nearly straight (10²).
constexpr double kLambdaGrid[] = {1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0, 10.0, 100.0};
// The first refit's λ (same units): little smoothing, so that the
// linearised choice starts from a map that follows the data.
constexpr double kFirstLambda = 1e-3;
// The anchor's weight α in units of the mean information per knot times
// the number of knots (about the data's information along a component
// spread over all knots): 10³ holds a confounded component at 10⁻³ of
// what the data alone would put there.
constexpr double kAnchorFactor = 1e3;

// How far above the BIC with an effect (`bic`) the backward pass's refit
// without it may end and still remove it: the solver's accuracy
// (CostResolution, estimation/fit.h, in χ² = 2·cost units). The effect goes into
// the map whole where the map can carry it (TransferToMap: a load offset is
// a constant of f(v)), and the two models are then one function whose
// BICs differ by round-off and the solver's stop: on the velocity bump case
// 26834.934363 both ways, the sign of the difference (+6e-8 or −6e-10)
// changing with the number of threads a sum ran on. The model without it
// says the same with fewer parameters.
double RemovalTolerance(double bic, double function_tolerance) {
  return 2.0 * CostResolution(0.5 * bic, function_tolerance);
}

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The weights W(q, k) = w_k(z_q) with f(z_q) = Σ_k w_k·f_k: the spline is
// linear in its values, so w_k is the spline through the k-th unit vector
// (its second derivatives solved once per k).
Eigen::MatrixXd CardinalWeights(const std::vector<double>& knots, const std::vector<double>& z) {
  const int n = static_cast<int>(knots.size());
  Eigen::MatrixXd w(z.size(), n);
  for (int k = 0; k < n; ++k) {
    std::array<double, kMaxForceMapKnots> unit{}, m{};
    unit[k] = 1.0;
    ForceMapSecondDerivatives(knots, unit, &m);
    for (size_t q = 0; q < z.size(); ++q) w(q, k) = ForceMapValue(knots, unit, m, z[q]);
  }
  return w;
}

std::string Number(double x, int digits = 4) { return FormatNumber(x, digits); }

// The unit of the map's variable.
const char* VariableUnit(const ForceMap& map) {
  return map.variable == ForceMapVariable::kV ? "m/s" : "m";
}

const char* VariableName(const ForceMap& map) {
  return map.variable == ForceMapVariable::kV ? "v" : "x";
}

// "f(x)·sgn(v)" style description of the form.
std::string FormText(const ForceMap& map) {
  if (map.variable == ForceMapVariable::kV) return "f(v)";
  return map.friction ? "f(x)*sgn(v)" : "f(x)";
}

// The values of x and v the fitted experiments visit at the job's values,
// at their sample instants, pooled.
struct Visited {
  std::vector<double> x, v;
};

Visited VisitedValues(const FitJob& job) {
  Visited out;
  for (const FitExperiment& e : job.experiments) {
    SimulationOptions options = e.options;
    options.channels = {Channel::kX, Channel::kV};
    const SimulationGrid grid = MakeGrid(options, e.drive);
    const Trace<double> trace =
        Simulate(job.model.structure, job.model.params, e.initial_state, e.drive, options, grid);
    if (!trace.finite) {
      throw std::runtime_error("experiment '" + e.name +
                               "': simulation failed at the fitted parameters");
    }
    out.x.insert(out.x.end(), trace[Channel::kX].begin(), trace[Channel::kX].end());
    out.v.insert(out.v.end(), trace[Channel::kV].begin(), trace[Channel::kV].end());
  }
  return out;
}

// About `count` knots for the values `samples` visits: half at its
// quantiles (Ruppert, Wand & Carroll 2003, "Semiparametric Regression",
// §5.5: where the data spend their time, so that every interval holds
// samples), half spread uniformly over its range (where it passes quickly:
// a velocity crossed only while accelerating still shapes the response);
// both ends included, and a knot closer than a quarter of the uniform
// spacing to the previous one dropped. Empty if fewer than kMinForceMapKnots remain
// (the variable hardly moves).
std::vector<double> MapKnots(std::vector<double> samples, int count) {
  std::vector<double> knots;
  if (samples.empty()) return knots;
  std::sort(samples.begin(), samples.end());
  const double lo = samples.front(), hi = samples.back();
  if (!(hi - lo > 1e-9 * std::max(1.0, std::abs(lo) + std::abs(hi)))) return knots;
  const int half = std::max(2, count / 2);
  std::vector<double> all;
  for (int k = 0; k < half; ++k) {
    const double q = static_cast<double>(k) / (half - 1);
    all.push_back(samples[static_cast<size_t>(std::lround(q * (samples.size() - 1)))]);
    all.push_back(lo + q * (hi - lo));
  }
  std::sort(all.begin(), all.end());
  const double min_gap = 0.25 * (hi - lo) / (half - 1);
  for (double t : all) {
    if (knots.empty() || t - knots.back() >= min_gap) knots.push_back(t);
  }
  knots.back() = hi;  // the end of the range, replacing a knot just below it
  if (knots.size() >= 2 && !(knots.back() > knots[knots.size() - 2])) knots.pop_back();
  if (static_cast<int>(knots.size()) < kMinForceMapKnots) knots.clear();
  if (static_cast<int>(knots.size()) > kMaxForceMapKnots) knots.resize(kMaxForceMapKnots);
  return knots;
}

Candidate MapCandidate(ForceMapVariable variable, bool friction, std::vector<double> knots) {
  Candidate c;
  c.effect = "force_map";
  c.force_map.enabled = true;
  c.force_map.variable = variable;
  c.force_map.friction = friction;
  c.force_map.knots = std::move(knots);
  c.name = "force_map." + ForceMapKind(c.force_map);
  for (size_t k = 0; k < c.force_map.knots.size(); ++k) {
    c.columns.push_back({"f_map." + std::to_string(k), {}});
  }
  return c;
}

// `job` with the map of `c` switched on at zero and its values free (the
// last K entries of job.free), as a warm refit with `first_horizon`.
FitJob MapJob(const FitJob& job, const Candidate& c, double first_horizon) {
  FitJob out = job;
  out.model.structure.force_map = c.force_map;
  out.model.params.f_map.fill(0.0);
  for (const CandidateColumn& column : c.columns) {
    FreeParameter f;
    f.name = column.param;
    f.unit = "N";
    f.initial = 0.0;
    f.lower = -kForceBound;
    f.upper = kForceBound;
    f.scale = 1.0;
    f.log = false;
    out.free.push_back(f);
  }
  AsWarmRefit(&out);
  out.solver.first_horizon = first_horizon;
  out.solver.progress = false;
  return out;
}

// The penalty's matrix λ·DᵀD + α·CᵀC of `job` (its map, λ, anchor α and
// confounded components C) embedded in the n × n space of θ: the map's
// values are the last K entries of θ (MapJob), θ = value.
Eigen::MatrixXd PenaltyMatrix(const FitJob& job, int n) {
  const ForceMap& f = job.model.structure.force_map;
  const int k = static_cast<int>(f.knots.size());
  std::vector<std::string> names;
  for (const FreeParameter& p : job.free) names.push_back(p.name);
  const Eigen::MatrixXd d = SecondDifferences(f.knots);
  const Eigen::MatrixXd c = ConfoundedComponents(f, names);
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(n, n);
  p.bottomRightCorner(k, k) =
      job.force_map_lambda * d.transpose() * d + job.force_map_anchor * c.transpose() * c;
  return p;
}

// The penalised Gauss–Newton figures at the residuals r and Jacobian J at
// θ with penalty matrix P: (JᵀJ + P)⁻¹, edf = tr((JᵀJ + P)⁻¹JᵀJ) and the
// data χ², at θ or (`step`) predicted at the penalised optimum one
// Gauss–Newton step away.
struct Penalised {
  double chi2 = 0.0;
  double edf = 0.0;
  Eigen::MatrixXd inverse;
};

Penalised AtPenalty(const Eigen::VectorXd& r, const Eigen::MatrixXd& j, const Eigen::MatrixXd& p,
                    const Eigen::VectorXd& theta, bool step) {
  const Eigen::MatrixXd jtj = j.transpose() * j;
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(jtj + p);
  Penalised out;
  out.inverse = cod.pseudoInverse();
  out.edf = (out.inverse * jtj).trace();
  Eigen::VectorXd predicted = r;
  if (step) predicted -= j * (out.inverse * (j.transpose() * r + p * theta));
  out.chi2 = predicted.squaredNorm();
  return out;
}

// θ of `job`'s free parameters at their initial values.
Eigen::VectorXd ThetaOf(const FitJob& job) {
  const ParameterMap map(job.model.params, job.free);
  Eigen::VectorXd theta(map.num_free());
  for (int k = 0; k < map.num_free(); ++k) theta[k] = map.ToInternal(k, job.free[k].initial);
  return theta;
}

// A map job's figures at its free parameters' initial values (its fitted
// point after ApplyEstimates): the data χ² = Σr², edf, BIC = χ² + edf·ln(m),
// s² = χ²/(m − edf) and (JᵀJ + P)⁻¹.
struct Assessment {
  double chi2 = 0.0, edf = 0.0, bic = 0.0, s2 = 0.0;
  Eigen::MatrixXd inverse;
};

Assessment Assess(const FitJob& job) {
  Eigen::VectorXd r;
  Eigen::MatrixXd j;
  StackedJacobian(job, &r, &j);
  const Penalised at =
      AtPenalty(r, j, PenaltyMatrix(job, static_cast<int>(j.cols())), ThetaOf(job), false);
  Assessment out;
  const double m = static_cast<double>(r.size());
  out.chi2 = at.chi2;
  out.edf = at.edf;
  out.bic = at.chi2 + at.edf * std::log(m);
  out.s2 = at.chi2 / std::max(1.0, m - at.edf);
  out.inverse = at.inverse;
  return out;
}

// Moves the load force of `effect` (about to be switched off in `job`) into
// the map where the map can carry it exactly or nearly: Coulomb friction
// F_c·sgn_ε(v) (and the motor side's T_c/r_g, the same through the gear)
// into f(x)·sgn_ε(v) or f(v); a load offset F_0 into f(x) or f(v); a
// spring k_x·(x − x_0) into f(x). The refit without the effect then starts
// from the same model instead of one missing the effect's share (for
// f(x)·sgn_ε(v) and F_c the two are the same force). Never throws.
void TransferToMap(const std::string& effect, FitJob* job) {
  const AxisParams<double>& p = job->model.params;
  const ForceMap& f = job->model.structure.force_map;
  const bool v_map = f.variable == ForceMapVariable::kV;
  for (size_t k = 0; k < f.knots.size(); ++k) {
    const double t = f.knots[k];
    double add = 0.0;
    if (effect == "coulomb" && (v_map || f.friction)) {
      add = p.F_c * (v_map ? std::tanh(t / p.v_eps) : 1.0);
    } else if (effect == "motor_coulomb" && (v_map || f.friction)) {
      add = p.T_c / p.r_g * (v_map ? std::tanh(t / (p.r_g * p.omega_eps)) : 1.0);
    } else if (effect == "load_offset" && !f.friction) {
      add = p.F_0;
    } else if (effect == "spring" && !v_map && !f.friction) {
      add = p.k_x * (t - p.x_0);
    }
    if (add == 0.0) continue;
    job->model.params.f_map[k] += add;
    for (FreeParameter& free : job->free) {
      if (free.name == "f_map." + std::to_string(k)) {
        free.initial = std::clamp(job->model.params.f_map[k], free.lower, free.upper);
      }
    }
  }
}

// Runs of `z` where `inside` holds, as "x in [a, b] m, [c, d] m".
std::string Runs(const ForceMapCurve& c, const ForceMap& map, const std::vector<bool>& inside) {
  std::ostringstream out;
  int runs = 0;
  for (size_t j = 0; j < inside.size();) {
    if (!inside[j]) {
      ++j;
      continue;
    }
    size_t end = j;
    while (end + 1 < inside.size() && inside[end + 1]) ++end;
    out << (runs++ ? ", " : "") << "[" << Number(c.z[j]) << ", " << Number(c.z[end]) << "] "
        << VariableUnit(map);
    j = end + 1;
  }
  return runs ? std::string(VariableName(map)) + " in " + out.str() : "";
}

}  // namespace

ForceMapReport AddForceMap(const DiscoverySettings& settings, const DiscoveryReport& loop,
                           FitJob* job, FitResult* result, std::ostream* progress) {
  const Clock::time_point start = Clock::now();
  ForceMapReport report;
  report.bic_before = result->bic;
  if (loop.verdict.verdict != "incomplete") {
    report.reason = "not tried: the library's verdict is '" + loop.verdict.verdict + "'";
    return report;
  }
  if (job->model.structure.force_map.enabled) {
    report.reason = "not tried: the model has a force map already";
    return report;
  }
  for (const ChannelDiagnostics& d : loop.final_diagnostics) {
    for (const BinnedResidual& b : d.bins) {
      if ((b.variable == "x" || b.variable == "v") && b.p_value < loop.verdict.threshold) {
        report.structure.push_back(d.experiment + "/" + d.channel + ": " + b.variable +
                                   " (chi2 p " + Number(b.p_value, 3) + ")");
      }
    }
  }
  if (report.structure.empty()) {
    report.reason =
        "not tried: no significant binned structure of the residual against x or v "
        "(threshold " + Number(loop.verdict.threshold, 3) + ")";
    return report;
  }
  ApplyEstimates(*result, job);
  // The library model's BIC from the same residuals as the map's (Assess,
  // at the fitted initial states ApplyEstimates wrote; its edf, like the
  // map's, without them, so the two compare alike).
  report.bic_before = Assess(*job).bic;
  const Visited visited = VisitedValues(*job);
  std::vector<Candidate> candidates;
  const std::vector<double> x_knots = MapKnots(visited.x, settings.force_map_knots);
  const std::vector<double> v_knots = MapKnots(visited.v, settings.force_map_knots);
  if (!x_knots.empty()) {
    candidates.push_back(MapCandidate(ForceMapVariable::kX, false, x_knots));
    candidates.push_back(MapCandidate(ForceMapVariable::kX, true, x_knots));
  }
  if (!v_knots.empty()) candidates.push_back(MapCandidate(ForceMapVariable::kV, false, v_knots));
  if (candidates.empty()) {
    report.reason = "not tried: the experiments do not move";
    return report;
  }
  const Ranking ranking = RankCandidates(*job, candidates, settings.alpha);
  report.scores = ranking.scores;
  const Score& best = ranking.scores.front();
  const double threshold = settings.alpha / static_cast<double>(candidates.size());
  if (!(best.p_value < threshold)) {
    report.reason = "not tried: no form of the map is significant (best " + best.name +
                    ", p " + Number(best.p_value, 3) + ", threshold " + Number(threshold, 3) + ")";
    return report;
  }
  report.tried = true;
  report.reason = "the library's verdict is 'incomplete' with binned structure against x or v";

  // Every significant form refitted at little smoothing; the lowest BIC
  // wins. The score ranking alone is not trusted where the model is far
  // from the data (the friction patch case: f(v) first by χ² 4.10e4
  // against f(x)·sgn(v)'s 4.06e4). Those far above the leading form stop
  // (on the velocity bump case f(x) and f(x)·sgn(v) ended 7 times above
  // f(v)'s BIC after 30 and 12 s).
  std::vector<FitJob> jobs;
  std::vector<double> info;  // mean information per knot of each form
  for (const Score& score : ranking.scores) {
    if (!(score.p_value < threshold)) continue;
    for (const Candidate& c : candidates) {
      if (c.name != score.name) continue;
      FitJob form = MapJob(*job, c, job->solver.first_horizon);
      Eigen::VectorXd r0;
      Eigen::MatrixXd j0;
      StackedJacobian(form, &r0, &j0);
      const int k = static_cast<int>(c.force_map.knots.size());
      info.push_back(j0.rightCols(k).colwise().squaredNorm().mean());
      form.force_map_lambda = kFirstLambda * info.back();
      form.force_map_anchor = kAnchorFactor * info.back() * k;
      jobs.push_back(std::move(form));
    }
  }
  const auto form_name = [&](size_t f) {
    return "force_map." + ForceMapKind(jobs[f].model.structure.force_map);
  };
  // The first form by score publishes its BIC as the level (discovery/screen.h
  // SharedLevel); the others run beside it and stop where they would have
  // stopped had they run after it against that level (kStopFactor times
  // it), so that a form far above the leader stops once the leader ends,
  // and one that is not runs as if there were no level. Map steps (s),
  // velocity bump / friction patch case: 55.9 / 67.1 with every form run
  // to the end, 27.3 / 55.7 so. Tried: as the loop's candidates, a screen
  // of the first horizons choosing the leader, which then ran alone on
  // both threads, the others after it: 23.9 / 77.2, the friction patch's
  // slowest form starting only after the screen and the leader. The fits
  // run with a control each (the jobs keep no level).
  const int threads = std::max(1, job->solver.threads);
  const auto shared_level = std::make_shared<SharedLevel>(kStopFactor);
  std::vector<FitControl> controls(jobs.size());
  for (size_t f = 0; f < controls.size(); ++f) {
    if (f == 0) {
      controls[f].publish_level = shared_level;
    } else {
      controls[f].pending_level = shared_level;
    }
  }
  std::vector<double> seconds;
  std::vector<FitResult> fits = FitConcurrently(jobs, threads, &seconds, controls);
  double level = std::numeric_limits<double>::infinity();
  std::string level_name;
  if (fits[0].abandoned_horizon == 0.0 && std::isfinite(fits[0].bic)) {
    level = fits[0].bic;
    level_name = form_name(0) + "'s fit BIC (2·cost + n·ln m)";
  }
  size_t winner = jobs.size();
  for (size_t f = 0; f < jobs.size(); ++f) {
    ForceMapForm form;
    form.name = form_name(f);
    form.seconds = seconds[f];
    form.bic = std::numeric_limits<double>::infinity();
    form.stopped = StoppedText(fits[f], level, level_name);
    if (!form.stopped.empty()) {
      form.bic = fits[f].bic;
    } else if (std::isfinite(fits[f].final_cost)) {
      ApplyEstimates(fits[f], &jobs[f]);
      const Assessment a = Assess(jobs[f]);
      form.bic = a.bic;
      form.edf = a.edf;
      if (winner == jobs.size() || form.bic < report.forms[winner].bic) winner = f;
    }
    report.forms.push_back(form);
    if (progress) {
      *progress << "force map: " << form.name << " at lambda " << jobs[f].force_map_lambda
                << ": BIC " << (form.stopped.empty() ? "" : ">= ") << form.bic;
      if (form.stopped.empty()) {
        *progress << ", edf " << form.edf;
      } else {
        *progress << ": stopped " << form.stopped;
      }
      *progress << " (" << Number(form.seconds, 3) << " s)\n";
    }
  }
  if (winner == jobs.size()) {
    report.reason += "; every refit failed";
    report.seconds = SecondsSince(start);
    return report;
  }
  FitJob map_job = std::move(jobs[winner]);
  FitResult fit = std::move(fits[winner]);
  report.kind = ForceMapKind(map_job.model.structure.force_map);
  report.map = map_job.model.structure.force_map;
  const int k_map = static_cast<int>(report.map.knots.size());

  // The λ of the lowest linearised BIC over the grid, refitted there.
  {
    Eigen::VectorXd r;
    Eigen::MatrixXd j;
    StackedJacobian(map_job, &r, &j);
    const double log_m = std::log(static_cast<double>(r.size()));
    const Eigen::VectorXd theta = ThetaOf(map_job);
    double best_bic = std::numeric_limits<double>::infinity();
    double lambda = map_job.force_map_lambda;
    FitJob trial = map_job;
    for (double g : kLambdaGrid) {
      SmoothingChoice choice;
      trial.force_map_lambda = choice.lambda = g * info[winner];
      const Penalised at = AtPenalty(r, j, PenaltyMatrix(trial, static_cast<int>(j.cols())), theta,
                                     true);
      choice.edf = at.edf;
      choice.chi2 = at.chi2;
      choice.bic = choice.chi2 + choice.edf * log_m;
      report.grid.push_back(choice);
      if (choice.bic < best_bic) {
        best_bic = choice.bic;
        lambda = choice.lambda;
      }
    }
    if (lambda != map_job.force_map_lambda) {
      FitJob refit_job = map_job;
      refit_job.force_map_lambda = lambda;
      refit_job.solver.first_horizon = 0.0;  // next to its optimum
      const Clock::time_point refit_start = Clock::now();
      FitResult refit = FitParameters(refit_job, nullptr);
      if (progress) {
        *progress << "force map: refit at lambda " << lambda << " ("
                  << Number(SecondsSince(refit_start), 3) << " s)\n";
      }
      if (std::isfinite(refit.final_cost)) {
        ApplyEstimates(refit, &refit_job);
        refit_job.solver.first_horizon = map_job.solver.first_horizon;
        map_job = std::move(refit_job);
        fit = std::move(refit);
      }
    }
  }
  report.lambda = map_job.force_map_lambda;
  Assessment at = Assess(map_job);
  report.bic_after = at.bic;
  report.kept = report.bic_after < report.bic_before;
  if (progress) {
    *progress << "force map " << report.kind << ": lambda " << report.lambda << " 1/N^2, edf "
              << at.edf << ", BIC " << report.bic_before << " -> " << report.bic_after
              << (report.kept ? " (kept)" : " (not kept)") << "\n";
  }

  // Backward pass: the loop's effects may stand in for what the map now
  // carries.
  if (report.kept) {
    const std::vector<std::string>& selected = loop.selected;
    for (auto it = selected.rbegin(); it != selected.rend(); ++it) {
      const std::string& effect = *it;
      if (std::find(loop.removed.begin(), loop.removed.end(), effect) != loop.removed.end()) {
        continue;
      }
      if (effect == "coulomb" && map_job.model.structure.effects.stribeck) continue;
      FitJob without = JobWithout(map_job, effect);
      TransferToMap(effect, &without);
      const Clock::time_point refit_start = Clock::now();
      FitResult refit = FitParameters(without, nullptr);
      const double refit_seconds = SecondsSince(refit_start);
      ForceMapRemoval removal;
      removal.effect = effect;
      removal.bic_with = at.bic;
      removal.bic_without = std::numeric_limits<double>::infinity();
      if (std::isfinite(refit.final_cost) && refit.abandoned_horizon == 0.0) {
        ApplyEstimates(refit, &without);
        const Assessment a = Assess(without);
        removal.bic_without = a.bic;
        // Not higher than with the effect beyond the solver's accuracy: a
        // tie (see RemovalTolerance), which parsimony decides.
        if (a.bic < at.bic + RemovalTolerance(at.bic, without.solver.function_tolerance)) {
          removal.removed = true;
          map_job = std::move(without);
          fit = std::move(refit);
          at = a;
        }
      }
      if (progress) {
        *progress << "force map: without " << effect << ": BIC " << removal.bic_with << " -> "
                  << removal.bic_without << (removal.removed ? " (removed" : " (stays") << ", "
                  << Number(refit_seconds, 3) << " s)\n";
      }
      report.removals.push_back(removal);
    }
    report.bic_after = at.bic;
  }
  report.edf = at.edf;
  report.s2 = at.s2;
  const Eigen::MatrixXd cov = at.s2 * at.inverse.bottomRightCorner(k_map, k_map);
  for (int k = 0; k < k_map; ++k) {
    report.values.push_back(map_job.model.params.f_map[k]);
    report.std_errors.push_back(std::sqrt(std::max(0.0, cov(k, k))));
  }
  report.channels = ChannelChanges(*result, fit);

  // The curve with its band, and where the band excludes zero.
  const std::vector<double>& kn = report.map.knots;
  const Eigen::Map<const Eigen::VectorXd> values(report.values.data(), k_map);
  std::vector<bool> nonzero;
  for (int q = 0; q < kCurvePoints; ++q) {
    report.curve.z.push_back(kn.front() + (kn.back() - kn.front()) * q / (kCurvePoints - 1));
  }
  const Eigen::MatrixXd weights = CardinalWeights(kn, report.curve.z);
  for (int q = 0; q < kCurvePoints; ++q) {
    const Eigen::VectorXd wv = weights.row(q).transpose();
    const double f = wv.dot(values);
    const double sd = std::sqrt(std::max(0.0, wv.dot(cov * wv)));
    report.curve.force.push_back(f);
    report.curve.low.push_back(f - kZ975 * sd);
    report.curve.high.push_back(f + kZ975 * sd);
    nonzero.push_back(std::abs(f) > kZ975 * sd);
  }
  const std::string runs = Runs(report.curve, report.map, nonzero);
  if (!runs.empty()) report.significant.push_back(runs);

  if (report.kept) {
    // The map's figures: the data's χ² (the fit's cost holds the roughness
    // penalty too) over m − edf, as the verdict's s² test needs them, the
    // estimated initial states counted as FitParameters counts them (edf
    // has no columns for them, StackedJacobian).
    const double states = EstimatedStateCount(map_job);
    const double m = fit.num_residuals;
    fit.bic = at.bic + states * std::log(m);
    fit.aic = at.chi2 + 2.0 * (at.edf + states);
    fit.residual_dof = std::max(1.0, m - at.edf - states);
    fit.residual_variance = at.chi2 / fit.residual_dof;
    *job = std::move(map_job);
    *result = std::move(fit);
    report.diagnostics = DiagnoseResiduals(*job);
    report.verdict = JudgeResiduals(report.diagnostics, *result, settings.alpha);
  }
  report.seconds = SecondsSince(start);
  return report;
}

void ApplyRemovals(const ForceMapReport& report, DiscoveryReport* loop) {
  for (const ForceMapRemoval& r : report.removals) {
    if (!r.removed) continue;
    loop->selected.erase(std::remove(loop->selected.begin(), loop->selected.end(), r.effect),
                         loop->selected.end());
    loop->removed.push_back(r.effect);
  }
}

std::string FormatForceMap(const ForceMapReport& report) {
  std::ostringstream out;
  out << "Force map: " << report.reason << "\n";
  for (const std::string& s : report.structure) out << "  binned structure: " << s << "\n";
  if (!report.scores.empty()) {
    TextTable scores;
    scores.headers = {"form", "chi2", "dof", "p"};
    scores.right = {false, true, true, true};
    for (const Score& s : report.scores) {
      scores.rows.push_back({s.name, Number(s.chi2), std::to_string(s.dof), Number(s.p_value, 3)});
    }
    out << "\nScore tests of the map's forms:\n" << RenderText(scores);
  }
  if (!report.tried) return out.str();
  if (!report.forms.empty()) {
    TextTable forms;
    forms.headers = {"form", "BIC (edf)", "edf", "refit (s)"};
    forms.right = {false, true, true, true};
    for (const ForceMapForm& f : report.forms) {
      forms.rows.push_back({f.name, (f.stopped.empty() ? "" : ">= ") + Number(f.bic, 7),
                            f.stopped.empty() ? Number(f.edf) : "-", Number(f.seconds, 3)});
    }
    out << "\nThe significant forms refitted (little smoothing; the lowest BIC wins):\n"
        << RenderText(forms);
    for (const ForceMapForm& f : report.forms) {
      if (!f.stopped.empty()) out << f.name << ": stopped " << f.stopped << "\n";
    }
  }
  if (report.kind.empty()) return out.str();
  const ForceMap& map = report.map;
  out << "\nForce map " << FormText(map) << " (" << report.kind << "): " << map.knots.size()
      << " knots over [" << Number(map.knots.front()) << ", " << Number(map.knots.back()) << "] "
      << VariableUnit(map) << "\n";
  TextTable grid;
  grid.headers = {"lambda (1/N^2)", "edf", "chi2 (linearised)", "BIC", ""};
  grid.right = {true, true, true, true, false};
  for (const SmoothingChoice& s : report.grid) {
    grid.rows.push_back({Number(s.lambda, 3), Number(s.edf), Number(s.chi2, 7), Number(s.bic, 7),
                         s.lambda == report.lambda ? "chosen" : ""});
  }
  out << "\nRoughness penalty, BIC with the effective number of parameters:\n"
      << RenderText(grid);
  TextTable values;
  values.headers = {"knot (" + std::string(VariableUnit(map)) + ")", "force (N)",
                    "std error (N)"};
  values.right = {true, true, true};
  for (size_t k = 0; k < report.values.size(); ++k) {
    values.rows.push_back({Number(map.knots[k]), Number(report.values[k]),
                           Number(report.std_errors[k], 3)});
  }
  out << "\nLearned force (values at the knots; 95 % band: +-1.96 std error):\n"
      << RenderText(values);
  out << "lambda " << Number(report.lambda, 3) << " 1/N^2, edf " << Number(report.edf)
      << ", s2 " << Number(report.s2) << "; BIC " << Number(report.bic_before, 7) << " -> "
      << Number(report.bic_after, 7) << (report.kept ? " (kept)" : " (not kept)") << "\n";
  for (const ForceMapRemoval& r : report.removals) {
    out << "without " << r.effect << ": BIC " << Number(r.bic_with, 7) << " -> "
        << Number(r.bic_without, 7) << (r.removed ? " (removed: a stand-in for the map)" : " (stays)")
        << "\n";
  }
  out << "significantly non-zero: "
      << (report.significant.empty() ? "nowhere" : Join(report.significant, "; ")) << "\n";
  TextTable channels;
  channels.headers = {"experiment", "channel", "RMS before", "RMS after", "fit % before",
                      "fit % after"};
  channels.right = {false, false, true, true, true, true};
  for (const ChannelChange& c : report.channels) {
    channels.rows.push_back({c.experiment, c.channel, Number(c.rms_before), Number(c.rms_after),
                             Number(c.fit_percent_before), Number(c.fit_percent_after)});
  }
  out << "\nBefore (library model) and after (with the map):\n" << RenderText(channels);
  if (report.kept) out << "\nWith the map: " << FormatVerdict(report.verdict);
  out << "(" << Number(report.seconds, 3) << " s)\n";
  return out.str();
}

nlohmann::json ForceMapToJson(const ForceMapReport& report) {
  nlohmann::json out;
  out["tried"] = report.tried;
  out["kept"] = report.kept;
  out["reason"] = report.reason;
  out["structure"] = report.structure;
  nlohmann::json scores = nlohmann::json::array();
  for (const Score& s : report.scores) {
    scores.push_back({{"effect", s.name},
                      {"chi2", JsonNumber(s.chi2)},
                      {"dof", s.dof},
                      {"p_value", JsonNumber(s.p_value)}});
  }
  out["scores"] = scores;
  nlohmann::json forms = nlohmann::json::array();
  for (const ForceMapForm& f : report.forms) {
    forms.push_back({{"effect", f.name},
                     {"bic", JsonNumber(f.bic)},
                     {"edf", JsonNumber(f.edf)},
                     {"stopped", f.stopped}});
  }
  out["forms"] = forms;
  nlohmann::json removals = nlohmann::json::array();
  for (const ForceMapRemoval& r : report.removals) {
    removals.push_back({{"effect", r.effect},
                        {"bic_with", JsonNumber(r.bic_with)},
                        {"bic_without", JsonNumber(r.bic_without)},
                        {"removed", r.removed}});
  }
  out["removals"] = removals;
  if (report.kind.empty()) return out;
  out["kind"] = report.kind;
  out["variable"] = VariableName(report.map);
  out["friction"] = report.map.friction;
  out["knots"] = report.map.knots;
  out["values"] = report.values;
  nlohmann::json se = nlohmann::json::array();
  for (double s : report.std_errors) se.push_back(JsonNumber(s));
  out["std_errors"] = se;
  out["lambda"] = JsonNumber(report.lambda);
  out["edf"] = JsonNumber(report.edf);
  out["s2"] = JsonNumber(report.s2);
  out["bic_before"] = JsonNumber(report.bic_before);
  out["bic_after"] = JsonNumber(report.bic_after);
  nlohmann::json grid = nlohmann::json::array();
  for (const SmoothingChoice& s : report.grid) {
    grid.push_back({{"lambda", JsonNumber(s.lambda)},
                    {"edf", JsonNumber(s.edf)},
                    {"chi2", JsonNumber(s.chi2)},
                    {"bic", JsonNumber(s.bic)}});
  }
  out["grid"] = grid;
  out["channels"] = ChannelChangesToJson(report.channels);
  out["verdict"] = report.verdict.verdict;
  out["remains"] = report.verdict.remains;
  out["significant"] = report.significant;
  out["seconds"] = JsonNumber(report.seconds);
  return out;
}

void WriteForceMapCsv(const std::string& path, const ForceMapReport& report) {
  std::ostringstream csv;
  csv << VariableName(report.map) << ",force,low,high\n" << std::setprecision(12);
  for (size_t q = 0; q < report.curve.z.size(); ++q) {
    csv << report.curve.z[q] << "," << report.curve.force[q] << "," << report.curve.low[q] << ","
        << report.curve.high[q] << "\n";
  }
  WriteFileAtomic(path, csv.str());
}

std::string ForceMapPlotScript(const ForceMapReport& report, const std::string& csv_path,
                               const std::string& output, bool svg) {
  std::ostringstream s;
  if (svg) {
    s << "set terminal svg size 1000,560 dynamic noenhanced font 'sans,12' background rgb "
         "'white'; ";
  } else {
    s << "set terminal pngcairo size 1000,600 noenhanced; ";
  }
  s << "set output '" << output
    << "'; set datafile separator ','; set grid; set key top left; set title 'learned force "
    << FormText(report.map) << (report.kept ? "" : " (not kept)") << "'; set xlabel '"
    << VariableName(report.map) << " (" << VariableUnit(report.map)
    << ")'; set ylabel 'force (N)'; plot '" << csv_path
    << "' every ::1 using 1:3:4 with filledcurves lc rgb '#c6dbef' title '95 % band', '"
    << csv_path << "' every ::1 using 1:2 with lines lw 2 lc rgb '#08519c' title 'f', 0 with "
    << "lines lc rgb 'gray' notitle";
  return s.str();
}

void WriteForceMap(const std::string& dir, const ForceMapReport& report,
                   std::vector<std::string>* warnings) {
  if (report.curve.z.empty()) return;
  const std::string csv_path = dir + "/force_map.csv";
  WriteForceMapCsv(csv_path, report);
  const auto script = [&](const std::string& png) {
    return ForceMapPlotScript(report, csv_path, png, false);
  };
  std::string warning;
  if (!RenderGnuplotPng(dir + "/force_map.png", script, "force map", &warning)) {
    if (warnings) warnings->push_back(warning);
  }
}

}  // namespace axis
