#include "run/campaign.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <boost/math/distributions/binomial.hpp>
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "common/concurrency.h"
#include "common/format.h"
#include "common/json_fields.h"
#include "discovery/accelerometer_convention.h"
#include "discovery/diagnostics.h"
#include "discovery/discovery.h"
#include "discovery/discovery_report.h"
#include "estimation/fit_result.h"
#include "run/campaign_settings.h"
#include "discovery/discovery_settings.h"
#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "run/job_run.h"
#include "sim/config.h"
#include "io/csv.h"
#include "sim/experiment.h"
#include "io/yaml_util.h"
#include "tune/analog_loop_tuning.h"
#include "tune/move_tuning.h"

namespace axis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A folder of its own under the system's temporary directory, removed with
// everything in it when the object goes.
struct ScopedTempDir {
  explicit ScopedTempDir(const std::string& tag)
      : path((std::filesystem::temp_directory_path() /
              ("fit-campaign-" + std::to_string(::getpid()) + "-" + tag))
                 .string()) {
    std::filesystem::create_directories(path);
  }
  ~ScopedTempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  ScopedTempDir(const ScopedTempDir&) = delete;
  ScopedTempDir& operator=(const ScopedTempDir&) = delete;
  const std::string path;
};

std::string FormatRate(const Rate& r) {
  if (r.n == 0) return "—";
  std::ostringstream out;
  out << r.k << "/" << r.n << " = " << std::fixed << std::setprecision(1)
      << 100.0 * r.k / r.n << " % [" << 100.0 * r.low << ", " << 100.0 * r.high << "]";
  return out.str();
}

nlohmann::json RateJson(const Rate& r) {
  return {{"k", r.k}, {"n", r.n}, {"ci95_low", JsonNumber(r.low)},
          {"ci95_high", JsonNumber(r.high)}};
}

}  // namespace

FitJob CampaignSeedJob(const CampaignConfig& c, int seed, const std::string& dir) {
  YAML::Node root = YAML::Clone(LoadYamlFile(c.job_path));
  std::vector<std::pair<std::string, YAML::Node>> experiments = JobExperiments(root);
  for (const auto& [name, generator] : c.generate) {
    const ExperimentConfig x = LoadExperiment(generator);
    Trace<double> trace = RunExperiment(x);
    if (!trace.finite) {
      throw std::runtime_error(generator + ": the simulation left the finite numbers");
    }
    AddNoise(x.noise_sigma, x.seed + 1000ULL * static_cast<std::uint64_t>(seed), &trace);
    const std::string csv = dir + "/" + name + ".csv";
    WriteTraceCsv(csv, trace, x.options.channels);
    for (auto& [job_name, node] : experiments) {
      if (job_name == name) node["data"] = csv;
    }
  }
  return ParseFitJob(root, c.job_path, DirectoryOf(c.job_path));
}

namespace {

// The proposal applied to the axis that made the records: the first
// generating config's model (its undeclared effects included), simulated
// at that config's step.
void JudgeTuningOnTheTrueAxis(const CampaignConfig& c, const AnalogLoopTuning& t,
                              SeedOutcome* o) {
  o->tuned_T_p = t.proposed.T_p;
  if (c.generate.empty()) return;
  const ExperimentConfig truth = LoadExperiment(c.generate.front().second);
  const std::vector<std::string> v =
      ViolationsOn(truth.model, truth.options.step, t.proposed, t.spec);
  o->spec_met_true = v.empty() ? 1 : 0;
  o->spec_violation_true = v.empty() ? "" : v.front();
}

void JudgeMoveOnTheTrueAxis(const CampaignConfig& c, const MoveTuning& t, SeedOutcome* o) {
  if (c.generate.empty()) return;
  const ExperimentConfig truth = LoadExperiment(c.generate.front().second);
  const std::vector<std::string> v =
      MoveViolationsOn(truth.model, truth.options.step, t.proposed, t.spec);
  o->move_spec_met_true = v.empty() ? 1 : 0;
  o->move_robust = t.proposed.robust ? 1 : 0;
  o->move_spec_violation_true = v.empty() ? "" : v.front();
  if (!t.klipper_ran) return;
  const std::vector<std::string> k =
      MoveViolationsOn(truth.model, truth.options.step, t.klipper, t.spec);
  o->klipper_spec_met_true = k.empty() ? 1 : 0;
  o->klipper_spec_violation_true = k.empty() ? "" : k.front();
}

}  // namespace

