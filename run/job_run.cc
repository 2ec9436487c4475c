#include "run/job_run.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "common/format.h"
#include "common/progress.h"
#include "design/experiment_design.h"
#include "discovery/diagnostics.h"
#include "discovery/discovery_session.h"
#include "discovery/force_map.h"
#include "discovery/frequency_response.h"
#include "estimation/at_estimate.h"
#include "estimation/current_loop_check.h"
#include "estimation/fit.h"
#include "estimation/fit_notes.h"
#include "estimation/fit_result.h"
#include "estimation/full_loop_refit.h"
#include "estimation/quasi_steady_screen.h"
#include "estimation/residual_bootstrap.h"
#include "run/fit_job.h"
#include "sim/simulation_count.h"
#include "report/published.h"
#include "report/report.h"
#include "report/tuning_report.h"
#include "tune/analog_loop_tuning.h"

namespace axis {
namespace {

// The job pipeline's steps over one JobRun, its state in members: the
// input notes, the fit of the declared model, the discovery loop and force
// map, the current-loop check, the residual diagnostics, the bootstrap, the
// next experiment, the tables and the report's sections.
class JobPipeline {
 public:
  JobPipeline(FitJob job, bool discover, std::ostream& out)
      : out_(out),
        progress_line_(dynamic_cast<ProgressStream*>(&out)),
        phases_([] {
          const SimulationCount c = SimulationsSoFar();
          return WorkCount{c.values, c.derivatives};
        }) {
    run_.job = std::move(job);
    discover_ = discover;
  }

  JobRun Run() {
    RefuseBenchmark();
    CollectInputNotes();
    if (discover_) run_.job.discover.enabled = true;
    // The declared model of a discovery run is expected to miss an effect:
    // its fit and the loop's refits are exploratory (fewer checks,
    // estimation/estimation_problem.h).
    run_.job.problem.exploratory = run_.job.discover.enabled;
    ScreenTheCurrentLoop();
    FitDeclaredModel();
    CheckTheAccelerometerSampling();
    if (run_.discovered) DiscoverEffects();
    CheckTheCurrentLoop();
    // The fit's s² settled (the force map's, the full loop's): the warning.
    result_.residual_note = ResidualNote(result_.residual_variance);
    if (!run_.discovered) DiagnoseTheFit();
    if (run_.job.problem.uncertainty.bootstrap > 0) phases_.Begin("residual bootstrap");
    ResidualBootstrap(run_.job.problem, &result_, &out_);
    AnalyseTheFrequencyResponse();
    if (run_.job.design.enabled) DesignTheNextExperiment();
    phases_.Begin("tables");
    PrintTables();
    if (run_.job.tune.enabled) TuneTheAxis();
    phases_.End();
    run_.phases = phases_.phases();
    AddSections();
    out_ << "run: " << FormatPhaseLog(run_.phases) << "\n";
    run_.result = std::move(result_);
    return std::move(run_);
  }

 private:
  // A stage of the run after the fit, on the progress line when `out` is
  // fit-params' progress stream (common/progress.h).
  void Stage(const char* what) {
    phases_.Begin(what);
    if (run_.job.problem.solver.progress && progress_line_ != nullptr) {
      progress_line_->Status(what, std::numeric_limits<double>::quiet_NaN());
    }
  }

  void RefuseBenchmark() const {
    if (!run_.job.benchmark.present) return;
    throw std::invalid_argument(run_.job.problem.path +
                                ": key 'benchmark': expected a job without 'benchmark:' here "
                                "(fit-params runs its criteria, each a job of its own: "
                                "run/benchmark.h CriterionJob), got one");
  }

  // Columns read in a way the job did not state (e.g. held inputs).
  void CollectInputNotes() {
    for (const std::vector<FitExperiment>* list : {&run_.job.problem.experiments, &run_.job.problem.validate}) {
      for (const FitExperiment& e : *list) {
        for (const std::string& note : e.input_notes) {
          out_ << "  " << e.name << ": " << note << "\n";
          input_markdown_ += "- " + e.name + ": " + note + "\n";
          run_.input_lines.push_back(e.name + ": " + note);
          input_notes_.push_back({{"experiment", e.name}, {"note", note}});
        }
      }
    }
  }

