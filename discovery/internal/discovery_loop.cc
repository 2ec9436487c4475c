#include "discovery/internal/discovery_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iterator>
#include <limits>
#include <numeric>
#include <sstream>
#include <utility>

#include "common/progress.h"
#include "discovery/candidates.h"
#include "discovery/channel_changes.h"
#include "discovery/diagnostics.h"
#include "discovery/materiality.h"
#include "discovery/removal.h"
#include "discovery/internal/screen.h"
#include "discovery/significance.h"
#include "estimation/alignment_lag.h"
#include "estimation/at_estimate.h"
#include "estimation/fit.h"
#include "estimation/fit_control.h"
#include "estimation/horizon_checkpoint.h"
#include "estimation/record_prefix.h"

namespace axis {
namespace {

// A BIC gain above 10 is "very strong" evidence (Kass & Raftery 1995,
// J. Am. Stat. Assoc. 90, 773–795: 2 ln B > 10); below it the simpler of
// two front ends of one channel is kept.
// How often a delay's refit is moved to where its own simulation lines up
// with the records (RealignDelay).
constexpr int kAlignPasses = 3;

constexpr double kPi = 3.14159265358979323846;

constexpr double kDecisiveBic = 10.0;

// The front end's terms on one channel, simplest first: a delay, a
// first-order low-pass, a second-order one (−1: not a front-end term of
// that kind).
int FrontEndOrder(const std::string& name) {
  const std::string base = name.substr(0, name.find('.'));
  if (base == "sensor_delay") return 0;
  if (base == "sensor_lowpass") return 1;
  if (base == "sensor_lowpass2") return 2;
  return -1;
}

using Clock = std::chrono::steady_clock;

// Wall time since `start`, s.
double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The progress line's fraction when it is not known.
constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();

// Above this s² (residual variance in units of the declared noise) the model
// error outweighs the noise and the score ranking is not trusted: the top
// significant candidates are all refitted (Discover). 2: the misfit's
// variance exceeds the noise's.
constexpr double kMisspecifiedS2 = 2.0;

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

}  // namespace

DiscoveryLoop::DiscoveryLoop(const DiscoverySettings& settings, EstimationProblem* job, FitResult* result,
                             std::ostream* progress, std::function<void(const char*)> stage)
    : settings_(settings),
      job_(job),
      result_(result),
      progress_(progress),
      first_horizon_(job->solver.first_horizon),
      status_(AsProgressStream(progress)),
      stage_(std::move(stage)) {}

DiscoveryReport DiscoveryLoop::Run() {
  if (status_ != nullptr) status_->BeginPhase("discovery");
  for (step_ = 0; step_ < settings_.max_effects; ++step_) {
    if (!ForwardStep()) break;
  }
  if (report_.stop_reason.empty()) report_.stop_reason = "maximum number of effects reached";
  BackwardPass();
  DropInsignificantEffects();
  DropNegligible(job_, result_, &report_, progress_);
  DiagnoseFinalModel();
  return std::move(report_);
}

// ---------------------------------------------------------------- a forward step

bool DiscoveryLoop::ForwardStep() {
  if (!RankStepCandidates()) return false;
  ChooseRule();
  RefitCandidates();
  return KeepLowest();
}

bool DiscoveryLoop::RankStepCandidates() {
  ApplyEstimates(*result_, job_);
  candidates_ = ListCandidates(*job_, settings_.candidates);
  if (candidates_.empty()) {
    report_.stop_reason = "no candidate left";
    return false;
  }
  step_name_ = "discovery step " + std::to_string(step_ + 1) + " (at most " +
               std::to_string(settings_.max_effects) + ")";
  if (stage_) stage_(step_name_.c_str());
  if (status_ != nullptr) {
    status_->Status(step_name_ + ": score tests of " + std::to_string(candidates_.size()) +
                        " candidates",
                    kUnknown);
  }
  const Clock::time_point ranking_start = Clock::now();
  ranking_ = RankCandidates(*job_, candidates_, settings_.alpha);
  report_.score_seconds += SecondsSince(ranking_start);
  ++report_.score_rankings;
  if (step_ == 0) report_.ranking = ranking_;
  threshold_ = settings_.alpha / candidates_.size();
  const Score& best = ranking_.scores.front();
  if (progress_) {
    *progress_ << "discovery step " << step_ + 1 << ": best candidate " << best.name
               << " (chi2 " << best.chi2 << ", dof " << best.dof << ", p "
               << best.p_value << ", threshold " << threshold_ << ")\n";
  }
  if (!(best.p_value < threshold_)) {
    report_.stop_reason = "no significant candidate (best " + best.name +
                          ", p = " + std::to_string(best.p_value) + ")";
    return false;
  }
  return true;
}

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
void DiscoveryLoop::ChooseRule() {
  const double s2 = result_->residual_variance;
  by_refit_ = s2 > kMisspecifiedS2;
  std::ostringstream rule;
  rule << std::setprecision(3);
  if (by_refit_) {
    rule << "lowest BIC of the refitted significant candidates (s^2 = " << s2
         << " > " << kMisspecifiedS2 << ": the score ranking is not reliable)";
  } else {
    rule << "first significant candidate in score order whose refit improves BIC (s^2 = "
         << s2 << ")";
  }
  rule_ = rule.str();
  if (progress_) *progress_ << "  rule: " << rule_ << "\n";
}

void DiscoveryLoop::RefitCandidates() {
  improved_.clear();
  queued_.clear();
  tries_ = 0;
  rejected_.clear();
  batch_.clear();
  level_ = {result_->bic, "the BIC before the step"};
  for (const Score& score : ranking_.scores) {
    if ((!by_refit_ && !improved_.empty()) ||
        tries_ >= (by_refit_ ? settings_.misspecified_tries : settings_.tries) ||
        !(score.p_value < threshold_)) {
      break;
    }
    // Candidates the data cannot tell from this one. A twin with more
    // parameters is a richer alternative (Stribeck contains a
    // Coulomb-like shape): parsimony keeps this one. A twin of the same
    // size is a rival explanation: the loop stops and says so.
    if (queued_.count(score.name) > 0) continue;  // refitted with its family
    // The front end's terms on one channel — a delay, a first- and a
    // second-order low-pass — have one score column to first order (a lag
    // of the channel's slope): the score test cannot tell them apart, their
    // refits can (they differ at second order). They are refitted together
    // and the lowest BIC decides, never a stop.
    const std::vector<std::string> family = FrontEndFamily(score);
    if (!family.empty()) {
      for (const std::string& name : family) {
        for (const Score& member : ranking_.scores) {
          if (member.name == name && member.p_value < threshold_) QueueRefit(member);
        }
      }
      if (!by_refit_) RunBatch();
      continue;
    }
    const std::string twin = TwinOf(score);
    // Beyond the top `tries` (misspecified rule only) a candidate with a
    // twin is passed over: the loop's stop is decided by the top ones.
    if (!twin.empty() && by_refit_ && tries_ >= settings_.tries) continue;
    if (!twin.empty()) {
      report_.stop_reason = score.name + " and " + twin +
                            " cannot be told apart on this data (projected "
                            "columns nearly parallel): add an experiment that "
                            "separates them, e.g. motion in both directions";
      break;
    }
    QueueRefit(score);
    if (!by_refit_) RunBatch();
  }
  QueueFrontEndCompanions();
  RunBatch();
}

// A channel with a front-end term already in the model (a delay kept at an
// earlier step, or declared) and its own residual still above its noise
// (ChannelAboveNoise; front_ends seed 15: the tachometer's filters
// refitted while only `a` was off, 12 refits, 246 s): the
// channel's other front-end terms are refitted whatever their score says.
// To first order a filter's lag is the delay's (MODEL.md §6), so once the
// delay has taken the lag the filter's score column lies in its span and
// its test sees nothing, while the filter's attenuation of the fast parts,
// its second-order part, is still in the residual (issue 56: a 10.5-sample
// advance behind a 310 Hz low-pass kept as the delay alone at s² = 2.1,
// and a payload then stood in for the filter). The refits and BIC decide,
// with the simpler front end kept within kDecisiveBic (SimplestFrontEnd).
// Each once until the front end changes again: refitted at every later
// step, the rejected filters took 100–220 s of a 530 s run on the
// independent front-end campaign (seed 17).
void DiscoveryLoop::QueueFrontEndCompanions() {
  const SensorSwitches& on = job_->model.structure.sensors;
  for (const Score& score : ranking_.scores) {
    if (queued_.count(score.name) > 0 || FrontEndOrder(score.name) < 0 ||
        companions_tried_.count(score.name) > 0) {
      continue;
    }
    const Candidate& c = *std::find_if(candidates_.begin(), candidates_.end(),
                                       [&](const Candidate& x) { return x.name == score.name; });
    const int k = static_cast<int>(c.channel);
    if (!(on.delay[k] || on.lowpass[k] || on.lowpass2[k]) || !ChannelAboveNoise(k)) continue;
    companions_tried_.insert(score.name);
    QueueRefit(score);
  }
}

bool DiscoveryLoop::ChannelAboveNoise(int k) const {
  const std::string name = ChannelName(static_cast<Channel>(k));
  double chi2 = 0.0, n = 0.0;
  for (const ExperimentFit& e : result_->experiments) {
    if (e.role != "fit") continue;
    for (const ChannelFit& c : e.channels) {
      if (!c.fitted || c.channel != name || !(c.sigma > 0.0)) continue;
      const double samples = static_cast<double>(c.measured.size());
      chi2 += samples * (c.rms / c.sigma) * (c.rms / c.sigma);
      n += samples;
    }
  }
  return n > 0.0 && chi2 - n > 3.0 * std::sqrt(2.0 * n);
}

std::vector<std::string> DiscoveryLoop::FrontEndFamily(const Score& score) const {
  std::vector<std::string> family;
  for (const auto& [a, b] : ranking_.indistinguishable) {
    const std::string other = a == score.name ? b : (b == score.name ? a : "");
    if (other.empty() || !SameChannelFrontEnd(score.name, other)) continue;
    if (family.empty()) family.push_back(score.name);
    if (std::find(family.begin(), family.end(), other) == family.end()) family.push_back(other);
  }
  return family;
}

std::string DiscoveryLoop::TwinOf(const Score& score) const {
  std::string twin;
  for (const auto& [a, b] : ranking_.indistinguishable) {
    const std::string other = a == score.name ? b : (b == score.name ? a : "");
    if (!other.empty() && DofOf(other) <= score.dof) twin = other;
  }
  return twin;
}

int DiscoveryLoop::DofOf(const std::string& name) const {
  for (const Score& sc : ranking_.scores) {
    if (sc.name == name) return sc.dof;
  }
  return 0;
}

void DiscoveryLoop::QueueRefit(const Score& score) {
  const Candidate& chosen = *std::find_if(
      candidates_.begin(), candidates_.end(),
      [&](const Candidate& c) { return c.name == score.name; });
  queued_.insert(score.name);
  Pending q{&score, chosen, RefitJobs(chosen, score), {}, {}};
  for (size_t k = job_->free.size(); k < q.starts[0].free.size(); ++k) {
    q.names.push_back(q.starts[0].free[k].name);
  }
  if (IsFilterAfterDelay(chosen)) {
    q.labels = {"tau = 0.5 output period", "tau = 1 output period", "tau = 2 output periods"};
  }
  ++tries_;
  batch_.push_back(std::move(q));
}

// One start each, no optimum check, Gauss–Newton intervals; but the
// horizon continuation stays: from the optimum with the effect at its
// score step, the whole record at once ended in higher minima (EMPS: the
// Stribeck refit at BIC 1.145e4 instead of 1.135e4, B_a 379 instead of 153
// N·s/m; coulomb_viscous_asymmetry: motor-side Coulomb friction at 3.2e6
// instead of 2.6e5), so refits with an effect added keep it.
std::vector<EstimationProblem> DiscoveryLoop::RefitJobs(const Candidate& candidate,
                                             const Score& score) const {
  std::vector<EstimationProblem> out;
  if (IsFilterAfterDelay(candidate)) return FilterAfterDelayJobs(candidate, score);
  const Score start = DelayStart(candidate, score);
  for (size_t k = 0; k < StartsOf(candidate); ++k) {
    EstimationProblem refit = *job_;
    AddEffect(candidate, start, k, &refit);
    AsWarmRefit(&refit);
    refit.solver.first_horizon = first_horizon_;
    out.push_back(std::move(refit));
  }
  return out;
}

// A delay's score step is its first-order estimate, a lag times the
// channel's slope: good to a fraction of a sample. Where the records line up
// with the simulation at a lag more than half a sample away from it
// (estimation/alignment_lag.h, searched over a quarter of the longest
// record), the refit starts from that lag instead.
Score DiscoveryLoop::DelayStart(const Candidate& candidate, const Score& score) const {
  if (candidate.effect != "sensor_delay" || score.step.empty()) return score;
  double period = 0.0, longest = 0.0;
  for (const FitExperiment& e : job_->experiments) {
    for (const FittedChannel& f : e.fitted) {
      if (f.channel != candidate.channel) continue;
      period = std::max(period, e.options.output_period);
      longest = std::max(longest, e.t.empty() ? 0.0 : e.t.back());
    }
  }
  const double lag = AlignmentLag(*result_, ChannelName(candidate.channel), 0.25 * longest);
  if (!std::isfinite(lag) || !(std::abs(lag - score.step[0]) > 0.5 * period)) return score;
  Score from_lag = score;
  from_lag.step[0] = lag;
  if (progress_) {
    *progress_ << "  " << candidate.name << ": the records line up at a lag of " << lag
               << " s (score step " << score.step[0] << " s): the refit starts there\n";
  }
  return from_lag;
}

// improved_[lowest], or a simpler front-end term of the same channel whose
// BIC is above it by at most kDecisiveBic (the simplest such).
size_t DiscoveryLoop::SimplestFrontEnd(size_t lowest) const {
  const std::string& best = improved_[lowest].candidate.name;
  size_t chosen = lowest;
  for (size_t k = 0; k < improved_.size(); ++k) {
    const std::string& name = improved_[k].candidate.name;
    if (k == lowest || !SameChannelFrontEnd(name, best) || FrontEndOrder(name) < 0) continue;
    if (FrontEndOrder(name) < FrontEndOrder(improved_[chosen].candidate.name) &&
        improved_[k].fit.bic - improved_[lowest].fit.bic <= kDecisiveBic) {
      chosen = k;
    }
  }
  return chosen;
}

bool DiscoveryLoop::IsFilterAfterDelay(const Candidate& candidate) const {
  const std::string& effect = candidate.effect;
  return (effect == "sensor_lowpass" || effect == "sensor_lowpass2") &&
         job_->model.structure.sensors.delay[static_cast<int>(candidate.channel)];
}

// A filter added beside a delay that has taken its lag starts at a time
// constant of its own: half, one and two output periods (at least 1.2·T/π,
// inside the record's band), the delay shortened by the filter's lag (τ,
// or 2ζ·τ for the second order), each refitted from the current estimate
// with the horizon continuation (as RefitJobs). From its score step (zero: the delay took the lag)
// the refit stays next to no filter, where the delay is the better
// explanation (issue 56: τ = 26 µs, above Nyquist, BIC worse than without).
std::vector<EstimationProblem> DiscoveryLoop::FilterAfterDelayJobs(const Candidate& candidate,
                                                                  const Score& score) const {
  const double period = FittedPeriod(*job_, candidate.channel);
  const std::string channel = ChannelName(candidate.channel);
  const bool second = candidate.effect == "sensor_lowpass2";
  const std::string tau_name = (second ? "tau_lp2." : "tau_lp.") + channel;
  const std::string delay_name = "tau_d." + channel;
  std::vector<EstimationProblem> out;
  for (double periods : {0.5, 1.0, 2.0}) {
    EstimationProblem refit = *job_;
    AddEffect(candidate, score, 0, &refit);
    const double tau = std::max(periods * period, 1.2 * period / kPi);
    const double lag = second ? 2.0 * kButterworthDamping * tau : tau;
    for (FreeParameter& f : refit.free) {
      if (f.name == tau_name) f.initial = tau;
      if (f.name == delay_name) f.initial = std::clamp(f.initial - lag, f.lower, f.upper);
    }
    *FindParam(&refit.model.params, tau_name) = tau;
    double* delay = FindParam(&refit.model.params, delay_name);
    *delay -= lag;
    AsWarmRefit(&refit);
    refit.solver.first_horizon = first_horizon_;  // as the other refits (RefitJobs)
    out.push_back(std::move(refit));
  }
  return out;
}

bool DiscoveryLoop::KeepLowest() {
  if (improved_.empty()) {
    if (report_.stop_reason.empty()) {
      report_.stop_reason = "no significant candidate improved BIC (tried " + rejected_ + ")";
    }
    return false;
  }
  size_t lowest = 0;
  for (size_t k = 1; k < improved_.size(); ++k) {
    if (improved_[k].fit.bic < improved_[lowest].fit.bic) lowest = k;
  }
  const size_t chosen = SimplestFrontEnd(lowest);
  for (size_t k = 0; k < improved_.size(); ++k) {
    if (k == chosen) continue;
    DiscoveryStep& other = report_.steps[improved_[k].step];
    other.kept = false;
    std::ostringstream why;
    if (k == lowest) {
      why << "BIC " << other.bic_after << " below " << improved_[chosen].candidate.name
          << "'s " << improved_[chosen].fit.bic << " by less than " << kDecisiveBic
          << ": the simpler front end is kept";
    } else {
      why << "BIC " << other.bic_after << " above " << improved_[chosen].candidate.name
          << "'s " << improved_[chosen].fit.bic;
    }
    other.outranked = why.str();
  }
  lowest = chosen;
  Trial& winner = improved_[lowest];
  if (progress_) *progress_ << "  kept " << winner.candidate.name << "\n";
  report_.selected.push_back(winner.candidate.name);
  if (FrontEndOrder(winner.candidate.name) >= 0) companions_tried_.clear();
  *job_ = std::move(winner.job);
  *result_ = std::move(winner.fit);
  TrimAheadOfTheRecords();
  return true;
}

// A channel read ahead of its time (a sensor delay below zero, MODEL.md §6)
// shows in its last |τ_d| seconds what the input after the record's end
// made of the motion, and the record does not hold that input: no model
// can predict those samples (issue 56: records 10.5 and 14.2 samples early,
// their last samples 19 sigma off under the true model, a payload then
// kept to bend the fit toward them). Once the model holds such a delay,
// every record's last 1.5·|τ_d| + 2 output periods are no longer fitted
// (still simulated, so that the channel read ahead sees the motion there),
// the current model is refitted on what is left, and the later steps
// compare their refits on the same samples. Trimmed again, from the whole
// records, if a later delay reads further ahead.
void DiscoveryLoop::TrimAheadOfTheRecords() {
  double ahead = 0.0, period = 0.0;
  for (const FitExperiment& e : job_->experiments) {
    period = std::max(period, e.options.output_period);
    for (const FittedChannel& f : e.fitted) {
      const int k = static_cast<int>(f.channel);
      if (job_->model.structure.sensors.delay[k]) {
        ahead = std::max(ahead, -job_->model.params.tau_d[k]);
      }
    }
  }
  const double trim = 1.5 * ahead + 2.0 * period;
  if (!(ahead > 0.5 * period) || !(trim > trimmed_ + 0.5 * period)) return;
  if (whole_records_.empty()) whole_records_ = job_->experiments;
  for (size_t i = 0; i < whole_records_.size(); ++i) {
    const FitExperiment& whole = whole_records_[i];
    if (whole.t.empty() || whole.t.back() <= trim) continue;
    FitExperiment cut = Truncate(whole, whole.t.back() - trim, trim);
    cut.options.duration = whole.options.duration;  // simulated to the record's end
    job_->experiments[i] = std::move(cut);
  }
  trimmed_ = trim;
  EstimationProblem refit = *job_;
  ApplyEstimates(*result_, &refit);
  AsWarmRefit(&refit);
  FitResult again = FitParameters(refit, nullptr);
  if (!std::isfinite(again.bic)) return;
  *job_ = std::move(refit);
  *result_ = std::move(again);
  std::ostringstream note;
  note << "the last " << trim << " s of each record are not fitted: channel read "
       << ahead << " s ahead of its time (a sensor delay below zero) shows there the "
       << "response to input past the record's end; the model was refitted without them";
  report_.notes.push_back(note.str());
  if (progress_) *progress_ << "  note: " << note.str() << "\n";
}

// ---------------------------------------------------------------- a batch of refits

void DiscoveryLoop::RunBatch() {
  if (batch_.empty()) return;  // the call after the loop, all run already
  ShowBatchStatus();
  ScreenBatch();
  CutAfterScreen();
  RunAgainstLevel();
  for (size_t b = 0; b < batch_.size(); ++b) {
    if (goes_on_[b]) {
      JudgeCandidate(b);
    } else {
      RecordCut(b);
    }
  }
  batch_.clear();
}

void DiscoveryLoop::ShowBatchStatus() const {
  std::string names;
  for (const Pending& q : batch_) names += (names.empty() ? "" : ", ") + q.candidate.name;
  if (status_ != nullptr && !batch_.empty()) {
    status_->BeginPhase("refits");
    status_->Status(step_name_ + ": " +
                        (batch_.size() == 1
                             ? "candidate refit " + std::to_string(tries_) + " of at most " +
                                   std::to_string(settings_.tries) + " (" + names + ")"
                             : "refitting " + std::to_string(batch_.size()) +
                                   " candidates at once (" + names + ")"),
                    kUnknown);
  }
}

// The screen (several candidates, a horizon continuation): every refit
// runs the first kScreenStages horizons only
// (FitControl::stop_after_horizon), and the refits then run in the order
// of their BICs' lower bounds there, lowest first, so that the leading
// refits are the likeliest to set a low level. The order changes only
// which refits stop early, not which wins (the lowest BIC of those that
// run to the end).
void DiscoveryLoop::ScreenBatch() {
  order_ = std::vector<size_t>(batch_.size());
  std::iota(order_.begin(), order_.end(), size_t{0});
  screen_seconds_.assign(batch_.size(), 0.0);
  screen_bound_.assign(batch_.size(), std::numeric_limits<double>::infinity());
  // The screen's shorter horizons, per candidate and start, which its
  // refit goes on after instead of running them again
  // (FitControl::resume): the same points, costs and stops, up to
  // the last bits of a cost summed on another number of threads (the
  // leader's refit runs on more than its screen did). On the
  // coulomb_load_offset case (issue 11) 17.0 → 15.1 s whole process,
  // the same steps and stops, estimates equal to 12 digits.
  resume_ = std::vector<std::vector<std::shared_ptr<const HorizonCheckpoint>>>(batch_.size());
  if (batch_.size() > 1 && first_horizon_ > 0.0) {
    std::vector<EstimationProblem> screen;
    for (const Pending& q : batch_) screen.insert(screen.end(), q.starts.begin(), q.starts.end());
    const std::vector<ScreenedFit> screened = ScreenFits(std::move(screen), job_->solver.threads);
    std::vector<double> key(batch_.size(), std::numeric_limits<double>::infinity());
    size_t k = 0;
    for (size_t c = 0; c < batch_.size(); ++c) {
      resume_[c].resize(batch_[c].starts.size());
      for (size_t s = 0; s < batch_[c].starts.size(); ++s, ++k) {
        key[c] = std::min(key[c], screened[k].bound);
        screen_seconds_[c] += screened[k].seconds;
        resume_[c][s] = screened[k].checkpoint;
      }
    }
    std::stable_sort(order_.begin(), order_.end(),
                     [&](size_t x, size_t y) { return key[x] < key[y]; });
    screen_bound_ = key;
  }
}

// By the lowest BIC rule (by_refit_) only the candidates GoOnPastScreen
// names (discovery/internal/screen.h): the top `tries` by score or by the screen's
// bound, and those whose screen failed.
void DiscoveryLoop::CutAfterScreen() {
  const size_t n = batch_.size();
  goes_on_.assign(n, true);
  if (by_refit_) {
    std::vector<size_t> score_rank(n);
    for (size_t b = 0; b < n; ++b) score_rank[b] = ScoreRank(b);
    goes_on_ = GoOnPastScreen(score_rank, screen_bound_,
                              static_cast<size_t>(std::max(1, settings_.tries)));
  }
  order_.erase(std::remove_if(order_.begin(), order_.end(),
                              [&](size_t c) { return !goes_on_[c]; }),
               order_.end());
}

// The refits in that order. The leading one, the first candidate's (every
// start, each fit's evaluation on the threads left), runs before the
// others so that it can set the level; the rest run after, stopped above
// it. (The first two candidates as leaders, one per core, were slower on
// the coulomb_load_offset case, 58.7 against 48.6 s: after the screen the
// second leader was the payload, whose refit ran 16 s to BIC 2.6e5 beside
// Coulomb friction's 1.2e4.)
void DiscoveryLoop::RunAgainstLevel() {
  pos_.assign(batch_.size(), 0);
  level_of_.assign(batch_.size(), level_);
  fits_.clear();
  seconds_.clear();
  cut_.clear();
  cut_bound_.clear();
  runs_done_ = 0;
  RunCandidates(order_.begin(), order_.begin() + 1);
  if (order_.size() > 1) {
    SetLevelFromLeader();
    // The others all run against the same level, so their order only
    // decides which finish first: the longest screens first
    // (longest-processing-time order, the screen's time standing in
    // for the refit's), so that a long refit does not start last.
    std::stable_sort(order_.begin() + 1, order_.end(), [&](size_t x, size_t y) {
      return screen_seconds_[x] > screen_seconds_[y];
    });
    RunCandidates(order_.begin() + 1, order_.end());
  }
}

// On copies of their starts (those in batch_, one of which the loop may
// adopt, keep no level and no checkpoint); pos_[c]: candidate c's first
// start in fits_, level_of_[c]: the level it ran against. The starts of a
// candidate with more of them than solver.finalists stop before the whole
// record and only its finalists go on (ContinueFinalists), as
// FitParameters does with the starts of one fit (estimation/fit.h: the
// solver.finalists lowest on the longest shorter horizon fit the whole
// record; here ranked by the BIC bound there, which takes the lower of the
// stage's end and the start's own cost). The starts of a filter beside a delay
// ended together: on the independent square + sweep records their three
// whole-record stages, 0.8–3.5 s each, reached the same cost to 1e-4
// where their 3.2 s stages had differed by 30.
void DiscoveryLoop::RunCandidates(std::vector<size_t>::const_iterator from,
                                  std::vector<size_t>::const_iterator to) {
  std::vector<EstimationProblem> jobs;
  std::vector<FitControl> controls;
  std::vector<size_t> owner;
  for (auto it = from; it != to; ++it) {
    pos_[*it] = fits_.size() + jobs.size();
    level_of_[*it] = level_;
    for (size_t k = 0; k < batch_[*it].starts.size(); ++k) {
      jobs.push_back(batch_[*it].starts[k]);
      FitControl control;
      control.abandon_above_bic = kStopFactor * level_.bic;
      if (k < resume_[*it].size()) control.resume = resume_[*it][k];
      control.stop_before_whole_record = batch_[*it].starts.size() > Finalists();
      controls.push_back(std::move(control));
      owner.push_back(*it);
    }
  }
  std::vector<double> secs;
  std::vector<FitResult> out =
      FitConcurrently(jobs, job_->solver.threads, &secs, controls, RefitProgress(runs_done_));
  runs_done_ += jobs.size();
  cut_.resize(fits_.size() + jobs.size(), false);
  cut_bound_.resize(fits_.size() + jobs.size(), std::numeric_limits<double>::quiet_NaN());
  ContinueFinalists(jobs, controls, owner, &out, &secs, fits_.size());
  fits_.insert(fits_.end(), std::make_move_iterator(out.begin()),
               std::make_move_iterator(out.end()));
  seconds_.insert(seconds_.end(), secs.begin(), secs.end());
}

namespace {

// Whether `fit` (run with `control`) stopped before the whole record at
// control.stop_before_whole_record's horizon, not on its BIC bound.
bool StoppedBeforeWholeRecord(const FitResult& fit, const FitControl& control) {
  return control.stop_before_whole_record && fit.abandoned_horizon > 0.0 &&
         fit.checkpoint != nullptr && std::isfinite(fit.bic) &&
         !(fit.bic > control.abandon_above_bic);
}

}  // namespace

void DiscoveryLoop::ContinueFinalists(const std::vector<EstimationProblem>& jobs,
                                      const std::vector<FitControl>& controls,
                                      const std::vector<size_t>& owner,
                                      std::vector<FitResult>* out, std::vector<double>* secs,
                                      size_t first) {
  const size_t finalists = Finalists();
  // Per round: the starts that go on (indices into jobs), lowest bound first
  // per candidate; the second round only where every finalist failed.
  std::vector<size_t> waiting;  // stopped before the whole record, not yet run on
  for (size_t j = 0; j < jobs.size(); ++j) {
    if (StoppedBeforeWholeRecord((*out)[j], controls[j])) waiting.push_back(j);
  }
  std::stable_sort(waiting.begin(), waiting.end(),
                   [&](size_t x, size_t y) { return (*out)[x].bic < (*out)[y].bic; });
  for (int round = 0; round < 2 && !waiting.empty(); ++round) {
    std::vector<size_t> go;
    std::vector<size_t> taken_per(batch_.size(), 0);
    for (size_t j : waiting) {
      if (round == 1 || taken_per[owner[j]] < finalists) {
        go.push_back(j);
        ++taken_per[owner[j]];
      }
    }
    std::vector<EstimationProblem> again;
    std::vector<FitControl> again_controls;
    for (size_t j : go) {
      again.push_back(jobs[j]);
      FitControl control = controls[j];
      control.stop_before_whole_record = false;
      control.resume = (*out)[j].checkpoint;
      again_controls.push_back(std::move(control));
    }
    std::vector<double> again_secs;
    std::vector<FitResult> ends = FitConcurrently(again, job_->solver.threads, &again_secs,
                                                  again_controls, RefitProgress(runs_done_));
    runs_done_ += again.size();
    std::vector<bool> ran(jobs.size(), false);
    for (size_t g = 0; g < go.size(); ++g) {
      (*out)[go[g]] = std::move(ends[g]);
      (*secs)[go[g]] += again_secs[g];
      ran[go[g]] = true;
    }
    // The rest wait (as not continued) unless every finalist of their
    // candidate failed.
    std::vector<bool> failed(batch_.size(), true);
    for (size_t j : go) {
      if (std::isfinite((*out)[j].bic)) failed[owner[j]] = false;
    }
    std::vector<size_t> left;
    for (size_t j : waiting) {
      if (ran[j]) continue;
      if (failed[owner[j]]) {
        left.push_back(j);
      } else {
        cut_[first + j] = true;
        cut_bound_[first + j] = (*out)[j].bic;
        (*out)[j].bic = std::numeric_limits<double>::infinity();
      }
    }
    waiting = std::move(left);
  }
}

size_t DiscoveryLoop::Finalists() const {
  return static_cast<size_t>(std::max(1, job_->solver.finalists));
}

// The progress line while a batch's refits run: k of n done, with the
// phase's remaining time extrapolated (common/progress.h); n counts every
// start of the candidates that went on past the screen, and for a
// candidate of more starts than finalists its finalists' runs to the whole
// record (a start stopped on its bound, or failed, leaves n a little high;
// k is kept at most n).
std::function<void(size_t, size_t)> DiscoveryLoop::RefitProgress(size_t already) {
  if (status_ == nullptr) return {};
  size_t total = 0;
  for (size_t c : order_) {
    const size_t n = batch_[c].starts.size();
    total += n + (n > Finalists() ? Finalists() : 0);
  }
  return [this, already, total](size_t done, size_t) {
    const size_t k = std::min(already + done, total);
    status_->Status(step_name_ + ": refits " + std::to_string(k) + " of " +
                        std::to_string(total) + " done",
                    total > 0 ? static_cast<double>(k) / static_cast<double>(total) : kUnknown);
  };
}

// The leader's BIC becomes the level if it ran to the end below it and
// would be kept (a physical value).
void DiscoveryLoop::SetLevelFromLeader() {
  const Pending& q = batch_[order_[0]];
  for (size_t s = 0; s < q.starts.size(); ++s) {
    const FitResult& fit = fits_[s];
    if (fit.abandoned_horizon == 0.0 && std::isfinite(fit.bic) && fit.bic < level_.bic &&
        ImplausibleValue(q.candidate.name, fit, q.starts[s]).empty()) {
      level_ = {fit.bic, q.candidate.name + "'s BIC"};
    }
  }
}

size_t DiscoveryLoop::ScoreRank(size_t b) const {
  return static_cast<size_t>(batch_[b].score - ranking_.scores.data()) + 1;
}

void DiscoveryLoop::RecordCut(size_t b) {
  const Pending& q = batch_[b];
  DiscoveryStep record = StepOf(q);
  record.bic_after = screen_bound_[b];
  record.seconds = screen_seconds_[b];
  std::ostringstream why;
  why << std::setprecision(4) << "after the screen: BIC >= " << screen_bound_[b] << " at the "
      << ScreenHorizon(first_horizon_) << " s horizon, " << RanksByBound(screen_bound_)[b]
      << " of " << batch_.size() << " there, and " << ScoreRank(b)
      << " by score: only the top " << std::max(1, settings_.tries)
      << " by either went on to the whole record";
  record.stopped = why.str();
  record.kept = false;
  report_.steps.push_back(record);
  PrintRefit(q, record);
  rejected_ += (rejected_.empty() ? "" : ", ") + q.candidate.name;
}

// Candidate b's refit as a step of the report; one that improved BIC
// waits in improved_ for the step's choice.
void DiscoveryLoop::JudgeCandidate(size_t b) {
  Pending& q = batch_[b];
  const size_t n = q.starts.size();
  const size_t first = pos_[b];  // q's first start in fits_
  std::vector<FitResult> own(fits_.begin() + first, fits_.begin() + first + n);
  DiscoveryStep record = StepOf(q);
  record.seconds = screen_seconds_[b];
  for (size_t k = 0; k < n; ++k) record.seconds += seconds_[first + k];
  const size_t best = ChooseStart(b, &own, &record);
  FitResult& refit = own[best];
  EstimationProblem& refit_job = q.starts[best];
  RecordRefit(q, level_of_[b], refit, refit_job, &record);
  report_.steps.push_back(record);
  PrintRefit(q, record);
  if (!record.kept) {
    rejected_ += (rejected_.empty() ? "" : ", ") + q.candidate.name;
    return;
  }
  improved_.push_back({report_.steps.size() - 1, q.candidate, std::move(refit_job),
                       std::move(refit)});
}

size_t DiscoveryLoop::ChooseStart(size_t b, std::vector<FitResult>* own,
                                  DiscoveryStep* record) {
  const size_t n = batch_[b].starts.size();
  size_t best = LowestFiniteBic(*own);
  if (best == n) best = RetryFromTenth(b, own, record);
  if (n > 1) record->starts = StartsText(b, *own, best);
  if (best == n) best = 0;  // none finite: report the first
  // An added parameter that ended on a bound of its search interval
  // (Linear: the score step ± 100 times it + 1): the step was too
  // small a guide (the base fit had absorbed most of the effect:
  // a record in motion, Coulomb friction's step 0.11 N where the
  // truth is 40 N, B_a at 455 instead of 200 N·s/m), so that side is
  // widened 100-fold and the refit continued from where it ended.
  if (std::isfinite((*own)[best].bic) && (*own)[best].abandoned_horizon == 0.0) {
    WidenIfOnBound(b, best, own, record);
    RealignDelay(b, best, own, record);
  }
  return best;
}

// Seen on the power_load_offset campaign (seed 4, s² = 204): the offset,
// first by score, failed in 0.27 s from its score step and a stand-in
// (cogging) took the step. Since the refits solve without the projected
// line search (EstimationProblem::no_line_search) that seed's refits no
// longer fail from the score step, and no test reaches this path.
size_t DiscoveryLoop::RetryFromTenth(size_t b, std::vector<FitResult>* own,
                                     DiscoveryStep* record) {
  Pending& q = batch_[b];
  Score damped = *q.score;
  for (double& x : damped.step) x *= 0.1;
  for (double& x : damped.single_step) x *= 0.1;
  q.starts = RefitJobs(q.candidate, damped);
  FitControl control;
  control.abandon_above_bic = kStopFactor * level_.bic;
  level_of_[b] = level_;
  std::vector<double> again;
  *own = FitConcurrently(q.starts, job_->solver.threads, &again,
                         std::vector<FitControl>(q.starts.size(), control));
  for (double s : again) record->seconds += s;
  const size_t best = LowestFiniteBic(*own);
  record->retried = "refit from the score step failed; retried from a tenth of it";
  return best;
}

std::string DiscoveryLoop::StartsText(size_t b, const std::vector<FitResult>& own,
                                      size_t best) const {
  const Pending& q = batch_[b];
  const size_t n = q.starts.size();
  std::ostringstream starts;
  starts << std::setprecision(4) << n << " starts, BIC";
  const size_t first = pos_[b];
  for (size_t k = 0; k < n; ++k) {
    starts << (k == 0 ? " " : ", ");
    if (cut_[first + k]) {
      starts << "not continued (>= " << cut_bound_[first + k] << " at the "
             << own[k].abandoned_horizon << " s horizon)";
    } else {
      starts << (own[k].abandoned_horizon > 0.0 ? ">= " : "") << own[k].bic;
    }
    starts << " from " << (k < q.labels.size() ? q.labels[k] : StartLabel(q.candidate, k));
  }
  if (best < n) {
    starts << "; kept the start from "
           << (best < q.labels.size() ? q.labels[best] : StartLabel(q.candidate, best));
  }
  return starts.str();
}

// A delay refitted from a lag the base fit's simulation suggested can stop
// in a local minimum a few samples off: the base fit, without the delay,
// had bent the plant's parameters toward it, so its simulation lined up
// with the records at only part of the lag (issue 56: records 10.5 samples
// early, aligned at 5.7, the refit stuck at s² = 2.1). The refit's own
// simulation is nearer the truth: while it lines up with the records at a
// lag more than half a sample away (estimation/alignment_lag.h), the delay
// is moved by that lag and the refit continued, kAlignPasses times at most,
// keeping each that lowers BIC.
void DiscoveryLoop::RealignDelay(size_t b, size_t best, std::vector<FitResult>* own,
                                 DiscoveryStep* record) {
  Pending& q = batch_[b];
  if (q.candidate.effect != "sensor_delay") return;
  const std::string channel = ChannelName(q.candidate.channel);
  const std::string name = "tau_d." + channel;
  const double period = FittedPeriod(*job_, q.candidate.channel);
  double longest = 0.0;
  for (const FitExperiment& e : job_->experiments) {
    for (const FittedChannel& f : e.fitted) {
      if (f.channel == q.candidate.channel) longest = std::max(longest, e.t.empty() ? 0.0 : e.t.back());
    }
  }
  for (int pass = 0; pass < kAlignPasses; ++pass) {
    const FitResult& now = (*own)[best];
    const double lag = AlignmentLag(now, channel, 0.25 * longest);
    if (!std::isfinite(lag) || !(std::abs(lag) > 0.5 * period)) return;
    EstimationProblem moved = q.starts[best];
    ApplyEstimates(now, &moved);
    for (FreeParameter& f : moved.free) {
      if (f.name != name) continue;
      const double tau = f.initial + lag;
      const double reach = std::max(std::abs(f.lower), std::abs(f.upper));
      f.lower = std::min(f.lower, tau - reach);
      f.upper = std::max(f.upper, tau + reach);
      f.initial = tau;
      *FindParam(&moved.model.params, name) = tau;
    }
    const Clock::time_point again = Clock::now();
    FitResult further = FitParameters(moved, nullptr);
    record->seconds += SecondsSince(again);
    if (!(std::isfinite(further.bic) && further.bic < now.bic)) return;
    (*own)[best] = std::move(further);
    q.starts[best] = std::move(moved);
    std::ostringstream why;
    why << "the refit's simulation lined up with the records " << lag
        << " s further; the delay moved and refitted (" << pass + 1 << " time(s))";
    record->realigned = why.str();
  }
}

void DiscoveryLoop::WidenIfOnBound(size_t b, size_t best, std::vector<FitResult>* own,
                                   DiscoveryStep* record) {
  Pending& q = batch_[b];
  EstimationProblem wider = q.starts[best];
  if (WidenSearchBounds((*own)[best], q.names, &wider)) {
    ApplyEstimates((*own)[best], &wider);
    const Clock::time_point again = Clock::now();
    FitResult further = FitParameters(wider, nullptr);
    record->seconds += std::chrono::duration<double>(Clock::now() - again).count();
    if (std::isfinite(further.bic) && further.bic < (*own)[best].bic) {
      (*own)[best] = std::move(further);
      q.starts[best] = std::move(wider);
      record->widened = "an added parameter ended on its search bound; refitted "
                        "with that bound widened 100-fold";
    }
  }
}

DiscoveryStep DiscoveryLoop::StepOf(const Pending& q) const {
  DiscoveryStep record;
  record.effect = q.candidate.name;
  record.rule = rule_;
  record.chi2 = q.score->chi2;
  record.dof = q.score->dof;
  record.p_value = q.score->p_value;
  record.bic_before = result_->bic;
  return record;
}

void DiscoveryLoop::RecordRefit(const Pending& q, const Level& level, const FitResult& refit,
                                const EstimationProblem& refit_job, DiscoveryStep* record) const {
  record->bic_after = refit.bic;
  record->stopped = StoppedText(refit, level.bic, level.name);
  if (record->stopped.empty()) {
    record->implausible = ImplausibleValue(q.candidate.name, refit, refit_job);
    for (const ParameterEstimate& e : refit.parameters) {
      if (e.free && std::find(q.names.begin(), q.names.end(), e.name) != q.names.end()) {
        record->parameters.push_back(e);
      }
    }
    record->channels = ChannelChanges(*result_, refit);
  }
  record->kept =
      refit.bic < result_->bic && record->implausible.empty() && record->stopped.empty();
}

void DiscoveryLoop::PrintRefit(const Pending& q, const DiscoveryStep& record) const {
  if (!progress_) return;
  *progress_ << "  refit with " << q.candidate.name << ": BIC " << record.bic_before
             << " -> " << BoundMark(record) << record.bic_after
             << (record.kept ? " (improves)" : " (rejected)")
             << (record.implausible.empty() ? "" : ": " + record.implausible)
             << (record.stopped.empty() ? "" : ": stopped " + record.stopped)
             << (record.retried.empty() ? "" : " (" + record.retried + ")")
             << (record.widened.empty() ? "" : " (" + record.widened + ")")
             << (record.realigned.empty() ? "" : " (" + record.realigned + ")")
             << (record.starts.empty() ? "" : " (" + record.starts + ")")
             << " (" << record.seconds << " s)\n";
}

// ---------------------------------------------------------------- after the forward steps

// Backward pass: without each added effect but the last, in the order they
// were added, each refit from the model the earlier removals left. Up to
// solver.threads of the refits from the current model run at once
// (RefitsWithout: most effects stay, and those refits are the ones one
// after the other would run); after a removal the later ones of the batch
// are dropped and run again from the model without it (with one thread a
// batch is one refit: the pass one after the other).
void DiscoveryLoop::BackwardPass() {
  const std::vector<std::string> added = report_.selected;
  if (status_ != nullptr) status_->BeginPhase("backward pass");
  if (stage_) stage_("discovery backward pass");
  const size_t width = static_cast<size_t>(std::max(1, job_->solver.threads));
  size_t next = 0;  // the first of `added` not yet decided
  while (next + 1 < added.size()) {
    std::vector<size_t> index;
    std::vector<Candidate> batch;
    for (size_t k = next; k + 1 < added.size() && batch.size() < width; ++k) {
      const Candidate candidate = CandidateNamed(added[k]);
      if (RefinedInModel(candidate.effect, job_->model.structure)) continue;
      index.push_back(k);
      batch.push_back(candidate);
    }
    if (batch.empty()) break;
    if (status_ != nullptr) {
      std::string names;
      for (const Candidate& c : batch) names += (names.empty() ? "" : ", ") + c.name;
      status_->Status(std::string("discovery backward pass: refit without ") +
                          (batch.size() > 1 ? "each of " : "") + names + " (" +
                          std::to_string(index.back() + 1) + " of " +
                          std::to_string(added.size() - 1) + ")",
                      static_cast<double>(next) / static_cast<double>(added.size() - 1));
    }
    std::vector<Removal> removals = RefitsWithout(batch, job_, *result_);
    next = index.back() + 1;
    for (size_t b = 0; b < batch.size(); ++b) {
      Removal& r = removals[b];
      report_.steps.push_back(r.record);
      if (progress_) {
        *progress_ << "  refit without " << batch[b].name << ": BIC " << r.record.bic_before
                   << " -> " << BoundMark(r.record) << r.record.bic_after
                   << (r.record.kept ? " (removed)" : " (stays)")
                   << (r.record.stopped.empty() ? "" : ": stopped " + r.record.stopped) << "\n";
      }
      if (r.record.kept) {
        DropEffect(batch[b].name, std::move(r.without), std::move(r.refit), job_, result_,
                   &report_);
        next = index[b] + 1;  // the later ones again, from the model without it
        break;
      }
    }
  }
}

void DiscoveryLoop::DropInsignificantEffects() {
  report_.level = settings_.alpha / std::max<size_t>(1, report_.ranking.scores.size());
  DropInsignificant(report_.level, job_, result_, &report_, progress_);
}

void DiscoveryLoop::DiagnoseFinalModel() {
  if (status_ != nullptr) status_->Status("discovery: diagnosing the final model", kUnknown);
  report_.final_diagnostics = DiagnoseResiduals(*job_);
  report_.verdict = JudgeResiduals(report_.final_diagnostics, *result_, settings_.alpha);
}

}  // namespace axis