SeedOutcome RunCampaignSeed(const CampaignConfig& c, int seed, int solver_threads) {
  SeedOutcome o;
  o.seed = seed;
  o.value.assign(c.truth_values.size(), kNaN);
  o.ci95_low = o.value;
  o.ci95_high = o.value;
  const auto start = std::chrono::steady_clock::now();
  try {
    const ScopedTempDir dir(std::to_string(seed));
    FitJob job = CampaignSeedJob(c, seed, dir.path);
    job.problem.solver.progress = false;
    job.problem.solver.threads = solver_threads;
    if (!c.discover) job.discover.enabled = false;  // the campaign's key decides
    // fit-params' own pipeline, its printed text dropped.
    std::ostringstream discarded;
    discarded.setstate(std::ios::badbit);
    const JobRun run = RunJob(std::move(job), c.discover, discarded);
    ResidualVerdict verdict;
    if (run.discovered) {
      if (run.force_map.kept) o.force_map = "force_map." + run.force_map.kind;
      o.selected = run.discovery.selected;
      for (const DiscoveryStep& s : run.discovery.steps) {
        if (!s.removal && s.kept && o.first_added.empty() && !IsConventionStep(s.effect)) {
          o.first_added = s.effect;
        }
        if (!s.retried.empty()) o.retried.push_back(s.effect);
      }
      verdict = run.discovery.verdict;
    } else {
      // The diagnostics of the fitted model, at its estimate.
      verdict = JudgeResiduals(run.diagnostics, run.result, run.job.discover.alpha);
    }
    std::sort(o.selected.begin(), o.selected.end());
    o.verdict = verdict.verdict;
    o.s2 = verdict.s2;
    for (size_t k = 0; k < c.truth_values.size(); ++k) {
      for (const ParameterEstimate& e : run.result.parameters) {
        if (e.name != c.truth_values[k].first || !e.free) continue;
        o.value[k] = e.value;
        o.ci95_low[k] = e.ci95_low;
        o.ci95_high[k] = e.ci95_high;
      }
    }
    if (run.tuning.ran) JudgeTuningOnTheTrueAxis(c, run.tuning, &o);
    if (run.move_tuning.ran) JudgeMoveOnTheTrueAxis(c, run.move_tuning, &o);
  } catch (const std::exception& e) {
    o.error = e.what();
  }
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return o;
}

std::string FormatSeedLine(const SeedOutcome& o) {
  std::ostringstream out;
  out << "seed " << o.seed << ": "
      << (o.error.empty() ? "selected {" + Join(o.selected, ", ") + "}, verdict " + o.verdict +
                                (o.force_map.empty() ? "" : ", kept " + o.force_map)
                          : "failed: " + o.error)
      << " (" << std::fixed << std::setprecision(0) << o.seconds << " s)";
  return out.str();
}

nlohmann::json SeedOutcomeToJson(const SeedOutcome& o) {
  const auto numbers = [](const std::vector<double>& list) {
    nlohmann::json out = nlohmann::json::array();
    for (double v : list) out.push_back(JsonNumber(v));
    return out;
  };
  return {{"seed", o.seed},
          {"error", o.error},
          {"selected", o.selected},
          {"first_added", o.first_added},
          {"retried", o.retried},
          {"verdict", o.verdict},
          {"s2", JsonNumber(o.s2)},
          {"force_map", o.force_map},
          {"value", numbers(o.value)},
          {"ci95_low", numbers(o.ci95_low)},
          {"ci95_high", numbers(o.ci95_high)},
          {"seconds", JsonNumber(o.seconds)},
          {"tuned_T_p", JsonNumber(o.tuned_T_p)},
          {"spec_met_true", o.spec_met_true},
          {"spec_violation_true", o.spec_violation_true},
          {"move_spec_met_true", o.move_spec_met_true},
          {"move_spec_violation_true", o.move_spec_violation_true},
          {"move_robust", o.move_robust},
          {"klipper_spec_met_true", o.klipper_spec_met_true},
          {"klipper_spec_violation_true", o.klipper_spec_violation_true}};
}