  // A job declared with the full current loop is fitted on its
  // quasi-steady screen (estimation/quasi_steady_screen.h): the starts, the
  // checks and the discovery loop at the screen's coarser step; the full
  // loop at the job's own step is refitted once the model is settled
  // (CheckTheCurrentLoop). Where the screen has no coarser step or none
  // divides a record's period, the job is fitted as declared.
  void ScreenTheCurrentLoop() {
    const EstimationProblem& job = run_.job.problem;
    if (run_.job.full_loop.screen != FullLoopRefitSettings::Screen::kAuto ||
        !HasQuasiSteadyScreen(job)) {
      return;
    }
    EstimationProblem screen;
    try {
      screen = QuasiSteadyScreen(job);
    } catch (const std::invalid_argument&) {
      return;
    }
    const double declared_step = SmallestStep(job);
    screen_step_ = SmallestStep(screen);
    if (!(screen_step_ > declared_step)) return;
    out_ << "screen: fitting the quasi-steady current loop at " << screen_step_
         << " s first, then the declared full loop at " << declared_step
         << " s from its estimate (simulation.quasi_steady_screen: off fits the full loop "
            "throughout)\n";
    declared_ = job;
    screened_ = true;
    run_.job.problem = std::move(screen);
  }

  void FitDeclaredModel() {
    phases_.Begin("base fit");
    const auto start = std::chrono::steady_clock::now();
    result_ = FitParameters(run_.job.problem, &out_);
    base_fit_seconds_ =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run_.discovered = run_.job.discover.enabled;
  }

  // The declared model's fit under the other accelerometer convention
  // (estimation/sampling_check.h): said at once, before discovery would
  // explain a sampling misfit by plant effects.
  void CheckTheAccelerometerSampling() {
    if (result_.abandoned_horizon != 0.0) return;
    // No accelerometer fitted: nothing to check or say.
    if (!(FittedPeriod(run_.job.problem, Channel::kA) > 0.0)) return;
    Stage("checking the accelerometer's sampling convention");
    try {
      run_.sampling_check = CheckAccelerometerSampling(run_.job.problem, result_);
    } catch (const std::runtime_error&) {
      run_.sampling_check = SamplingCheck{};  // the estimate does not simulate: no check
    }
    if (!run_.sampling_check.note.empty()) out_ << SamplingLine() << "\n";
  }

  // The sampling check's note as printed: a warning where the model or job
  // declares the convention (a declaration is the user's knowledge of the
  // recorder: kept, discovery/discovery_session.h), else a note.
  std::string SamplingLine() const {
    if (run_.job.problem.model.declared.count("accelerometer") > 0) {
      return "warning: the declared convention is kept; " + run_.sampling_check.note;
    }
    return "note: " + run_.sampling_check.note;
  }

  // The residual diagnostics of the model as declared, before adding
  // anything; then discovery (discovery/discovery_session.h: the
  // convention, the loop, the convention again, the force map).
  void DiscoverEffects() {
    EstimationProblem& job = run_.job.problem;
    out_ << "\nBefore discovery:\n" << FormatParameterTable(result_) << "\n"
         << FormatFitTable(result_);
    run_.diagnostics = DiagnoseResiduals(AtEstimate(job, result_));
    out_ << "\n" << FormatDiagnostics(run_.diagnostics);
    DiscoveryOutcome outcome =
        RunDiscovery(run_.job.discover, run_.sampling_check, base_fit_seconds_, &job, &result_,
                     out_, [this](const char* what) { Stage(what); });
    run_.discovery = std::move(outcome.report);
    run_.force_map = std::move(outcome.force_map);
    run_.sampling_check = std::move(outcome.sampling_check);
    out_ << "\nAfter discovery:\n";
  }

