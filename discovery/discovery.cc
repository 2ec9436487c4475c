#include "discovery/discovery.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <memory>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>

#include "common/format.h"
#include "common/progress.h"
#include "common/statistics.h"
#include "discovery/diagnostics.h"
#include "discovery/screen.h"
#include "estimation/at_estimate.h"
#include "estimation/experiment_cost.h"
#include "estimation/fit.h"
#include "estimation/fit_control.h"
#include "estimation/fit_result.h"
#include "estimation/horizon_checkpoint.h"
#include "estimation/stacked_jacobian.h"
#include "job/discovery_settings.h"
#include "job/fit_job.h"
#include "sim/config.h"

namespace axis {
namespace {

using Clock = std::chrono::steady_clock;

// Wall time since `start`, s.
double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

constexpr double kPi = 3.14159265358979323846;

// The Stribeck velocities tried (m/s): its shape has no effect at
// F_st = F_c, so the test spans this small grid of shapes.
constexpr double kStribeckGrid[] = {0.005, 0.02, 0.1};

// Above this s² (residual variance in units of the declared noise) the model
// error outweighs the noise and the score ranking is not trusted: the top
// significant candidates are all refitted (Discover). 2: the misfit's
// variance exceeds the noise's.
constexpr double kMisspecifiedS2 = 2.0;

std::vector<CandidateColumn> ColumnsOf(const std::string& effect,
                                      const std::string& channel) {
  if (effect == "coulomb") return {{"F_c", {}}};
  if (effect == "stribeck") {
    std::vector<CandidateColumn> out;
    for (double v : kStribeckGrid) out.push_back({"F_st", {{"v_st", v}}});
    return out;
  }
  if (effect == "viscous_asymmetry") return {{"Delta_B", {}}};
  if (effect == "load_offset") return {{"F_0", {}}};
  if (effect == "spring") return {{"k_x", {{"x_0", 0.0}}}};
  if (effect == "payload") return {{"Delta_M", {}}};
  if (effect == "motor_coulomb") return {{"T_c", {}}};
  if (effect == "cogging") {
    return {{"A_cog", {{"phi_cog", 0.0}}}, {"A_cog", {{"phi_cog", kPi / 2}}}};
  }
  if (effect == "sensor_delay") return {{"tau_d." + channel, {}}};
  if (effect == "sensor_bias") return {{"b." + channel, {}}};
  return {};
}

// The structure with candidate `c` switched on (or off).
AxisStructure WithEffect(AxisStructure s, const Candidate& c, bool on = true) {
  for (const EffectInfo& e : DynamicEffectTable()) {
    if (c.effect == e.name) s.effects.*(e.flag) = on;
  }
  const int ch = static_cast<int>(c.channel);
  if (c.effect == "sensor_delay") s.sensors.delay[ch] = on;
  if (c.effect == "sensor_bias") s.sensors.bias[ch] = on;
  if (c.effect == "force_map") {
    s.force_map = c.force_map;
    s.force_map.enabled = on;
  }
  return s;
}

}  // namespace

// The candidate's Jacobian columns (m × k), stacked like StackedJacobian.
Eigen::MatrixXd CandidateColumns(const FitJob& job, const Candidate& c, int m) {
  Eigen::MatrixXd out(m, c.columns.size());
  const AxisStructure structure = WithEffect(job.model.structure, c);
  for (size_t col = 0; col < c.columns.size(); ++col) {
    const CandidateColumn& column = c.columns[col];
    AxisParams<double> params = job.model.params;
    for (const auto& [name, value] : column.settings) *FindParam(&params, name) = value;
    FreeParameter f;
    f.name = column.param;
    f.scale = 1.0;
    f.log = false;
    const double at = *FindParam(&params, column.param);
    const ParameterMap map(params, {f});
    EvaluationCounter counter;
    int row = 0;
    for (const FitExperiment& e : job.experiments) {
      const ExperimentCost cost(structure, map, e, 1, -1, &counter);
      std::vector<double> r(cost.num_residuals()), d(cost.num_residuals());
      const double direction = 1.0;
      if (!cost.Directional(&at, &direction, r.data(), d.data())) {
        std::fill(d.begin(), d.end(), 0.0);
      }
      for (size_t k = 0; k < d.size(); ++k) out(row + k, col) = d[k];
      row += static_cast<int>(d.size());
    }
  }
  return out;
}

Eigen::MatrixXd Basis(const Eigen::MatrixXd& a) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  qr.setThreshold(1e-10);
  const int rank = static_cast<int>(qr.rank());
  Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(a.rows(), rank);
  return q;
}

namespace {

FreeParameter Linear(const std::string& name, double value) {
  FreeParameter f;
  f.name = name;
  f.initial = value;
  const double width = 100.0 * std::abs(value) + 1.0;
  f.lower = value - width;
  f.upper = value + width;
  f.log = false;
  f.unit = ParamUnit(name);
  return f;
}

FreeParameter Positive(const std::string& name, double value, double lo, double hi) {
  FreeParameter f = Linear(name, value);
  f.initial = std::clamp(value, lo * 1.0001, hi * 0.9999);
  f.lower = lo;
  f.upper = hi;
  f.log = true;
  return f;
}

// How many starts the refit of candidate `c` takes: one per v_st of the
// grid for Stribeck friction, each with F_st − F_c at that column's own
// step (Score::single_step), the lowest BIC kept; one for every other
// effect (linear, or started from its score step in closed form). The
// Stribeck shape is nonlinear in v_st and its columns nearly parallel: on
// the power_stribeck campaign (v_st = 0.05 m/s) one refit from the joint
// step at the grid value of its largest component ended at v_st ≈ 0.4 m/s
// (BIC ~3e3 above the true minimum) on 4 seeds of 20; from the three
// grid values, seed 5 still ended in a higher minimum from v_st = 0.005
// (BIC 1.468e4) and at the truth from 0.02 and 0.1 (1.189e4).
size_t StartsOf(const Candidate& c) {
  return c.effect == "stribeck" ? std::size(kStribeckGrid) : 1;
}

// What start `start` of candidate `c` begins from, for the report; empty
// for a candidate with one start.
std::string StartLabel(const Candidate& c, size_t start) {
  if (StartsOf(c) == 1) return "";
  std::ostringstream out;
  out << "v_st = " << kStribeckGrid[start] << " m/s";
  return out.str();
}

}  // namespace

