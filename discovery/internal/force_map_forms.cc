#include "discovery/internal/force_map_forms.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "estimation/fit.h"
#include "sim/channels.h"
#include "sim/simulate.h"

namespace axis {

Visited VisitedValues(const EstimationProblem& job) {
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

EstimationProblem MapJob(const EstimationProblem& job, const Candidate& c, double first_horizon) {
  EstimationProblem out = job;
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

void TransferToMap(const std::string& effect, EstimationProblem* job) {
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

}  // namespace axis