  // With the quasi-steady current loop: how far the approximation moves the
  // estimate on these records (estimation/current_loop_check.h); a note if
  // by more than half a standard error, and past
  // simulation.full_loop_refit_above standard errors a refit of the
  // paper's full loop from there (RefitTheFullLoop). After discovery the
  // loop's steps and tables stay the quasi-steady model's and the final
  // values and intervals are the refit's, of the discovered model: without
  // it the discovery-mode estimates kept the approximation's shift (2–3
  // standard errors on the independent-data square + sweep records, where
  // 79/100 intervals held the truth); not after a force map is adopted
  // (its roughness penalty belongs to the quasi-steady fit's λ). A refit
  // that fails keeps the quasi-steady fit, with the note. A screened job
  // (ScreenTheCurrentLoop) is refitted whatever the shift: its user
  // declared the full loop.
  void CheckTheCurrentLoop() {
    const AxisStructure& structure = run_.job.problem.model.structure;
    if (structure.amplifier != Amplifier::kAnalogVelocityLoop ||
        structure.current_loop != CurrentLoop::kQuasiSteady) {
      return;
    }
    if (result_.abandoned_horizon != 0.0) {
      if (screened_) {
        result_.model_note += std::string(result_.model_note.empty() ? "" : "; ") +
                              "the fit stopped on the quasi-steady screen of the declared full "
                              "current loop: the values are the screen's";
      }
      return;
    }
    Stage("checking the quasi-steady current loop against the full loop");
    const auto check_start = std::chrono::steady_clock::now();
    run_.loop_check = CheckCurrentLoop(run_.job.problem, result_);
    run_.loop_check.screened = screened_;
    run_.loop_check.screen_step = screened_ ? screen_step_ : 0.0;
    const double check_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - check_start).count();
    std::string not_refitted;
    if (screened_ && run_.force_map.kept) {
      not_refitted = "; the declared full current loop was not refitted after the force map "
                     "(its roughness penalty belongs to the quasi-steady fit): the values are "
                     "the quasi-steady screen's";
    }
    if (!run_.force_map.kept &&
        (screened_ || run_.loop_check.largest > run_.job.full_loop.refit_above)) {
      try {
        RefitTheFullLoop(check_seconds);
      } catch (const std::exception& e) {
        not_refitted = std::string("; the full-loop refit failed (") + e.what() +
                       (screened_ ? "): the values are the quasi-steady screen's"
                                  : "): the values are the quasi-steady fit's");
      }
    }
    if (run_.discovered && run_.loop_check.refitted) JudgeTheEffectsAgain();
    if (!run_.loop_check.refitted && (!run_.loop_check.note.empty() || !not_refitted.empty())) {
      const std::string note = run_.loop_check.note.empty()
                                   ? not_refitted.substr(2)  // without its leading "; "
                                   : run_.loop_check.note + not_refitted;
      result_.model_note += (result_.model_note.empty() ? "" : "; ") + note;
    }
  }

  // The refit with the paper's full loop (estimation/full_loop_refit.h)
  // from the quasi-steady estimate less its first-order shift: a local
  // solve whose intervals are the quasi-steady fit's carried over, or the
  // job's optimum check and uncertainty method again
  // (simulation.full_loop_intervals); its initial values reported as the job's, the quasi-steady fit and the
  // check as its first phases. Throws std::runtime_error if it ends without
  // an estimate.
  void RefitTheFullLoop(double check_seconds) {
    Stage("refitting with the full current loop");
    const FitJob& job = run_.job;
    EstimationProblem full =
        FullLoopRefitProblem(job.problem, result_, run_.loop_check, job.full_loop.intervals);
    // The screened job's own step, not the check's.
    if (screened_) run_.loop_check.full_step = TakeFinerSteps(declared_, &full);
    std::ostringstream why;
    if (screened_) {
      why << "the job declares the full loop; simulation.quasi_steady_screen: auto";
    } else {
      why << "simulation.full_loop_refit_above: " << job.full_loop.refit_above;
    }
    out_ << "\n" << run_.loop_check.note << "\nRefitting with the full current loop at "
         << run_.loop_check.full_step << " s from the quasi-steady estimate (" << why.str()
         << ")\n";
    FitResult refit = FitParameters(full, &out_);
    if (!std::isfinite(refit.final_cost) || !refit.converged) {
      throw std::runtime_error(refit.termination.empty() ? "no estimate" : refit.termination);
    }
    const bool carried = job.full_loop.intervals == FullLoopRefitSettings::Intervals::kCarried;
    if (carried) CarryQuasiSteadyIntervals(result_, &refit);
    for (ParameterEstimate& e : refit.parameters) {
      for (const ParameterEstimate& before : result_.parameters) {
        if (before.name == e.name) e.initial = before.initial;
      }
    }
    // The time and evaluations of the quasi-steady fit and the check before
    // this fit's own phases.
    double quasi_seconds = 0.0;
    int quasi_jacobians = 0;
    for (const FitPhase& f : result_.phases) {
      quasi_seconds += f.seconds;
      quasi_jacobians += f.jacobians;
    }
    refit.phases.insert(refit.phases.begin(),
                        {FitPhase{"quasi-steady fit", quasi_seconds, result_.simulations,
                                  quasi_jacobians},
                         FitPhase{"current loop check", check_seconds, 0, 0}});
    refit.simulations += result_.simulations;
    refit.jacobian_evaluations += result_.jacobian_evaluations;
    run_.loop_check.refitted = true;
    std::ostringstream note;
    if (run_.loop_check.measured) {
      note << "fitted first with the quasi-steady current loop, which shifted the estimate by "
              "up to "
           << FormatNumber(run_.loop_check.largest, 3)
           << " standard errors against the full loop on these records";
    } else {
      note << "fitted first with the quasi-steady current loop (its shift against the full "
              "loop not measured"
           << (run_.loop_check.note.empty() ? "" : ": " + run_.loop_check.note) << ")";
    }
    note << "; the values and traces are the full loop's, refitted at "
         << run_.loop_check.full_step
         << " s from the estimate less that shift (" << why.str()
         << "; the cost's initial value is the full loop's at the quasi-steady estimate); "
         << (carried ? "the intervals are the quasi-steady fit's, carried over "
                       "(simulation.full_loop_intervals: carried)"
                     : "so are the optimum check and the intervals "
                       "(simulation.full_loop_intervals: refitted)");
    refit.model_note += (refit.model_note.empty() ? "" : "; ") + note.str();
    if (!result_.auto_starts_note.empty()) {
      refit.auto_starts_note = "in the quasi-steady fit: " + result_.auto_starts_note;
    }
    run_.job.problem = std::move(full);
    result_ = std::move(refit);
  }