// Switches candidate `c` on in `job` and frees its parameters, starting from
// the score step; `start` < StartsOf(c) picks the start.
void AddEffect(const Candidate& c, const Score& s, size_t start, FitJob* job) {
  job->model.structure = WithEffect(job->model.structure, c);
  AxisParams<double>& p = job->model.params;
  std::vector<FreeParameter> added;
  if (c.effect == "cogging") {
    const double amplitude = std::hypot(s.step[0], s.step[1]);
    const double phase = std::atan2(s.step[1], s.step[0]);
    p.A_cog = std::max(amplitude, 1e-6);
    p.phi_cog = phase;
    added.push_back(Positive("A_cog", p.A_cog, p.A_cog / 100, p.A_cog * 100 + 1e-3));
    added.push_back(Linear("phi_cog", phase));
    added.back().lower = phase - 2 * kPi;
    added.back().upper = phase + 2 * kPi;
  } else if (c.effect == "stribeck") {
    p.v_st = kStribeckGrid[start];
    p.F_st = p.F_c + s.single_step[start];
    added.push_back(Linear("F_st", p.F_st));
    added.push_back(Positive("v_st", p.v_st, 1e-4, 1.0));
  } else if (c.effect == "sensor_delay") {
    const std::string name = c.columns[0].param;
    const double tau = std::clamp(s.step[0], 1e-5, 0.05);
    *FindParam(&p, name) = tau;
    added.push_back(Positive(name, tau, 1e-6, 0.1));
  } else {
    const std::string name = c.columns[0].param;
    const double value = *FindParam(&p, name) + s.step[0];
    *FindParam(&p, name) = value;
    added.push_back(Linear(name, value));
    if (name == "Delta_M") added.back().lower = std::min(0.0, value - 1.0);
    // Viscous friction moving in −x is B_a + ΔB ≥ 0: no negative damping
    // (B_a as fitted so far; it moves a little in the refit).
    if (name == "Delta_B") added.back().lower = std::max(added.back().lower, -p.B_a);
  }
  for (FreeParameter& f : added) {
    f.initial = std::clamp(f.initial, f.lower, f.upper);
    job->free.push_back(f);
  }
}

