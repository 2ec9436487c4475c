#include "discovery/materiality.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "discovery/accelerometer_convention.h"
#include "discovery/candidates.h"
#include "discovery/internal/find_estimate.h"
#include "discovery/removal.h"
#include "estimation/at_estimate.h"
#include "sim/axis_params.h"
#include "sim/channels.h"
#include "sim/simulate.h"

namespace axis {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The physical floor of `effect`'s first parameter in `problem`'s model
// (materiality.h), +inf where it has none.
double FloorOf(const std::string& effect, const AxisParams<double>& p) {
  if (effect == "payload") return 0.01 * p.M;
  if (effect == "viscous_asymmetry") return 0.05 * p.B_a;
  return kInf;
}

}  // namespace

Contribution EffectContribution(const std::string& effect, const EstimationProblem& problem,
                                const FitResult& fit) {
  const Candidate c = CandidateNamed(effect);
  Contribution out;
  const EstimationProblem on = AtEstimate(problem, fit);
  EstimationProblem off = on;
  RemoveEffect(c, EffectParameters(c), &off);
  const std::string param = EffectParameters(c).front();
  const ParameterEstimate* e = FindEstimate(fit, param);
  AxisParams<double> values = on.model.params;
  out.value = e != nullptr ? e->value : *FindParam(&values, param);
  out.floor = FloorOf(c.effect, on.model.params);
  for (const FitExperiment& experiment : on.experiments) {
    const SimulationGrid grid = MakeGrid(experiment.options, experiment.drive);
    const Trace<double> with = Simulate(on.model.structure, on.model.params,
                                        experiment.initial_state, experiment.drive,
                                        experiment.options, grid);
    const Trace<double> without = Simulate(off.model.structure, off.model.params,
                                           experiment.initial_state, experiment.drive,
                                           experiment.options, grid);
    for (const FittedChannel& f : experiment.fitted) {
      const std::vector<double>& a = with[f.channel];
      const std::vector<double>& b = without[f.channel];
      double share = std::numeric_limits<double>::infinity();  // a failed simulation
      if (with.finite && without.finite && a.size() == b.size() && !a.empty()) {
        // Over the fitted samples (not a tail simulated past them).
        const size_t n = std::min(a.size(), experiment.t.size());
        double sum = 0.0;
        for (size_t j = 0; j < n; ++j) sum += (a[j] - b[j]) * (a[j] - b[j]);
        share = std::sqrt(sum / n) / f.sigma;
      }
      if (share > out.share || out.channel.empty()) {
        out.share = std::max(out.share, share);
        out.channel = experiment.name + "/" + ChannelName(f.channel);
      }
    }
  }
  out.material = out.share >= kMaterialShare || std::abs(out.value) >= out.floor;
  return out;
}

std::string NegligibleNote(const std::string& effect, const Contribution& c, Motion motion) {
  const Candidate candidate = CandidateNamed(effect);
  const std::string param = EffectParameters(candidate).front();
  std::ostringstream out;
  out.precision(3);
  out << effect << " (" << param << " = " << c.value << " " << ParamUnit(param, motion)
      << ") is significant but negligible: it changes no fitted channel by more than "
      << c.share << "·σ (largest on " << c.channel << "), below " << kMaterialShare << "·σ";
  if (std::isfinite(c.floor)) {
    out << ", and |" << param << "| is below its physical floor " << c.floor << " "
        << ParamUnit(param, motion);
  }
  out << "; refitted without it";
  return out.str();
}

void DropNegligible(EstimationProblem* job, FitResult* result, DiscoveryReport* report,
                    std::ostream* progress) {
  const std::vector<std::string> effects = report->selected;
  for (size_t k = effects.size(); k-- > 0;) {
    if (IsConventionStep(effects[k])) continue;
    const Candidate candidate = CandidateNamed(effects[k]);
    if (RefinedInModel(candidate.effect, job->model.structure)) continue;
    const Contribution c = EffectContribution(candidate.name, *job, *result);
    if (c.material) continue;
    Removal removal = std::move(RefitsWithout({candidate}, job, *result)[0]);
    DiscoveryStep& record = removal.record;
    const FitResult& refit = removal.refit;
    if (!record.stopped.empty() || !std::isfinite(refit.final_cost)) continue;
    record.negligible = NegligibleNote(candidate.name, c, job->model.structure.motion);
    record.kept = true;  // removed whatever BIC says
    report->steps.push_back(record);
    report->notes.push_back(record.negligible);
    if (progress) {
      *progress << "  refit without " << candidate.name << ": " << record.negligible << "; BIC "
                << record.bic_before << " -> " << record.bic_after << " (removed)\n";
    }
    DropEffect(candidate.name, std::move(removal.without), std::move(removal.refit), job, result,
               report);
  }
}

}  // namespace axis