  // After a full-loop refit of a discovered model: the effects judged again
  // at the refit's estimate (discovery/discovery_session.h
  // JudgeEffectsAgain); where one goes, the intervals carried across its
  // removal and the note saying so.
  void JudgeTheEffectsAgain() {
    Stage("the discovered effects' significance with the full loop");
    const std::string refit_note = result_.model_note;
    const FitResult with_effects = result_;
    std::vector<std::string> removed;
    try {
      removed = JudgeEffectsAgain(run_.job.discover.alpha, &run_.job.problem, &result_,
                                  &run_.discovery, out_);
    } catch (const std::exception& e) {
      result_.model_note += std::string("; the significance check with the full loop failed (") +
                            e.what() + ")";
      return;
    }
    if (removed.empty()) return;
    std::string names;
    for (const std::string& name : removed) names += (names.empty() ? "" : ", ") + name;
    const bool carried = run_.job.full_loop.intervals == FullLoopRefitSettings::Intervals::kCarried;
    if (carried) CarryIntervalsAcrossRemoval(with_effects, &result_);
    result_.model_note = refit_note + "; then " + names +
                         " not significant with the full loop (Wald and likelihood ratio at "
                         "the loop's level): refitted without" +
                         (carried ? " (the intervals carried over as before)"
                                  : " (the full loop's own intervals)");
    out_ << "note: " << names << " dropped: not significant with the full current loop\n";
  }

  // The residual diagnostics of the fitted model, for report.html (with
  // discovery they are those of the declared model, DiscoverEffects).
  void DiagnoseTheFit() {
    Stage("diagnosing the residuals");
    try {
      run_.diagnostics = DiagnoseResiduals(AtEstimate(run_.job.problem, result_));
    } catch (const std::runtime_error&) {
      run_.diagnostics.clear();  // the fitted model does not simulate: no diagnostics
    }
  }

  // The frequency response of each fitted experiment at the final
  // estimate (discovery/frequency_response.h).
  // Off with `frequency_response: {enabled: false}`.
  void AnalyseTheFrequencyResponse() {
    if (!run_.job.frequency_response.enabled) return;
    Stage("frequency response");
    try {
      run_.frequency_response = AnalyseFrequencyResponse(AtEstimate(run_.job.problem, result_),
                                                         result_, run_.job.frequency_response);
    } catch (const std::exception& e) {
      run_.frequency_response.clear();  // the fitted model does not simulate a record
      run_.frequency_response_note = std::string("no frequency response: ") + e.what();
    }
  }

  void DesignTheNextExperiment() {
    Stage("designing the next experiment");
    try {
      run_.proposal =
          ProposeExperiment(run_.job.problem, result_, run_.job.design, run_.job.discover,
                            run_.job.problem.solver.progress ? &out_ : nullptr);
    } catch (const std::runtime_error& e) {
      // A simulation at the estimates failed: the fit's results stand.
      run_.proposal = ExperimentProposal{};
      run_.proposal.reason = std::string("no proposal: ") + e.what();
    }
    proposal_text_ = FormatProposal(run_.proposal);
    out_ << "\n" << proposal_text_;
  }