SeedOutcome SeedOutcomeFromJson(const nlohmann::json& j, const std::string& where) {
  SeedOutcome o;
  o.seed = JsonIntField(j, "seed", where);
  o.error = JsonStringField(j, "error", where);
  o.selected = JsonStrings(j, "selected", where);
  o.first_added = JsonStringField(j, "first_added", where);
  o.retried = JsonStrings(j, "retried", where);
  o.verdict = JsonStringField(j, "verdict", where);
  o.s2 = JsonNumberField(j, "s2", where);
  o.force_map = JsonStringField(j, "force_map", where);
  o.value = JsonNumbers(j, "value", where);
  o.ci95_low = JsonNumbers(j, "ci95_low", where);
  o.ci95_high = JsonNumbers(j, "ci95_high", where);
  if (o.ci95_low.size() != o.value.size() || o.ci95_high.size() != o.value.size()) {
    throw std::invalid_argument(where + ": expected value, ci95_low and ci95_high of one "
                                "length, got " + std::to_string(o.value.size()) + ", " +
                                std::to_string(o.ci95_low.size()) + ", " +
                                std::to_string(o.ci95_high.size()));
  }
  o.seconds = JsonNumberField(j, "seconds", where);
  o.tuned_T_p = JsonNumberField(j, "tuned_T_p", where);
  o.spec_met_true = JsonIntField(j, "spec_met_true", where);
  o.spec_violation_true = JsonStringField(j, "spec_violation_true", where);
  o.move_spec_met_true = JsonIntField(j, "move_spec_met_true", where);
  o.move_spec_violation_true = JsonStringField(j, "move_spec_violation_true", where);
  o.move_robust = JsonIntField(j, "move_robust", where);
  o.klipper_spec_met_true = JsonIntField(j, "klipper_spec_met_true", where);
  o.klipper_spec_violation_true = JsonStringField(j, "klipper_spec_violation_true", where);
  return o;
}

CampaignConfig LoadCampaign(const std::string& path) {
  std::vector<YAML::Node> truth_value_keys;  // of c.truth_values, for messages
  CampaignConfig c = LoadCampaignSettings(path, &truth_value_keys);
  // Every generating config and the job with the first seed's data (its
  // `data:` paths are replaced, so they need not exist).
  const ScopedTempDir check("check");
  const FitJob job = CampaignSeedJob(c, c.first_seed, check.path);
  // Each true value names a parameter the fits estimate: a free parameter
  // of the job or, with discovery, one of an effect of truth.effects (the
  // loop frees it when it adds the effect). Another name, a misspelt one,
  // would be tallied as a parameter no seed estimates.
  std::vector<std::string> free_names, effect_names;
  for (const FreeParameter& f : job.problem.free) free_names.push_back(f.name);
  if (c.discover) {
    for (const std::string& e : c.truth_effects) {
      for (const std::string& p : FreedParameters(e)) effect_names.push_back(p);
    }
  }
  CheckTruthValues(c, free_names, effect_names, truth_value_keys);
  return c;
}

std::vector<SeedOutcome> RunCampaign(const CampaignConfig& config, int threads,
                                     std::ostream* progress) {
  if (threads < 1) {
    throw std::invalid_argument("RunCampaign: expected at least 1 thread, got " +
                                std::to_string(threads));
  }
  const int n = config.last_seed - config.first_seed + 1;
  std::vector<SeedOutcome> outcomes(n);
  // The cores are shared out: seeds in parallel, each fit's Ceres threads
  // the rest.
  const int cores = std::max(1u, std::thread::hardware_concurrency());
  const int solver_threads = std::max(1, cores / std::min(threads, n));
  std::mutex mutex;
  int done = 0;
  ForEachConcurrently(static_cast<size_t>(n), threads, [&](size_t k) {
    SeedOutcome o =
        RunCampaignSeed(config, config.first_seed + static_cast<int>(k), solver_threads);
    std::lock_guard<std::mutex> lock(mutex);
    ++done;
    if (progress) {
      *progress << "[" << done << "/" << n << "] " << FormatSeedLine(o) << std::endl;
    }
    outcomes[k] = std::move(o);
  });
  return outcomes;
}

