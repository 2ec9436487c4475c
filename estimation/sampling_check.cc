#include "estimation/sampling_check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>

#include "common/concurrency.h"
#include "estimation/alignment_lag.h"
#include "estimation/at_estimate.h"
#include "estimation/fit.h"
#include "sim/channels.h"

namespace axis {
namespace {

const char* ConventionName(AccelerometerSampling s) {
  return s == AccelerometerSampling::kInstant ? "instant" : "period_mean";
}

// The samples of channel `a` the job fits.
int SamplesOfA(const EstimationProblem& job) {
  int samples = 0;
  for (const FitExperiment& e : job.experiments) {
    for (const FittedChannel& f : e.fitted) {
      if (f.channel == Channel::kA) samples += static_cast<int>(e.t.size());
    }
  }
  return samples;
}

// `job` under `convention`, with a free delay on every fitted channel
// (sensor_delay.<channel>, MODEL.md §6: either sign) that has none yet: a
// skew between the channels is not the convention's. Each starts from 0
// within ± the longest output period of the experiments that fit it, which
// holds the half-period between the conventions and sub-sample skews
// (wider, a refit from 0 can slip a whole period of the gear's ringing);
// or, where the declared fit's records line up with its simulation at a lag
// beyond a period (estimation/alignment_lag.h, searched over a quarter of
// the longest record), from that lag within ± two periods of it: a refit
// from 0 stops three samples short of a 3 ms delay on a 1 kHz record, and
// the other convention's half-sample lag then looks better (issue 56).
// *added counts them.
EstimationProblem WithConventionAndDelays(const EstimationProblem& job, const FitResult& fit,
                                          AccelerometerSampling convention, int* added) {
  EstimationProblem out = job;
  out.model.structure.accelerometer = convention;
  std::array<double, kNumChannels> period{};
  double longest = 0.0;
  for (const FitExperiment& e : job.experiments) {
    for (const FittedChannel& c : e.fitted) {
      const int k = static_cast<int>(c.channel);
      period[k] = std::max(period[k], e.options.output_period);
    }
    if (!e.t.empty()) longest = std::max(longest, e.t.back());
  }
  *added = 0;
  for (int k = 0; k < kNumChannels; ++k) {
    if (!(period[k] > 0.0) || out.model.structure.sensors.delay[k]) continue;
    const char* channel = ChannelName(static_cast<Channel>(k));
    const double lag = AlignmentLag(fit, channel, 0.25 * longest);
    const bool far = std::isfinite(lag) && std::abs(lag) > period[k];
    out.model.structure.sensors.delay[k] = true;
    out.model.params.tau_d[k] = far ? lag : 0.0;
    FreeParameter f;
    f.name = std::string("tau_d.") + channel;
    f.unit = ParamUnit(f.name, out.model.structure.motion);
    f.initial = far ? lag : 0.0;
    f.lower = far ? lag - 2.0 * period[k] : -period[k];
    f.upper = far ? lag + 2.0 * period[k] : period[k];
    out.free.push_back(f);
    ++*added;
  }
  return out;
}

// Σ(r/σ)² of a warm refit of `job` (AsWarmRefit), with Σ log(σ_k²/σ²) where
// its fit weighted samples (Deviance); the fit into *fit if not null.
double WarmRefitChi2(EstimationProblem job, FitResult* fit) {
  AsWarmRefit(&job);
  job.solver.progress = false;
  FitResult r = FitParameters(job, nullptr);
  const double chi2 = Deviance(r);
  if (fit != nullptr) *fit = std::move(r);
  return chi2;
}

// As WarmRefitChi2 for `job` with free delays, each then moved to where the
// refit's own simulation lines up with the records while that is more than
// half a period away (estimation/alignment_lag.h) or the delay sits on an
// end of its window (the window widened past it), and refitted, twice at
// most, keeping each refit that lowers Σ(r/σ)²: a delay started from a
// lag the declared fit suggested (bent toward it without the delay) can
// stop a few samples off. `first`, if not null, receives the first refit
// (before any move).
double AlignedRefitChi2(EstimationProblem job, FitResult* fit, FitResult* first = nullptr) {
  FitResult r;
  double chi2 = WarmRefitChi2(job, &r);
  if (first != nullptr) *first = r;
  double longest = 0.0;
  for (const FitExperiment& e : job.experiments) {
    if (!e.t.empty()) longest = std::max(longest, e.t.back());
  }
  for (int pass = 0; pass < 2 && std::isfinite(chi2); ++pass) {
    EstimationProblem moved = AtEstimate(job, r);
    bool any = false;
    for (FreeParameter& f : moved.free) {
      if (f.name.rfind("tau_d.", 0) != 0) continue;
      const std::string channel = f.name.substr(6);
      const std::optional<Channel> c = ParseChannel(channel);
      const double period = c ? FittedPeriod(job, *c) : 0.0;
      const double lag = AlignmentLag(r, channel, 0.25 * longest);
      // A delay on an end of its window: the window missed it (the other
      // parameters then bend toward the rest of the delay and the lag left
      // can be under half a period: a record 5 ms early at 1 kHz, its
      // window ending at 3.8 ms, 0.45 ms left). The window moves out
      // beyond it all the same.
      const bool on_end = f.initial <= f.lower || f.initial >= f.upper;
      const bool far = std::isfinite(lag) && std::abs(lag) > 0.5 * period;
      if (!far && !on_end) continue;
      const double width = f.upper - f.lower;
      if (std::isfinite(lag)) f.initial += lag;
      f.lower = std::min(f.lower, f.initial - 0.5 * width);
      f.upper = std::max(f.upper, f.initial + 0.5 * width);
      *FindParam(&moved.model.params, f.name) = f.initial;
      any = true;
    }
    if (!any) break;
    FitResult again;
    const double chi2_again = WarmRefitChi2(moved, &again);
    if (!(chi2_again < chi2)) break;
    chi2 = chi2_again;
    r = std::move(again);
    job = std::move(moved);
  }
  if (fit != nullptr) *fit = std::move(r);
  return chi2;
}

// `job` without its fitted delay on `a` (sensor_delay.a, tau_d.a free), or
// nullopt if it has none.
std::optional<EstimationProblem> WithoutFittedDelayOfA(const EstimationProblem& job) {
  const int a = static_cast<int>(Channel::kA);
  const auto it = std::find_if(job.free.begin(), job.free.end(),
                               [](const FreeParameter& f) { return f.name == "tau_d.a"; });
  if (!job.model.structure.sensors.delay[a] || it == job.free.end()) return std::nullopt;
  EstimationProblem out = job;
  out.model.structure.sensors.delay[a] = false;
  out.model.params.tau_d[a] = 0.0;
  out.free.erase(out.free.begin() + (it - job.free.begin()));
  return out;
}

// With kBestBic: each convention's lower BIC of its refit as the job stands
// (`fitted` entries of θ) and with the `added` delays, over `residuals`;
// the other one's also without the job's fitted delay on `a`.
void BestBics(double residuals, double fitted, int added, SamplingCheck* check) {
  const double log_m = std::log(std::max(1.0, residuals));
  auto best = [&](double plain, double delayed) {
    double b = std::numeric_limits<double>::infinity();
    if (std::isfinite(plain)) b = plain + fitted * log_m;
    if (std::isfinite(delayed)) b = std::min(b, delayed + (fitted + added) * log_m);
    return b;
  };
  check->bic_declared = best(check->chi2_declared, check->chi2_declared_delay);
  check->bic_other = best(check->chi2_other, check->chi2_other_delay);
  if (std::isfinite(check->chi2_other_without_delay_a)) {
    check->bic_other =
        std::min(check->bic_other, check->chi2_other_without_delay_a + (fitted - 1.0) * log_m);
  }
}

// Whether the refits of `check` name the other convention (SamplingRule);
// with kBestBic its BICs are set first (BestBics).
bool Decides(double residuals, double fitted, int added, SamplingCheck* check) {
  if (check->rule == SamplingRule::kBestBic) {
    BestBics(residuals, fitted, added, check);
    const double s2 = check->chi2_declared / std::max(1.0, residuals - fitted);
    return check->bic_declared - check->bic_other > kSamplingBicMargin * std::max(1.0, s2);
  }
  const double s2 = check->chi2_declared_delay / std::max(1, check->dof);
  const double gain = check->chi2_declared_delay - check->chi2_other_delay;
  const double excess = std::max(0.0, check->chi2_declared_delay - check->dof);
  return gain > kSamplingBicMargin * std::max(1.0, s2) && gain > kSamplingExcessShare * excess;
}

}  // namespace

SamplingCheck CheckAccelerometerSampling(const EstimationProblem& job, const FitResult& result,
                                         SamplingRule rule) {
  SamplingCheck check;
  check.rule = rule;
  check.bic_declared = check.bic_other = std::numeric_limits<double>::quiet_NaN();
  check.chi2_other_without_delay_a = std::numeric_limits<double>::quiet_NaN();
  bool fits_a = false;
  for (const FitExperiment& e : job.experiments) {
    for (const FittedChannel& f : e.fitted) fits_a = fits_a || f.channel == Channel::kA;
  }
  if (!fits_a) return check;
  check.ran = true;
  const EstimationProblem at = AtEstimate(job, result);
  const AccelerometerSampling other =
      at.model.structure.accelerometer == AccelerometerSampling::kInstant
          ? AccelerometerSampling::kPeriodMean
          : AccelerometerSampling::kInstant;
  check.declared = ConventionName(at.model.structure.accelerometer);
  check.other = ConventionName(other);
  check.samples = SamplesOfA(at);
  check.chi2_declared = Deviance(result);
  check.chi2_other = std::numeric_limits<double>::quiet_NaN();
  const double dof0 = result.residual_dof;
  if (rule == SamplingRule::kMisfit && dof0 > 0.0 &&
      check.chi2_declared - dof0 <= 3.0 * std::sqrt(2.0 * dof0)) {
    check.explained = true;
    check.dof = static_cast<int>(dof0);
    check.chi2_declared_delay = check.chi2_other_delay = std::numeric_limits<double>::quiet_NaN();
    return check;
  }
  int added = 0;
  const AccelerometerSampling declared = at.model.structure.accelerometer;
  const EstimationProblem declared_job = WithConventionAndDelays(at, result, declared, &added);
  const EstimationProblem other_job = WithConventionAndDelays(at, result, other, &added);
  EstimationProblem plain = at;
  plain.model.structure.accelerometer = other;
  const std::optional<EstimationProblem> without = WithoutFittedDelayOfA(plain);
  // The refits that depend on none of the others, two at a time (each
  // evaluating on the job's own threads, so that each ends as it would
  // alone): both conventions with the added delays; then, with kBestBic and
  // both of those finite, the other convention as the job stands, with and
  // without its delay on `a`.
  // With no delay added (every fitted channel has one already) the other
  // convention's job is `plain` itself, and its first refit is plain's
  // (refitted twice before: the discovered model's check on the
  // independent square + sweep records, seed 2, 7.6 s, now 4.6 s).
  FitResult other_fit;
  std::optional<FitResult> plain_fit;
  if (added == 0) plain_fit.emplace();
  ForEachConcurrently(2, job.solver.threads, [&](size_t k) {
    if (k == 0) check.chi2_declared_delay = AlignedRefitChi2(declared_job, nullptr);
    if (k == 1) {
      check.chi2_other_delay =
          AlignedRefitChi2(other_job, &other_fit, plain_fit ? &*plain_fit : nullptr);
    }
  });
  // The other convention as the job stands: plain's refit into
  // check.refit, from memory where it ran above.
  const auto refit_plain = [&]() {
    if (!plain_fit) return WarmRefitChi2(plain, &check.refit);
    check.refit = *plain_fit;
    return Deviance(check.refit);
  };
  check.dof = static_cast<int>(result.residual_dof) - added;  // the refits' own
  if (!std::isfinite(check.chi2_other_delay) || !std::isfinite(check.chi2_declared_delay)) {
    return check;
  }
  const double residuals = result.num_residuals;
  const double fitted = result.num_residuals - result.residual_dof;
  if (rule == SamplingRule::kBestBic) {
    ForEachConcurrently(without ? 2 : 1, job.solver.threads, [&](size_t k) {
      if (k == 0) check.chi2_other = refit_plain();
      if (k == 1) check.chi2_other_without_delay_a = WarmRefitChi2(*without, nullptr);
    });
  }
  if (!Decides(residuals, fitted, added, &check)) return check;
  // The other convention's gain may be a lower minimum of a model far off,
  // not the convention's: the declared convention refitted from the other's
  // optimum (the payload discovery case, its payload undeclared at s² = 89:
  // Σ(r/σ)² 1.08e6 under the declared convention, 9.9e4 under the other,
  // from the same start). Each convention is judged at the better of the
  // two starts.
  EstimationProblem cross = AtEstimate(other_job, other_fit);
  cross.model.structure.accelerometer = declared;
  const double chi2_cross = WarmRefitChi2(cross, nullptr);
  if (chi2_cross < check.chi2_declared_delay) check.chi2_declared_delay = chi2_cross;
  if (!Decides(residuals, fitted, added, &check)) return check;
  if (rule == SamplingRule::kMisfit) check.chi2_other = refit_plain();
  if (!std::isfinite(check.chi2_other)) {
    check.chi2_other = std::numeric_limits<double>::quiet_NaN();
    return check;
  }
  std::ostringstream note;
  note << std::setprecision(4) << "the accelerometer's records fit 'accelerometer: "
       << check.other << "' better than the declared '" << check.declared << "' (";
  if (rule == SamplingRule::kBestBic) {
    note << "BIC of the better of each convention's refits, as the model stands and with a "
            "free delay on every fitted channel, "
         << check.bic_declared << " -> " << check.bic_other << "; ";
  } else {
    note << "each refitted with a free delay on every fitted channel, ";
  }
  note << "sum of (r/sigma)^2 " << check.chi2_declared_delay << " -> " << check.chi2_other_delay
       << "; without it " << check.chi2_declared << " -> " << check.chi2_other << "; "
       << check.samples << " samples of a): "
       << (rule == SamplingRule::kBestBic
               ? "the filter or delay kept on a stood in for the convention; "
               : "the misfit is the sampling convention's, not a wrong minimum; ")
       << "declare it in the model config (MODEL.md section 6) or the job's configuration "
          "(fit-params --discover starts from it)";
  check.note = note.str();
  return check;
}

}  // namespace axis