  // The analog loop tuned to the job's spec on the identified axis
  // (tune/analog_loop_tuning.h), printed after the fit's tables.
  void TuneTheAxis() {
    Stage("tuning the analog loop");
    try {
      run_.tuning = TuneAnalogLoop(run_.job.problem, result_, run_.job.tune);
    } catch (const std::runtime_error& e) {
      run_.tuning = AnalogLoopTuning{};
      run_.tuning.note = std::string("no tuning: ") + e.what();
    }
    out_ << "\n" << FormatTuning(run_.tuning);
    if (!run_.job.tune.move.enabled) return;
    Stage("tuning the position controller and the move");
    try {
      run_.move_tuning = TuneMove(run_.job.problem, result_, run_.job.tune, &run_.tuning);
    } catch (const std::exception& e) {
      run_.move_tuning = MoveTuning{};
      run_.move_tuning.note = std::string("no move tuning: ") + e.what();
    }
    out_ << "\n" << FormatMoveTuning(run_.move_tuning);
  }

  void PrintTables() {
    const FitResult& result = result_;
    out_ << "\n" << FormatParameterTable(result) << "\n" << FormatFitTable(result);
    out_ << "cost " << result.initial_cost << " -> " << result.final_cost
         << (result.converged ? " (converged)" : " (NOT converged)") << ", "
         << result.simulations << " simulations, " << result.jacobian_evaluations
         << " Jacobian evaluations\n";
    out_ << FormatPhases(result) << "\n";
    out_ << "integration: " << result.integration
         << (run_.job.step_note.empty() ? "" : "; " + run_.job.step_note) << "\n";
    if (!result.model_note.empty()) out_ << "note: " << result.model_note << "\n";
    if (!result.auto_starts_note.empty()) out_ << "starts: " << result.auto_starts_note << "\n";
    if (!result.sample_sigma_note.empty()) out_ << "weights: " << result.sample_sigma_note << "\n";
    if (!run_.sampling_check.note.empty()) out_ << SamplingLine() << "\n";
    if (!result.residual_note.empty()) out_ << "warning: " << result.residual_note << "\n";
    out_ << result.optimum_check << "\n";
    out_ << "uncertainty: " << result.uncertainty_note << "\n";
    if (!result.misspecification_note.empty()) {
      out_ << "misspecification: " << result.misspecification_note << "\n";
    }
    if (run_.job.problem.uncertainty.bootstrap > 0) out_ << FormatBootstrap(result);
    if (!run_.frequency_response_note.empty()) out_ << run_.frequency_response_note << "\n";
    out_ << FormatFrequencyResponse(run_.frequency_response);
  }

  // What params.md and report.json add to the fit's own tables.
  void AddSections() {
    ReportSections& extra = run_.sections;
    if (!input_markdown_.empty()) {
      extra.markdown += "\n## Inputs\n\n" + input_markdown_;
      extra.json["input_notes"] = input_notes_;
    }
    if (run_.loop_check.ran) AddCurrentLoopSection();
    if (!run_.job.step_note.empty()) extra.json["integration_step_rule"] = run_.job.step_note;
    nlohmann::json phases = nlohmann::json::array();
    for (const RunPhase& p : run_.phases) {
      phases.push_back({{"name", p.name},
                        {"seconds", JsonNumber<nlohmann::json>(p.seconds)},
                        {"simulations", p.simulations},
                        {"derivative_simulations", p.derivative_simulations}});
    }
    extra.json["run_phases"] = phases;
    if (run_.sampling_check.ran) {
      const SamplingCheck& c = run_.sampling_check;
      extra.json["accelerometer_check"] = {
          {"declared", c.declared},
          {"explained_as_declared", c.explained},
          {"other", c.other},
          {"chi2_declared", JsonNumber<nlohmann::json>(c.chi2_declared)},
          {"chi2_other", JsonNumber<nlohmann::json>(c.chi2_other)},
          {"chi2_declared_with_delay", JsonNumber<nlohmann::json>(c.chi2_declared_delay)},
          {"chi2_other_with_delay", JsonNumber<nlohmann::json>(c.chi2_other_delay)},
          {"samples", c.samples},
          {"declared_by_user", run_.job.problem.model.declared.count("accelerometer") > 0},
          {"note", c.note}};
      if (!c.note.empty()) extra.markdown += "\n## Accelerometer sampling\n\n" + c.note + "\n";
    }
    if (!run_.frequency_response.empty()) {
      extra.markdown += "\n## Frequency response\n\n```\n" +
                        FormatFrequencyResponse(run_.frequency_response) + "```\n";
    }
    if (run_.job.frequency_response.enabled) {
      extra.json["frequency_response"] = FrequencyResponseToJson(run_.frequency_response);
    }
    if (run_.job.published.present) AddPublishedSection();
    if (run_.discovered) AddDiscoverySections();
    if (run_.job.design.enabled) {
      extra.markdown += "\n## Next experiment\n\n```\n" + proposal_text_ + "```\n";
      extra.json["next_experiment"] = ProposalToJson(run_.proposal);
    }
    if (run_.job.tune.enabled) {
      extra.markdown += "\n## Tuning\n\n```\n" + FormatTuning(run_.tuning) + "```\n";
      extra.json["tuning"] = TuningToJson(run_.tuning);
    }
    if (run_.job.tune.move.enabled) {
      extra.markdown += "\n## Move tuning\n\n```\n" + FormatMoveTuning(run_.move_tuning) + "```\n";
      extra.json["move_tuning"] = MoveTuningToJson(run_.move_tuning);
    }
  }