Rate RateOf(int k, int n) {
  Rate r;
  r.k = k;
  r.n = n;
  if (n == 0) return r;
  using boost::math::binomial_distribution;
  // Clopper–Pearson: α/2 = 0.025 in each tail.
  r.low = k == 0 ? 0.0
                 : binomial_distribution<>::find_lower_bound_on_p(n, k, 0.025);
  r.high = k == n ? 1.0
                  : binomial_distribution<>::find_upper_bound_on_p(n, k, 0.025);
  return r;
}

CampaignSummary Summarize(const CampaignConfig& config,
                          const std::vector<SeedOutcome>& outcomes) {
  CampaignSummary s;
  int false_discoveries = 0, front_end = 0, right_first = 0, exact = 0, as_expected = 0, ok = 0;
  int tuned = 0, spec_met = 0, moves = 0, move_met = 0, claimed = 0, claim_held = 0;
  int klippers = 0, klipper_met = 0;
  std::vector<int> covered(config.truth_values.size(), 0);
  bool truth_names_front_end = false;
  for (const std::string& e : config.truth_effects) {
    truth_names_front_end = truth_names_front_end || IsFrontEndEffect(e);
  }
  for (const SeedOutcome& o : outcomes) {
    ++s.seeds;
    if (!o.error.empty()) {
      ++s.failed;
      continue;
    }
    ++ok;
    const SelectedParts parts = SplitSelected(o.selected);
    false_discoveries += !parts.plant.empty();
    front_end += !parts.front_end.empty();
    right_first += std::find(config.truth_effects.begin(), config.truth_effects.end(),
                             o.first_added) != config.truth_effects.end();
    // A truth that names no front-end term (records behind an undeclared
    // front end, MODEL.md §6): the plant's effects must be exact, the front
    // end is counted apart (front_end_selected).
    exact += (truth_names_front_end ? o.selected : parts.plant) == config.truth_effects;
    as_expected += o.verdict == config.truth_verdict;
    s.explained += o.verdict == "explained";
    if (!o.force_map.empty()) ++s.force_maps[o.force_map];
    s.incomplete += o.verdict == "incomplete";
    tuned += o.spec_met_true >= 0;
    spec_met += o.spec_met_true == 1;
    moves += o.move_spec_met_true >= 0;
    move_met += o.move_spec_met_true == 1;
    claimed += o.move_robust == 1 && o.move_spec_met_true >= 0;
    claim_held += o.move_robust == 1 && o.move_spec_met_true == 1;
    klippers += o.klipper_spec_met_true >= 0;
    klipper_met += o.klipper_spec_met_true == 1;
    for (size_t k = 0; k < covered.size(); ++k) {
      const double truth = config.truth_values[k].second;
      covered[k] += o.ci95_low[k] <= truth && truth <= o.ci95_high[k];
    }
  }
  if (config.discover) {
    // With a force outside the library in the data what the loop selects
    // stands in for it: neither a false discovery nor an exact set.
    if (!config.truth_effects.empty()) {
      s.right_first = RateOf(right_first, ok);
    } else if (config.truth_outside.empty()) {
      s.false_discovery = RateOf(false_discoveries, ok);
    }
    if (!truth_names_front_end && config.truth_outside.empty()) {
      s.front_end_selected = RateOf(front_end, ok);
    }
    if (config.truth_outside.empty()) s.exact_set = RateOf(exact, ok);
  }
  int pooled = 0;
  for (int c : covered) {
    s.covered.push_back(RateOf(c, ok));
    pooled += c;
  }
  if (covered.size() >= 2) {
    s.covered_pooled = RateOf(pooled, ok * static_cast<int>(covered.size()));
  }
  if (!config.truth_verdict.empty()) s.verdict_as_expected = RateOf(as_expected, ok);
  if (tuned > 0) s.spec_met_true = RateOf(spec_met, tuned);
  if (moves > 0) s.move_spec_met_true = RateOf(move_met, moves);
  if (claimed > 0) s.move_claim_held = RateOf(claim_held, claimed);
  if (klippers > 0) s.klipper_spec_met_true = RateOf(klipper_met, klippers);
  return s;
}