namespace {

// Which bounds of an effect parameter AddEffect made are only a search
// interval around the score step (Linear), and may be widened when a refit
// ends on them: not those of log-scaled parameters (bounds of their own),
// cogging's phase (periodic), ΔB and ΔM (a physical lower bound; their
// upper one is left as it was too), nor friction amplitudes below zero.
struct SearchSides {
  bool lower = false, upper = false;
};
SearchSides SearchBoundSides(const FreeParameter& f) {
  if (f.log || f.name == "phi_cog" || f.name == "Delta_B" || f.name == "Delta_M") return {};
  return {f.name != "F_c" && f.name != "T_c", true};
}

// The index of the fit with the lowest finite BIC in `fits` among those
// that ran to the whole record (else among those stopped early, whose BIC
// is a lower bound: FitResult::abandoned_horizon), or fits.size() if none
// is finite.
size_t LowestFiniteBic(const std::vector<FitResult>& fits) {
  size_t best = fits.size();
  const auto better = [&](size_t k) {
    if (!std::isfinite(fits[k].bic)) return false;
    if (best == fits.size()) return true;
    const bool whole = fits[k].abandoned_horizon == 0.0;
    const bool best_whole = fits[best].abandoned_horizon == 0.0;
    if (whole != best_whole) return whole;
    return fits[k].bic < fits[best].bic;
  };
  for (size_t k = 0; k < fits.size(); ++k) {
    if (better(k)) best = k;
  }
  return best;
}

// ">= " before a step's bic_after that is a lower bound (a stopped refit,
// DiscoveryStep::stopped), else "".
const char* BoundMark(const DiscoveryStep& s) { return s.stopped.empty() ? "" : ">= "; }

// Switches candidate `c` off in `job` and fixes its parameters `params`.
void RemoveEffect(const Candidate& c, const std::vector<std::string>& params,
                  FitJob* job) {
  job->model.structure = WithEffect(job->model.structure, c, false);
  std::vector<FreeParameter> kept;
  for (const FreeParameter& f : job->free) {
    if (std::find(params.begin(), params.end(), f.name) == params.end()) kept.push_back(f);
  }
  job->free = kept;
}

// The candidate of a Candidate::name ("coulomb", "sensor_delay.a"); throws
// std::invalid_argument for a name that is not one.
Candidate CandidateNamed(const std::string& name) {
  const size_t dot = name.find('.');
  Candidate c;
  c.name = name;
  c.effect = name.substr(0, dot);
  if (!IsEffectName(name)) {
    throw std::invalid_argument("expected an effect of MODEL.md section 7 (" +
                                EffectNameList() + "), got '" + name + "'");
  }
  const std::string channel = dot == std::string::npos ? "" : name.substr(dot + 1);
  if (!channel.empty()) c.channel = *ParseChannel(channel);
  c.columns = ColumnsOf(c.effect, channel);
  return c;
}

// The parameters AddEffect frees for `c`.
std::vector<std::string> EffectParameters(const Candidate& c) {
  if (c.effect == "cogging") return {"A_cog", "phi_cog"};
  if (c.effect == "stribeck") return {"F_st", "v_st"};
  return {c.columns[0].param};
}

// Refits `job` without `c` (its parameters `params` fixed), warm-started at
// the optimum `result` with the effect switched off; `without` receives the
// job. The step records BIC with and without; kept = BIC improved.
std::pair<DiscoveryStep, FitResult> RefitWithout(const Candidate& c,
                                                 const std::vector<std::string>& params,
                                                 FitJob* job, const FitResult& result,
                                                 FitJob* without) {
  ApplyEstimates(result, job);
  *without = *job;
  RemoveEffect(c, params, without);
  // Without a large effect the optimum can be far from this start: the
  // removal keeps the horizon continuation (there is no bound on its cost
  // to check a warm refit against, as there is for an added effect).
  const double first_horizon = without->solver.first_horizon;
  AsWarmRefit(without);
  without->solver.first_horizon = first_horizon;
  // Removed only if BIC falls: a refit that can no longer fall below the
  // BIC with the effect stops early (FitControl::abandon_above_bic).
  FitControl control;
  control.abandon_above_bic = kStopFactor * result.bic;
  const Clock::time_point start = Clock::now();
  FitResult refit = FitParameters(*without, nullptr, control);
  DiscoveryStep record;
  record.seconds = SecondsSince(start);
  record.effect = c.name;
  record.removal = true;
  record.bic_before = result.bic;
  record.bic_after = refit.bic;
  record.stopped = StoppedText(refit, result.bic, "the BIC with the effect");
  record.kept = refit.bic < result.bic && record.stopped.empty();
  record.channels = ChannelChanges(result, refit);
  return {record, refit};
}

// The estimate of `name` in `fit`, or nullptr.
const ParameterEstimate* FindEstimate(const FitResult& fit, const std::string& name) {
  for (const ParameterEstimate& e : fit.parameters) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

// Widens 100-fold each search-bound side (SearchBoundSides) of the
// parameters `names` of `job` on which `fit` ended (within 1e-6 of the
// interval's width); true if any was widened.
bool WidenSearchBounds(const FitResult& fit, const std::vector<std::string>& names,
                       FitJob* job) {
  bool widened = false;
  for (FreeParameter& f : job->free) {
    if (std::find(names.begin(), names.end(), f.name) == names.end()) continue;
    const ParameterEstimate* e = FindEstimate(fit, f.name);
    if (e == nullptr) continue;
    const SearchSides sides = SearchBoundSides(f);
    const double width = f.upper - f.lower;
    if (sides.upper && e->value >= f.upper - 1e-6 * width) {
      f.upper += 100.0 * width;
      widened = true;
    } else if (sides.lower && e->value <= f.lower + 1e-6 * width) {
      f.lower -= 100.0 * width;
      widened = true;
    }
  }
  return widened;
}

// Drops `name` from the selected effects (to report->removed) and adopts
// the model without it (`without`, fitted as `refit`).
void DropEffect(const std::string& name, FitJob&& without, FitResult&& refit, FitJob* job,
                FitResult* result, DiscoveryReport* report) {
  report->removed.push_back(name);
  report->selected.erase(std::find(report->selected.begin(), report->selected.end(), name));
  *job = std::move(without);
  *result = std::move(refit);
}

}  // namespace

std::vector<std::string> FreedParameters(const std::string& effect) {
  return EffectParameters(CandidateNamed(effect));
}

FitJob JobWithout(const FitJob& job, const std::string& effect) {
  const Candidate c = CandidateNamed(effect);
  FitJob out = job;
  RemoveEffect(c, EffectParameters(c), &out);
  return out;
}

nlohmann::json ChannelChangesToJson(const std::vector<ChannelChange>& changes) {
  nlohmann::json out = nlohmann::json::array();
  for (const ChannelChange& c : changes) {
    out.push_back({{"experiment", c.experiment},
                   {"channel", c.channel},
                   {"rms_before", JsonNumber(c.rms_before)},
                   {"rms_after", JsonNumber(c.rms_after)},
                   {"fit_percent_before", JsonNumber(c.fit_percent_before)},
                   {"fit_percent_after", JsonNumber(c.fit_percent_after)}});
  }
  return out;
}

std::vector<ChannelChange> ChannelChanges(const FitResult& before, const FitResult& after) {
  std::vector<ChannelChange> out;
  for (const ExperimentFit& b : before.experiments) {
    for (const ExperimentFit& a : after.experiments) {
      if (a.name != b.name) continue;
      for (const ChannelFit& cb : b.channels) {
        for (const ChannelFit& ca : a.channels) {
          if (ca.channel != cb.channel) continue;
          // An open-loop input is replayed exactly: nothing to compare.
          if (cb.rms == 0.0 && ca.rms == 0.0) continue;
          out.push_back({b.name, cb.channel, cb.rms, ca.rms, cb.fit_percent,
                         ca.fit_percent});
        }
      }
    }
  }
  return out;
}

std::vector<Candidate> ListCandidates(const FitJob& job,
                                      const std::vector<std::string>& only) {
  std::vector<Candidate> all;
  const bool has_motor = job.model.structure.amplifier != Amplifier::kForceSource;
  for (const EffectInfo& e : DynamicEffectTable()) {
    if (job.model.structure.effects.*(e.flag)) continue;
    // Motor-side effects need a motor: force_source has none (MODEL.md §4).
    const std::string name = e.name;
    if (!has_motor && (name == "motor_coulomb" || name == "cogging")) continue;
    // Stribeck refines Coulomb friction ((F_st − F_c)·exp(−(v/v_st)²), MODEL.md
    // §7): a candidate only once Coulomb is in the model (the marginality
    // principle). Without it, its three shape columns also span a Coulomb
    // step and it outranks Coulomb on the extra shapes (EMPS: log10 p
    // −44280 vs −43230) while its refit, without the Coulomb term, fails.
    if (name == "stribeck" && !job.model.structure.effects.coulomb) continue;
    all.push_back({e.name, e.name, Channel::kT, ColumnsOf(e.name, ""), {}});
  }
  std::vector<Channel> fitted;
  for (const FitExperiment& e : job.experiments) {
    for (const FittedChannel& f : e.fitted) {
      if (std::find(fitted.begin(), fitted.end(), f.channel) == fitted.end()) {
        fitted.push_back(f.channel);
      }
    }
  }
  for (const char* effect : {"sensor_delay", "sensor_bias"}) {
    for (Channel ch : fitted) {
      const int c = static_cast<int>(ch);
      const bool has = std::string(effect) == "sensor_delay"
                           ? job.model.structure.sensors.delay[c]
                           : job.model.structure.sensors.bias[c];
      if (has) continue;
      const std::string name = std::string(effect) + "." + ChannelName(ch);
      all.push_back({name, effect, ch, ColumnsOf(effect, ChannelName(ch)), {}});
    }
  }
  if (only.empty()) return all;
  std::vector<Candidate> out;
  for (const std::string& name : only) {
    bool known = false;
    for (const EffectInfo& e : DynamicEffectTable()) known = known || name == e.name;
    for (const Candidate& c : all) known = known || c.name == name || c.effect == name;
    if (!known && name != "sensor_delay" && name != "sensor_bias") {
      std::string list;
      for (const EffectInfo& e : DynamicEffectTable()) list += std::string(e.name) + ", ";
      throw std::invalid_argument(
          "discover candidates: expected an effect of MODEL.md section 7 (" +
          list + "sensor_delay[.channel], sensor_bias[.channel]), got '" + name + "'");
    }
    for (const Candidate& c : all) {
      if (c.name == name || c.effect == name) out.push_back(c);
    }
  }
  return out;
}

Ranking RankCandidates(const FitJob& job, const std::vector<Candidate>& candidates,
                       double alpha) {
  Eigen::VectorXd r;
  Eigen::MatrixXd jf;
  StackedJacobian(job, &r, &jf);
  const int m = static_cast<int>(r.size());
  const int n = static_cast<int>(jf.cols());
  const Eigen::MatrixXd q = Basis(jf);
  // Residuals are divided by the declared σ: under the null hypothesis (the
  // model without the candidate, right noise levels) they have unit
  // variance, so the statistic uses s² = 1, not the residual variance, which
  // a misfit inflates and which would deflate every candidate alike.
  const double s2 = 1.0;
  (void)n;
  Ranking ranking;
  std::vector<Eigen::MatrixXd> bases;
  for (const Candidate& c : candidates) {
    Eigen::MatrixXd jc = CandidateColumns(job, c, m);
    jc -= q * (q.transpose() * jc);  // off the span of the free parameters
    Score s;
    s.name = c.name;
    s.dof = static_cast<int>(jc.cols());
    const Eigen::MatrixXd info = jc.transpose() * jc;
    const Eigen::VectorXd g = jc.transpose() * r;
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(info, Eigen::ComputeFullU | Eigen::ComputeFullV);
    svd.setThreshold(1e-12);
    const Eigen::VectorXd solved = svd.solve(g);
    s.chi2 = g.dot(solved) / s2;
    s.p_value = ChiSquaredSurvival(s.chi2, s.dof);
    s.step.resize(s.dof);
    for (int k = 0; k < s.dof; ++k) s.step[k] = -solved[k];
    s.single_step.resize(s.dof);
    for (int k = 0; k < s.dof; ++k) {
      s.single_step[k] = info(k, k) > 0.0 ? -g[k] / info(k, k) : 0.0;
    }
    ranking.scores.push_back(s);
    bases.push_back(Basis(jc));
  }
  const double threshold = alpha / std::max<size_t>(1, candidates.size());
  const auto projected_chi2 = [&](const Eigen::MatrixXd& basis) {
    return (basis.transpose() * r).squaredNorm() / s2;
  };
  for (size_t a = 0; a < candidates.size(); ++a) {
    for (size_t b = a + 1; b < candidates.size(); ++b) {
      if (bases[a].cols() == 0 || bases[b].cols() == 0) continue;
      if (ranking.scores[a].p_value >= threshold && ranking.scores[b].p_value >= threshold) continue;
      const Eigen::MatrixXd cross = bases[a].transpose() * bases[b];
      const double cosine = Eigen::JacobiSVD<Eigen::MatrixXd>(cross).singularValues()[0];
      if (!(cosine > 0.95)) continue;
      Eigen::MatrixXd both(m, bases[a].cols() + bases[b].cols());
      both << bases[a], bases[b];
      const double joint = projected_chi2(Basis(both));
      ParallelPair pair;
      pair.a = candidates[a].name;
      pair.b = candidates[b].name;
      pair.cosine = cosine;
      pair.chi2_a_given_b = std::max(0.0, joint - projected_chi2(bases[b]));
      pair.chi2_b_given_a = std::max(0.0, joint - projected_chi2(bases[a]));
      pair.separated =
          ChiSquaredSurvival(pair.chi2_a_given_b, ranking.scores[a].dof) < threshold ||
          ChiSquaredSurvival(pair.chi2_b_given_a, ranking.scores[b].dof) < threshold;
      ranking.parallel.push_back(pair);
      if (!pair.separated) ranking.indistinguishable.emplace_back(pair.a, pair.b);
    }
  }
  for (Score& x : ranking.scores) x.log_p_value = LogChiSquaredSurvival(x.chi2, x.dof);
  std::stable_sort(ranking.scores.begin(), ranking.scores.end(),
                   [](const Score& x, const Score& y) {
                     if (x.log_p_value != y.log_p_value) return x.log_p_value < y.log_p_value;
                     return x.chi2 / x.dof > y.chi2 / y.dof;
                   });
  return ranking;
}

DiscoveryReport Discover(const DiscoverySettings& settings, FitJob* job,
                         FitResult* result, std::ostream* progress) {
  DiscoveryReport report;
  // The job's continuation, kept by the loop's refits (AsWarmRefit
  // switches it off).
  const double first_horizon = job->solver.first_horizon;
  // Progress (common/progress.h): the stage only. How many refits a step
  // takes, and how many steps the loop makes, is known only as it goes, so
  // no remaining time is estimated here.
  ProgressStream* status = AsProgressStream(progress);
  const double unknown = std::numeric_limits<double>::quiet_NaN();
  if (status != nullptr) status->BeginPhase("discovery");
  for (int step = 0; step < settings.max_effects; ++step) {
    ApplyEstimates(*result, job);
    const std::vector<Candidate> candidates = ListCandidates(*job, settings.candidates);
    if (candidates.empty()) {
      report.stop_reason = "no candidate left";
      break;
    }
    const std::string step_name = "discovery step " + std::to_string(step + 1) +
                                  " (at most " + std::to_string(settings.max_effects) + ")";
    if (status != nullptr) {
      status->Status(step_name + ": score tests of " + std::to_string(candidates.size()) +
                         " candidates",
                     unknown);
    }
    const Clock::time_point ranking_start = Clock::now();
    const Ranking ranking = RankCandidates(*job, candidates, settings.alpha);
    report.score_seconds += SecondsSince(ranking_start);
    ++report.score_rankings;
    if (step == 0) report.ranking = ranking;
    const double threshold = settings.alpha / candidates.size();
    const Score& best = ranking.scores.front();
    if (progress) {
      *progress << "discovery step " << step + 1 << ": best candidate " << best.name
                << " (chi2 " << best.chi2 << ", dof " << best.dof << ", p "
                << best.p_value << ", threshold " << threshold << ")\n";
    }
    if (!(best.p_value < threshold)) {
      report.stop_reason = "no significant candidate (best " + best.name +
                           ", p = " + std::to_string(best.p_value) + ")";
      break;
    }
    const auto dof_of = [&](const std::string& name) {
      for (const Score& sc : ranking.scores) {
        if (sc.name == name) return sc.dof;
      }
      return 0;
    };
    // The score test is a linearisation at the current fit; the refit and
    // BIC decide. A significant candidate whose refit does not improve BIC
    // (the refit found a worse local minimum, or the candidate only mimics
    // another effect locally) makes way for the next one, up to
    // settings.tries refits per step. Far from a model that explains the
    // data (s² above kMisspecifiedS2) the score ranking itself is not
    // reliable (a stand-in can outrank the effect: motor-side Coulomb
    // friction above the load-side one at χ² 2.9e6 against 2.5e6; the
    // payload ninth on its own data): then the top
    // `misspecified_tries` (default: all) significant candidates are
    // refitted and the lowest BIC wins.
    const double s2 = result->residual_variance;
    const bool by_refit = s2 > kMisspecifiedS2;
    std::ostringstream rule;
    rule << std::setprecision(3);
    if (by_refit) {
      rule << "lowest BIC of the refitted significant candidates (s^2 = " << s2
           << " > " << kMisspecifiedS2 << ": the score ranking is not reliable)";
    } else {
      rule << "first significant candidate in score order whose refit improves BIC (s^2 = "
           << s2 << ")";
    }
    if (progress) *progress << "  rule: " << rule.str() << "\n";
    struct Trial {
      size_t step;  // index in report.steps
      Candidate candidate;
      FitJob job;
      FitResult fit;
    };
    std::vector<Trial> improved;
    int tries = 0;
    std::string rejected;
    // Refits waiting to run: in score order, one at a time by the first
    // rule (the first that improves BIC ends the step), all of the top
    // `misspecified_tries` at once, concurrently, by the second
    // (FitConcurrently).
    struct Pending {
      const Score* score;
      Candidate candidate;
      std::vector<FitJob> starts;      // one job per start (StartsOf)
      std::vector<std::string> names;  // the effect's parameters, now free
    };
    std::vector<Pending> batch;
    // The jobs of a candidate's refit: the effect added at `score`'s step,
    // one per start. One start each, no optimum check, Gauss–Newton
    // intervals; but the horizon continuation stays: from the optimum with
    // the effect at its score step, the whole record at once ended in
    // higher minima (EMPS: the Stribeck refit at BIC 1.145e4 instead of
    // 1.135e4, B_a 379 instead of 153 N·s/m; coulomb_viscous_asymmetry:
    // motor-side Coulomb friction at 3.2e6 instead of 2.6e5), so refits
    // with an effect added keep it.
    const auto refit_jobs = [&](const Candidate& candidate, const Score& score) {
      std::vector<FitJob> out;
      for (size_t k = 0; k < StartsOf(candidate); ++k) {
        FitJob refit = *job;
        AddEffect(candidate, score, k, &refit);
        AsWarmRefit(&refit);
        refit.solver.first_horizon = first_horizon;
        out.push_back(std::move(refit));
      }
      return out;
    };
    // The level a refit must end below to matter (issue 11): a refit whose
    // BIC's lower bound passes kStopFactor times it stops on a shorter
    // horizon (FitControl::abandon_above_bic). First the BIC before the
    // step (a refit above it is rejected); once a batch's leading refit has
    // run, its BIC if it would be kept (no other refit above it can win the
    // step).
    struct Level {
      double bic;
      std::string name;  // for DiscoveryStep::stopped
    };
    Level level{result->bic, "the BIC before the step"};
    const auto run_batch = [&]() {
      if (batch.empty()) return;  // the call after the loop, all run already
      std::string names;
      for (const Pending& q : batch) names += (names.empty() ? "" : ", ") + q.candidate.name;
      if (status != nullptr && !batch.empty()) {
        status->Status(step_name + ": " +
                           (batch.size() == 1
                                ? "candidate refit " + std::to_string(tries) + " of at most " +
                                      std::to_string(settings.tries) + " (" + names + ")"
                                : "refitting " + std::to_string(batch.size()) +
                                      " candidates at once (" + names + ")"),
                       unknown);
      }
      // The screen (several candidates, a horizon continuation): every
      // refit runs the first kScreenStages horizons only
      // (FitControl::stop_after_horizon), and the refits then run in
      // the order of their BICs' lower bounds there, lowest first, so that
      // the leading refits are the likeliest to set a low level. The
      // order changes only which refits stop early, not which wins (the
      // lowest BIC of those that run to the end).
      std::vector<size_t> order(batch.size());
      std::iota(order.begin(), order.end(), size_t{0});
      std::vector<double> screen_seconds(batch.size(), 0.0);
      // The screen's shorter horizons, per candidate and start, which its
      // refit goes on after instead of running them again
      // (FitControl::resume): the same points, costs and stops, up to
      // the last bits of a cost summed on another number of threads (the
      // leader's refit runs on more than its screen did). On the
      // coulomb_load_offset case (issue 11) 17.0 → 15.1 s whole process,
      // the same steps and stops, estimates equal to 12 digits.
      std::vector<std::vector<std::shared_ptr<const HorizonCheckpoint>>> resume(batch.size());
      if (batch.size() > 1 && first_horizon > 0.0) {
        std::vector<FitJob> screen;
        for (const Pending& q : batch) screen.insert(screen.end(), q.starts.begin(), q.starts.end());
        const std::vector<ScreenedFit> screened = ScreenFits(std::move(screen), job->solver.threads);
        std::vector<double> key(batch.size(), std::numeric_limits<double>::infinity());
        size_t k = 0;
        for (size_t c = 0; c < batch.size(); ++c) {
          resume[c].resize(batch[c].starts.size());
          for (size_t s = 0; s < batch[c].starts.size(); ++s, ++k) {
            key[c] = std::min(key[c], screened[k].bound);
            screen_seconds[c] += screened[k].seconds;
            resume[c][s] = screened[k].checkpoint;
          }
        }
        std::stable_sort(order.begin(), order.end(),
                         [&](size_t x, size_t y) { return key[x] < key[y]; });
      }
      // The refits in that order. The leading one, the first candidate's
      // (every start, each fit's evaluation on the threads left), runs
      // before the others so that it can set the level; the rest run after,
      // stopped above it. (The first two candidates as leaders, one per
      // core, were slower on the coulomb_load_offset case, 58.7 against
      // 48.6 s: after the screen the second leader was the payload, whose
      // refit ran 16 s to BIC 2.6e5 beside Coulomb friction's 1.2e4.)
      // run_candidates fits candidates [from, to) of `order` against the
      // current level, on copies of their starts (those in `batch`, one of
      // which the loop may adopt, keep no level and no checkpoint); pos[c]:
      // candidate c's first start in `fits`, level_of[c]: the level it ran
      // against.
      std::vector<size_t> pos(batch.size(), 0);
      std::vector<Level> level_of(batch.size(), level);
      std::vector<FitResult> fits;
      std::vector<double> seconds;
      const auto run_candidates = [&](std::vector<size_t>::const_iterator from,
                                      std::vector<size_t>::const_iterator to) {
        std::vector<FitJob> jobs;
        std::vector<FitControl> controls;
        for (auto it = from; it != to; ++it) {
          pos[*it] = fits.size() + jobs.size();
          level_of[*it] = level;
          for (size_t k = 0; k < batch[*it].starts.size(); ++k) {
            jobs.push_back(batch[*it].starts[k]);
            FitControl control;
            control.abandon_above_bic = kStopFactor * level.bic;
            if (k < resume[*it].size()) control.resume = resume[*it][k];
            controls.push_back(std::move(control));
          }
        }
        std::vector<double> secs;
        std::vector<FitResult> out =
            FitConcurrently(jobs, job->solver.threads, &secs, controls);
        fits.insert(fits.end(), std::make_move_iterator(out.begin()),
                    std::make_move_iterator(out.end()));
        seconds.insert(seconds.end(), secs.begin(), secs.end());
      };
      run_candidates(order.begin(), order.begin() + 1);
      if (order.size() > 1) {
        const Pending& q = batch[order[0]];
        for (size_t s = 0; s < q.starts.size(); ++s) {
          const FitResult& fit = fits[s];
          if (fit.abandoned_horizon == 0.0 && std::isfinite(fit.bic) && fit.bic < level.bic &&
              ImplausibleValue(q.candidate.name, fit, q.starts[s]).empty()) {
            level = {fit.bic, q.candidate.name + "'s BIC"};
          }
        }
        // The others all run against the same level, so their order only
        // decides which finish first: the longest screens first
        // (longest-processing-time order, the screen's time standing in
        // for the refit's), so that a long refit does not start last.
        std::stable_sort(order.begin() + 1, order.end(), [&](size_t x, size_t y) {
          return screen_seconds[x] > screen_seconds[y];
        });
        run_candidates(order.begin() + 1, order.end());
      }
      for (size_t b = 0; b < batch.size(); ++b) {
        Pending& q = batch[b];
        const size_t n = q.starts.size();
        const size_t first = pos[b];  // q's first start in `jobs`
        std::vector<FitResult> own(fits.begin() + first, fits.begin() + first + n);
        DiscoveryStep record;
        record.seconds = screen_seconds[b];
        for (size_t k = 0; k < n; ++k) record.seconds += seconds[first + k];
        size_t best = LowestFiniteBic(own);
        if (best == n) {
          // Seen on the power_load_offset campaign (seed 4, s² = 204): the
          // offset, first by score, failed in 0.27 s from its score step and
          // a stand-in (cogging) took the step.
          Score damped = *q.score;
          for (double& x : damped.step) x *= 0.1;
          for (double& x : damped.single_step) x *= 0.1;
          q.starts = refit_jobs(q.candidate, damped);
          FitControl control;
          control.abandon_above_bic = kStopFactor * level.bic;
          level_of[b] = level;
          std::vector<double> again;
          own = FitConcurrently(q.starts, job->solver.threads, &again,
                                std::vector<FitControl>(q.starts.size(), control));
          for (double s : again) record.seconds += s;
          best = LowestFiniteBic(own);
          record.retried = "refit from the score step failed; retried from a tenth of it";
        }
        if (n > 1) {
          std::ostringstream starts;
          starts << std::setprecision(4) << n << " starts, BIC";
          for (size_t k = 0; k < n; ++k) {
            starts << (k == 0 ? " " : ", ") << (own[k].abandoned_horizon > 0.0 ? ">= " : "")
                   << own[k].bic << " from " << StartLabel(q.candidate, k);
          }
          if (best < n) starts << "; kept the start from " << StartLabel(q.candidate, best);
          record.starts = starts.str();
        }
        if (best == n) best = 0;  // none finite: report the first
        // An added parameter that ended on a bound of its search interval
        // (Linear: the score step ± 100 times it + 1): the step was too
        // small a guide (the base fit had absorbed most of the effect:
        // a record in motion, Coulomb friction's step 0.11 N where the
        // truth is 40 N, B_a at 455 instead of 200 N·s/m), so that side is
        // widened 100-fold and the refit continued from where it ended.
        if (std::isfinite(own[best].bic) && own[best].abandoned_horizon == 0.0) {
          FitJob wider = q.starts[best];
          if (WidenSearchBounds(own[best], q.names, &wider)) {
            ApplyEstimates(own[best], &wider);
            const Clock::time_point again = Clock::now();
            FitResult further = FitParameters(wider, nullptr);
            record.seconds += std::chrono::duration<double>(Clock::now() - again).count();
            if (std::isfinite(further.bic) && further.bic < own[best].bic) {
              own[best] = std::move(further);
              q.starts[best] = std::move(wider);
              record.widened = "an added parameter ended on its search bound; refitted "
                               "with that bound widened 100-fold";
            }
          }
        }
        FitResult& refit = own[best];
        FitJob& refit_job = q.starts[best];
        record.effect = q.candidate.name;
        record.rule = rule.str();
        record.chi2 = q.score->chi2;
        record.dof = q.score->dof;
        record.p_value = q.score->p_value;
        record.bic_before = result->bic;
        record.bic_after = refit.bic;
        record.stopped = StoppedText(refit, level_of[b].bic, level_of[b].name);
        if (record.stopped.empty()) {
          record.implausible = ImplausibleValue(q.candidate.name, refit, refit_job);
          for (const ParameterEstimate& e : refit.parameters) {
            if (e.free && std::find(q.names.begin(), q.names.end(), e.name) != q.names.end()) {
              record.parameters.push_back(e);
            }
          }
          record.channels = ChannelChanges(*result, refit);
        }
        record.kept =
            refit.bic < result->bic && record.implausible.empty() && record.stopped.empty();
        report.steps.push_back(record);
        if (progress) {
          *progress << "  refit with " << q.candidate.name << ": BIC " << record.bic_before
                    << " -> " << BoundMark(record) << record.bic_after
                    << (record.kept ? " (improves)" : " (rejected)")
                    << (record.implausible.empty() ? "" : ": " + record.implausible)
                    << (record.stopped.empty() ? "" : ": stopped " + record.stopped)
                    << (record.retried.empty() ? "" : " (" + record.retried + ")")
                    << (record.widened.empty() ? "" : " (" + record.widened + ")")
                    << (record.starts.empty() ? "" : " (" + record.starts + ")")
                    << " (" << record.seconds << " s)\n";
        }
        if (!record.kept) {
          rejected += (rejected.empty() ? "" : ", ") + q.candidate.name;
          continue;
        }
        improved.push_back({report.steps.size() - 1, q.candidate, std::move(refit_job),
                            std::move(refit)});
      }
      batch.clear();
    };
    for (const Score& score : ranking.scores) {
      if ((!by_refit && !improved.empty()) ||
          tries >= (by_refit ? settings.misspecified_tries : settings.tries) ||
          !(score.p_value < threshold)) {
        break;
      }
      // Candidates the data cannot tell from this one. A twin with more
      // parameters is a richer alternative (Stribeck contains a
      // Coulomb-like shape): parsimony keeps this one. A twin of the same
      // size is a rival explanation: the loop stops and says so.
      std::string twin;
      for (const auto& [a, b] : ranking.indistinguishable) {
        const std::string other = a == score.name ? b : (b == score.name ? a : "");
        if (!other.empty() && dof_of(other) <= score.dof) twin = other;
      }
      // Beyond the top `tries` (misspecified rule only) a candidate with a
      // twin is passed over: the loop's stop is decided by the top ones.
      if (!twin.empty() && by_refit && tries >= settings.tries) continue;
      if (!twin.empty()) {
        report.stop_reason = score.name + " and " + twin +
                             " cannot be told apart on this data (projected "
                             "columns nearly parallel): add an experiment that "
                             "separates them, e.g. motion in both directions";
        break;
      }
      const Candidate& chosen = *std::find_if(
          candidates.begin(), candidates.end(),
          [&](const Candidate& c) { return c.name == score.name; });
      Pending q{&score, chosen, refit_jobs(chosen, score), {}};
      for (size_t k = job->free.size(); k < q.starts[0].free.size(); ++k) {
        q.names.push_back(q.starts[0].free[k].name);
      }
      ++tries;
      batch.push_back(std::move(q));
      if (!by_refit) run_batch();
    }
    run_batch();
    if (improved.empty()) {
      if (report.stop_reason.empty()) {
        report.stop_reason = "no significant candidate improved BIC (tried " + rejected + ")";
      }
      break;
    }
    size_t lowest = 0;
    for (size_t k = 1; k < improved.size(); ++k) {
      if (improved[k].fit.bic < improved[lowest].fit.bic) lowest = k;
    }
    for (size_t k = 0; k < improved.size(); ++k) {
      if (k == lowest) continue;
      DiscoveryStep& other = report.steps[improved[k].step];
      other.kept = false;
      std::ostringstream why;
      why << "BIC " << other.bic_after << " above " << improved[lowest].candidate.name << "'s "
          << improved[lowest].fit.bic;
      other.outranked = why.str();
    }
    Trial& winner = improved[lowest];
    if (progress) *progress << "  kept " << winner.candidate.name << "\n";
    report.selected.push_back(winner.candidate.name);
    *job = std::move(winner.job);
    *result = std::move(winner.fit);
  }
  if (report.stop_reason.empty()) report.stop_reason = "maximum number of effects reached";
  // Backward pass: without each added effect but the last.
  const std::vector<std::string> added = report.selected;
  if (status != nullptr) status->BeginPhase("backward pass");
  for (size_t k = 0; k + 1 < added.size(); ++k) {
    const Candidate candidate = CandidateNamed(added[k]);
    if (candidate.effect == "coulomb" && job->model.structure.effects.stribeck) continue;
    if (status != nullptr) {
      status->Status("discovery backward pass: refit without " + candidate.name + " (" +
                         std::to_string(k + 1) + " of " + std::to_string(added.size() - 1) +
                         ")",
                     static_cast<double>(k) / static_cast<double>(added.size() - 1));
    }
    FitJob without;
    auto [record, refit] =
        RefitWithout(candidate, EffectParameters(candidate), job, *result, &without);
    report.steps.push_back(record);
    if (progress) {
      *progress << "  refit without " << candidate.name << ": BIC " << record.bic_before
                << " -> " << BoundMark(record) << record.bic_after
                << (record.kept ? " (removed)" : " (stays)")
                << (record.stopped.empty() ? "" : ": stopped " + record.stopped) << "\n";
    }
    if (record.kept) {
      DropEffect(candidate.name, std::move(without), std::move(refit), job, result, &report);
    }
  }
  report.level = settings.alpha / std::max<size_t>(1, report.ranking.scores.size());
  DropInsignificant(report.level, job, result, &report, progress);
  if (status != nullptr) status->Status("discovery: diagnosing the final model", unknown);
  report.final_diagnostics = DiagnoseResiduals(*job);
  report.verdict = JudgeResiduals(report.final_diagnostics, *result, settings.alpha);
  return report;
}

void DropInsignificant(double level, FitJob* job, FitResult* result,
                       DiscoveryReport* report, std::ostream* progress) {
  if (!(level > 0.0)) {
    throw std::invalid_argument("DropInsignificant: expected a level > 0, got " +
                                std::to_string(level));
  }
  report->level = level;
  // The last added first (Stribeck before the Coulomb it refines).
  const std::vector<std::string> effects = report->selected;
  for (size_t k = effects.size(); k-- > 0;) {
    const Candidate candidate = CandidateNamed(effects[k]);
    if (candidate.effect == "coulomb" && job->model.structure.effects.stribeck) continue;
    ApplyEstimates(*result, job);
    const EffectSignificance w = EffectWald(candidate.name, *result);
    if (w.p_value < level) continue;
    if (ProgressStream* status = AsProgressStream(progress)) {
      status->Status("discovery significance: refit without " + candidate.name +
                         " (not significant)",
                     std::numeric_limits<double>::quiet_NaN());
    }
    FitJob without;
    auto [record, refit] =
        RefitWithout(candidate, EffectParameters(candidate), job, *result, &without);
    std::ostringstream why;
    why << "Wald chi2 " << w.chi2 << " (dof " << w.dof << "), p " << w.p_value
        << " not below " << level << ": not distinguishable from off";
    record.insignificant = why.str();
    record.kept = true;  // removed whatever BIC says
    report->steps.push_back(record);
    if (progress) {
      *progress << "  refit without " << candidate.name << ": " << record.insignificant
                << "; BIC " << record.bic_before << " -> " << record.bic_after
                << " (removed)\n";
    }
    DropEffect(candidate.name, std::move(without), std::move(refit), job, result, report);
  }
  ApplyEstimates(*result, job);
  report->significance.clear();
  for (const std::string& name : report->selected) {
    report->significance.push_back(EffectWald(name, *result));
  }
}

EffectSignificance EffectWald(const std::string& effect, const FitResult& fit) {
  const Candidate candidate = CandidateNamed(effect);
  const std::string& base = candidate.effect;
  const std::vector<CandidateColumn>& columns = candidate.columns;
  EffectSignificance w;
  w.effect = effect;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Free parameter k of the fit: its index in the correlation matrix.
  const auto index = [&](const std::string& name) -> int {
    for (size_t k = 0; k < fit.free_names.size(); ++k) {
      if (fit.free_names[k] == name) return static_cast<int>(k);
    }
    return -1;
  };
  const auto estimate = [&](const std::string& name) { return FindEstimate(fit, name); };
  const auto covariance = [&](const std::string& a, const std::string& b) {
    const int i = index(a), j = index(b);
    if (i < 0 || j < 0) return 0.0;
    const double rho = fit.correlation.rows() > std::max(i, j) ? fit.correlation(i, j)
                                                               : (i == j ? 1.0 : 0.0);
    return estimate(a)->std_error * estimate(b)->std_error * rho;
  };
  const std::string p = columns[0].param;
  const ParameterEstimate* e = estimate(p);
  double chi2 = nan;
  if (e != nullptr && index(p) >= 0) {
    if (base == "stribeck") {
      const ParameterEstimate* fc = estimate("F_c");
      const double d = e->value - (fc ? fc->value : 0.0);
      const double var = covariance("F_st", "F_st") + covariance("F_c", "F_c") -
                         2.0 * covariance("F_st", "F_c");
      chi2 = d * d / var;
    } else if (base == "cogging") {
      w.dof = 2;
      double var = covariance("A_cog", "A_cog");
      const double var_phi = covariance("phi_cog", "phi_cog");
      if (var_phi > 0.0) var -= covariance("A_cog", "phi_cog") * covariance("A_cog", "phi_cog") / var_phi;
      chi2 = e->value * e->value / var;
    } else {
      chi2 = e->value * e->value / covariance(p, p);
    }
  }
  w.chi2 = std::isfinite(chi2) ? chi2 : nan;
  w.p_value = std::isfinite(chi2) ? ChiSquaredSurvival(chi2, w.dof) : nan;
  return w;
}

std::string ImplausibleValue(const std::string& effect, const FitResult& fit,
                             const FitJob& job) {
  const auto value = [&](const std::string& name) {
    const ParameterEstimate* e = FindEstimate(fit, name);
    return e ? e->value : std::numeric_limits<double>::quiet_NaN();
  };
  std::ostringstream why;
  if (effect == "payload") {
    const double dm = value("Delta_M");
    if (dm < 0.0) {
      why << "payload Delta_M = " << dm << " kg is below zero: the declared mass M is too "
          << "large (free M instead)";
    }
  } else if (effect.rfind("sensor_delay.", 0) == 0) {
    double period = std::numeric_limits<double>::infinity();
    for (const FitExperiment& e : job.experiments) {
      period = std::min(period, e.options.output_period);
    }
    const std::string name = "tau_d." + effect.substr(std::string("sensor_delay.").size());
    const double tau = value(name);
    if (tau < period) {
      why << name << " = " << tau << " s is shorter than the sample period " << period
          << " s: a sub-sample timing error (e.g. of an input read by linear interpolation "
          << "between samples), not a sensor delay";
    }
  }
  return why.str();
}

std::string FormatDiscovery(const DiscoveryReport& report) {
  std::ostringstream out;
  out << "Model discovery (score test, Bonferroni, BIC)\n";
  out << "Ranking at the first step:\n";
  out << "  candidate                 chi2      dof   p-value     log10 p\n";
  for (const Score& s : report.ranking.scores) {
    out << "  " << std::left << std::setw(22) << s.name << std::right
        << std::setw(12) << std::setprecision(4) << s.chi2 << std::setw(6)
        << s.dof << std::setw(12) << s.p_value << std::setw(12)
        << s.log_p_value / std::log(10.0) << "\n";
  }
  for (const ParallelPair& q : report.ranking.parallel) {
    out << "  nearly parallel: " << q.a << " ~ " << q.b << " (cos " << q.cosine
        << "; chi2 " << q.a << "|" << q.b << " " << q.chi2_a_given_b << ", "
        << q.b << "|" << q.a << " " << q.chi2_b_given_a << "): "
        << (q.separated ? "the residual separates them"
                        : "indistinguishable on this data")
        << "\n";
  }
  for (size_t k = 0; k < report.steps.size(); ++k) {
    const DiscoveryStep& s = report.steps[k];
    if (s.removal) {
      out << "\nStep " << k + 1 << ": without " << s.effect
          << (s.kept ? " (removed)" : " (stays)") << "  BIC " << s.bic_before
          << " -> " << BoundMark(s) << s.bic_after << "  (refit "
          << s.seconds << " s)\n";
      if (!s.stopped.empty()) out << "  stopped " << s.stopped << "\n";
      if (!s.insignificant.empty()) out << "  not significant: " << s.insignificant << "\n";
    } else {
      out << "\nStep " << k + 1 << ": " << s.effect << (s.kept ? " (kept)" : " (rejected)")
          << "  chi2 " << s.chi2 << " (dof " << s.dof << ", p " << s.p_value
          << ")  BIC " << s.bic_before << " -> " << BoundMark(s) << s.bic_after << "  (refit "
          << s.seconds << " s)\n";
      if (!s.stopped.empty()) out << "  stopped " << s.stopped << "\n";
      if (!s.implausible.empty()) out << "  not physical: " << s.implausible << "\n";
      if (!s.outranked.empty()) out << "  outranked: " << s.outranked << "\n";
      if (!s.starts.empty()) out << "  starts: " << s.starts << "\n";
      if (!s.retried.empty()) out << "  " << s.retried << "\n";
      if (!s.widened.empty()) out << "  " << s.widened << "\n";
      if (!s.rule.empty()) out << "  rule: " << s.rule << "\n";
    }
    for (const ParameterEstimate& p : s.parameters) {
      out << "  " << p.name << " = " << p.value << " +- " << p.std_error << " "
          << p.unit << "  95% [" << p.ci95_low << ", " << p.ci95_high << "]\n";
    }
    size_t width = 11;
    for (const ChannelChange& c : s.channels) width = std::max(width, c.experiment.size() + 1);
    out << "  " << std::left << std::setw(static_cast<int>(width)) << "experiment"
        << "channel     RMS before   RMS after   fit% before  fit% after\n";
    for (const ChannelChange& c : s.channels) {
      out << "  " << std::left << std::setw(static_cast<int>(width)) << c.experiment << std::setw(8)
          << c.channel << std::right << std::setw(13) << c.rms_before
          << std::setw(12) << c.rms_after << std::setw(13) << c.fit_percent_before
          << std::setw(12) << c.fit_percent_after << "\n";
    }
  }
  out << "\nSelected: ";
  for (const std::string& s : report.selected) out << s << " ";
  if (report.selected.empty()) out << "none";
  if (!report.removed.empty()) {
    out << "\nRemoved by the backward pass: ";
    for (const std::string& r : report.removed) out << r << " ";
  }
  out << "\nStopped: " << report.stop_reason << "\n";
  double refits = 0.0;
  for (const DiscoveryStep& s : report.steps) refits += s.seconds;
  out << "Time: base fit " << report.base_fit_seconds << " s, score tests "
      << report.score_seconds << " s (" << report.score_rankings << " ranking(s)), refits "
      << refits << " s (" << report.steps.size() << ")\n";
  if (!report.significance.empty()) {
    out << "Significance of the selected effects (Wald, against off, level " << report.level
        << "):\n";
    for (const EffectSignificance& w : report.significance) {
      out << "  " << std::left << std::setw(22) << w.effect << std::right << " chi2 "
          << w.chi2 << " (dof " << w.dof << "), p " << w.p_value << "\n";
    }
  }
  if (!report.verdict.verdict.empty()) {
    out << "\nFinal model: " << FormatVerdict(report.verdict);
    if (report.verdict.verdict == "incomplete" && !report.selected.empty()) {
      out << "The selected effects explain part of the residual; with the model "
             "incomplete their values may stand in for what is missing.\n";
    }
  }
  return out.str();
}

}  // namespace axis