  void AddCurrentLoopSection() {
    const CurrentLoopCheck& check = run_.loop_check;
    nlohmann::json shifts = nlohmann::json::object();
    for (size_t k = 0; k < check.names.size(); ++k) {
      shifts[check.names[k]] = {
          {"shift", JsonNumber<nlohmann::json>(check.shift[k])},
          {"shift_in_std_errors", JsonNumber<nlohmann::json>(check.shift_in_se[k])}};
    }
    run_.sections.json["current_loop_check"] = {
        {"largest_shift_in_std_errors", JsonNumber<nlohmann::json>(check.largest)},
        {"refitted_with_full_loop", check.refitted},
        {"screened", check.screened},
        {"screen_step", JsonNumber<nlohmann::json>(check.screen_step)},
        {"parameters", shifts},
        {"note", check.note}};
    std::ostringstream line;
    line << "current loop: the quasi-steady fit of the full loop's trace at the estimate moves "
            "no parameter by more than "
         << FormatNumber(check.largest, 3) << " standard errors";
    if (check.measured && check.note.empty()) out_ << line.str() << "\n";
  }

  void AddPublishedSection() {
    Stage("simulating the published model");
    run_.has_published = true;
    run_.published = ComparePublished(run_.job.problem, result_, run_.job.published);
    const std::string table = FormatPublished(run_.published);
    out_ << "\n" << table;
    run_.sections.markdown += "\n## Published reference\n\n```\n" + table + "```\n";
    run_.sections.json["published"] = PublishedToJson(run_.published);
  }

  void AddDiscoverySections() {
    ReportSections& extra = run_.sections;
    extra.markdown += "\n## Residual diagnostics (model as declared)\n\n```\n" +
                      FormatDiagnostics(run_.diagnostics) +
                      "```\n\n## Model discovery\n\n```\n" +
                      FormatDiscovery(run_.discovery) + "```\n" +
                      "\n## Residual diagnostics (final model)\n\n```\n" +
                      FormatDiagnostics(run_.discovery.final_diagnostics) + "```\n";
    extra.json["discovery"] = DiscoveryToJson(run_.discovery);
    if (run_.job.discover.force_map) {
      extra.markdown += "\n## Force map\n\n```\n" + FormatForceMap(run_.force_map) + "```\n";
      extra.json["force_map"] = ForceMapToJson(run_.force_map);
    }
  }

  std::ostream& out_;
  ProgressStream* const progress_line_;
  PhaseLog phases_;  // run_.phases at the end
  bool discover_ = false;
  JobRun run_;
  FitResult result_;  // moved into run_.result at the end
  double base_fit_seconds_ = 0.0;
  // The job as declared, while its quasi-steady screen is fitted
  // (ScreenTheCurrentLoop).
  EstimationProblem declared_;
  bool screened_ = false;
  double screen_step_ = 0.0;  // s, the screen's smallest step
  nlohmann::json input_notes_ = nlohmann::json::array();
  std::string input_markdown_;
  std::string proposal_text_;  // FormatProposal's, with `design:`
};

}  // namespace

JobRun RunJob(FitJob job, bool discover, std::ostream& out) {
  return JobPipeline(std::move(job), discover, out).Run();
}

}  // namespace axis