std::string FormatCampaign(const CampaignConfig& config, const CampaignSummary& s,
                           const std::vector<SeedOutcome>& outcomes) {
  std::ostringstream out;
  out << "# " << config.title << "\n\n"
      << "Campaign " << config.path << ": job " << config.job_path << ", seeds "
      << config.first_seed << "–" << config.last_seed << " (" << s.seeds << ", " << s.failed
      << " failed), truth {" << Join(config.truth_effects, ", ") << "}"
      << (config.truth_outside.empty()
              ? ""
              : " and, outside the library, {" + Join(config.truth_outside, ", ") + "}")
      << (config.discover ? "" : ", no discovery") << ".\n\n"
      << "| measure | rate (95 % Clopper–Pearson interval, %) |\n|---|---|\n";
  if (s.false_discovery.n) {
    out << "| false discovery (a plant effect selected) | " << FormatRate(s.false_discovery)
        << " |\n";
  }
  if (s.front_end_selected.n) {
    out << "| a sensor front-end term selected | " << FormatRate(s.front_end_selected) << " |\n";
  }
  if (s.right_first.n) {
    out << "| right effect first | " << FormatRate(s.right_first) << " |\n";
  }
  if (s.exact_set.n) out << "| exact final set | " << FormatRate(s.exact_set) << " |\n";
  for (size_t k = 0; k < s.covered.size(); ++k) {
    out << "| " << config.truth_values[k].first << " = " << config.truth_values[k].second
        << " inside its 95 % interval | " << FormatRate(s.covered[k]) << " |\n";
  }
  if (s.covered_pooled.n) {
    out << "| all " << s.covered.size() << " values inside their 95 % intervals (pooled) | "
        << FormatRate(s.covered_pooled) << " |\n";
  }
  if (s.verdict_as_expected.n) {
    out << "| verdict " << config.truth_verdict << " | " << FormatRate(s.verdict_as_expected)
        << " |\n";
  }
  if (s.spec_met_true.n) {
    out << "| spec met on the true axis (tune:, the proposal applied to the generating model) | "
        << FormatRate(s.spec_met_true) << " |\n";
  }
  if (s.move_spec_met_true.n) {
    out << "| move spec met on the true axis (tune.move:, the proposed controller and move "
           "on the generating model) | "
        << FormatRate(s.move_spec_met_true) << " |\n";
  }
  if (s.move_claim_held.n) {
    out << "| of those the tuning said meet the move spec at every check, met on the true axis | "
        << FormatRate(s.move_claim_held) << " |\n";
  }
  if (s.klipper_spec_met_true.n) {
    out << "| move spec met on the true axis with the shaper Klipper's rule recommends "
           "(tune.move.klipper, on the same tuned gains) | "
        << FormatRate(s.klipper_spec_met_true) << " |\n";
  }
  out << "| verdicts | explained " << s.explained << ", incomplete " << s.incomplete
      << " |\n";
  if (!s.force_maps.empty()) {
    std::vector<std::string> kinds;
    for (const auto& [kind, n] : s.force_maps) kinds.push_back(kind + " " + std::to_string(n));
    out << "| force map kept (discovery/force_map.h) | " << Join(kinds, ", ") << " of " << s.seeds
        << " |\n";
  }
  std::vector<double> seconds;
  for (const SeedOutcome& o : outcomes) seconds.push_back(o.seconds);
  std::sort(seconds.begin(), seconds.end());
  if (!seconds.empty()) {
    out << "| wall time per seed (s) | " << std::fixed << std::setprecision(0)
        << seconds.front() << "–" << seconds.back() << ", median "
        << seconds[seconds.size() / 2] << " |\n" << std::defaultfloat;
  }
  out << "\nSeeds with a selected effect, a failure or an unexpected verdict:\n\n";
  int listed = 0;
  for (const SeedOutcome& o : outcomes) {
    const bool odd = !o.error.empty() || o.selected != config.truth_effects ||
                     (!config.truth_verdict.empty() && o.verdict != config.truth_verdict) ||
                     o.spec_met_true == 0 || o.move_spec_met_true == 0 ||
                     o.klipper_spec_met_true == 0;
    if (!odd) continue;
    ++listed;
    out << "- seed " << o.seed << ": "
        << (o.error.empty() ? "selected {" + Join(o.selected, ", ") + "}, verdict " + o.verdict
                            : "failed: " + o.error)
        << (o.spec_met_true == 0 ? "; on the true axis: " + o.spec_violation_true : "")
        << (o.move_spec_met_true == 0
                ? "; the move on the true axis: " + o.move_spec_violation_true +
                      (o.move_robust == 1 ? " (the tuning had it meet the spec at every check)"
                                          : " (the tuning said it does not meet the spec at "
                                            "every check)")
                : "")
        << (o.klipper_spec_met_true == 0
                ? "; Klipper's rule's shaper on the true axis: " + o.klipper_spec_violation_true
                : "")
        << "\n";
  }
  if (listed == 0) out << "- none\n";
  return out.str();
}