namespace axis {

nlohmann::json DiscoveryToJson(const DiscoveryReport& report) {
  nlohmann::json out;
  out["selected"] = report.selected;
  out["removed"] = report.removed;
  out["base_fit_seconds"] = JsonNumber(report.base_fit_seconds);
  out["score_seconds"] = JsonNumber(report.score_seconds);
  out["score_rankings"] = report.score_rankings;
  out["steps"] = nlohmann::json::array();
  for (const DiscoveryStep& s : report.steps) {
    nlohmann::json step;
    step["effect"] = s.effect;
    step["parameters"] = nlohmann::json::object();
    for (const ParameterEstimate& p : s.parameters) {
      step["parameters"][p.name] = {{"value", JsonNumber(p.value)},
                                    {"std_error", JsonNumber(p.std_error)},
                                    {"ci95_low", JsonNumber(p.ci95_low)},
                                    {"ci95_high", JsonNumber(p.ci95_high)}};
    }
    step["chi2"] = JsonNumber(s.chi2);
    step["dof"] = s.dof;
    step["p_value"] = JsonNumber(s.p_value);
    step["bic_before"] = JsonNumber(s.bic_before);
    step["bic_after"] = JsonNumber(s.bic_after);
    step["kept"] = s.kept;
    step["removal"] = s.removal;
    step["seconds"] = JsonNumber(s.seconds);
    if (!s.implausible.empty()) step["implausible"] = s.implausible;
    if (!s.insignificant.empty()) step["insignificant"] = s.insignificant;
    if (!s.rule.empty()) step["rule"] = s.rule;
    if (!s.outranked.empty()) step["outranked"] = s.outranked;
    if (!s.starts.empty()) step["starts"] = s.starts;
    if (!s.retried.empty()) step["retried"] = s.retried;
    if (!s.widened.empty()) step["widened"] = s.widened;
    if (!s.stopped.empty()) step["stopped"] = s.stopped;
    step["channels"] = ChannelChangesToJson(s.channels);
    out["steps"].push_back(step);
  }
  out["ranking"] = nlohmann::json::array();
  for (const Score& s : report.ranking.scores) {
    out["ranking"].push_back({{"effect", s.name}, {"chi2", JsonNumber(s.chi2)},
                              {"dof", s.dof}, {"p_value", JsonNumber(s.p_value)},
                              {"log10_p_value", JsonNumber(s.log_p_value / std::log(10.0))}});
  }
  out["indistinguishable"] = nlohmann::json::array();
  for (const auto& [a, b] : report.ranking.indistinguishable) {
    out["indistinguishable"].push_back({a, b});
  }
  out["nearly_parallel"] = nlohmann::json::array();
  for (const ParallelPair& q : report.ranking.parallel) {
    out["nearly_parallel"].push_back({{"a", q.a}, {"b", q.b}, {"cosine", JsonNumber(q.cosine)},
                                      {"chi2_a_given_b", JsonNumber(q.chi2_a_given_b)},
                                      {"chi2_b_given_a", JsonNumber(q.chi2_b_given_a)},
                                      {"separated", q.separated}});
  }
  out["stop_reason"] = report.stop_reason;
  out["level"] = JsonNumber(report.level);
  out["significance"] = nlohmann::json::array();
  for (const EffectSignificance& w : report.significance) {
    out["significance"].push_back({{"effect", w.effect}, {"chi2", JsonNumber(w.chi2)},
                                   {"dof", w.dof}, {"p_value", JsonNumber(w.p_value)}});
  }
  const ResidualVerdict& v = report.verdict;
  out["verdict"] = v.verdict;
  out["verdict_detail"] = {{"s2", JsonNumber(v.s2)},
                           {"s2_p_value", JsonNumber(v.s2_p_value)},
                           {"tests", v.tests},
                           {"threshold", JsonNumber(v.threshold)},
                           {"channels", v.channels},
                           {"remains", v.remains},
                           {"stand_ins_possible", v.verdict == "incomplete" &&
                                                      !report.selected.empty()}};
  return out;
}

}  // namespace axis