void WriteCampaign(const std::string& dir, const CampaignConfig& config,
                   const CampaignSummary& s, const std::vector<SeedOutcome>& outcomes) {
  std::filesystem::create_directories(dir);
  std::ostringstream csv;
  csv << std::setprecision(10) << "seed,error,selected,first_added,verdict,s2,seconds";
  for (const auto& [name, truth] : config.truth_values) {
    (void)truth;
    csv << "," << name << "," << name << "_ci95_low," << name << "_ci95_high";
  }
  csv << ",tuned_T_p,spec_met_true,move_spec_met_true,move_robust,klipper_spec_met_true\n";
  for (const SeedOutcome& o : outcomes) {
    std::string error = o.error;
    std::replace(error.begin(), error.end(), ',', ';');
    std::replace(error.begin(), error.end(), '\n', ' ');
    csv << o.seed << "," << error << "," << Join(o.selected, " ") << "," << o.first_added
        << "," << o.verdict << "," << o.s2 << "," << o.seconds;
    for (size_t k = 0; k < config.truth_values.size(); ++k) {
      csv << "," << o.value[k] << "," << o.ci95_low[k] << "," << o.ci95_high[k];
    }
    csv << "," << o.tuned_T_p << "," << o.spec_met_true << "," << o.move_spec_met_true << ","
        << o.move_robust << "," << o.klipper_spec_met_true << "\n";
  }
  nlohmann::json j;
  j["title"] = config.title;
  j["campaign"] = config.path;
  j["job"] = config.job_path;
  j["seeds"] = {{"first", config.first_seed}, {"last", config.last_seed},
                {"run", s.seeds}, {"failed", s.failed}};
  j["truth_effects"] = config.truth_effects;
  j["truth_outside_library"] = config.truth_outside;
  if (s.false_discovery.n) j["false_discovery"] = RateJson(s.false_discovery);
  if (s.front_end_selected.n) j["front_end_selected"] = RateJson(s.front_end_selected);
  if (s.right_first.n) j["right_first"] = RateJson(s.right_first);
  if (s.exact_set.n) j["exact_set"] = RateJson(s.exact_set);
  j["coverage"] = nlohmann::json::object();
  for (size_t k = 0; k < s.covered.size(); ++k) {
    j["coverage"][config.truth_values[k].first] = RateJson(s.covered[k]);
  }
  if (s.covered_pooled.n) j["coverage_pooled"] = RateJson(s.covered_pooled);
  if (s.verdict_as_expected.n) j["verdict_as_expected"] = RateJson(s.verdict_as_expected);
  j["verdicts"] = {{"explained", s.explained}, {"incomplete", s.incomplete}};
  j["force_maps"] = s.force_maps;
  if (s.spec_met_true.n) j["spec_met_true"] = RateJson(s.spec_met_true);
  if (s.move_spec_met_true.n) j["move_spec_met_true"] = RateJson(s.move_spec_met_true);
  if (s.move_claim_held.n) j["move_claim_held"] = RateJson(s.move_claim_held);
  if (s.klipper_spec_met_true.n) j["klipper_spec_met_true"] = RateJson(s.klipper_spec_met_true);
  WriteFileAtomic(dir + "/results.csv", csv.str());
  WriteFileAtomic(dir + "/summary.md", FormatCampaign(config, s, outcomes));
  WriteFileAtomic(dir + "/summary.json", j.dump(2) + "\n");
}

}  // namespace axis
