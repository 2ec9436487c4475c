#include "run/job_run.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "common/format.h"
#include "common/progress.h"
#include "design/experiment_design.h"
#include "discovery/diagnostics.h"
#include "discovery/discovery.h"
#include "discovery/force_map.h"
#include "estimation/at_estimate.h"
#include "estimation/current_loop_check.h"
#include "estimation/fit.h"
#include "estimation/fit_notes.h"
#include "estimation/fit_result.h"
#include "estimation/uncertainty.h"
#include "job/discovery_settings.h"
#include "job/fit_job.h"
#include "report/published.h"
#include "report/report.h"

namespace axis {

JobRun RunJob(FitJob job, bool discover, std::ostream& out) {
  if (job.benchmark.present) {
    throw std::invalid_argument(job.path +
                                ": key 'benchmark': expected a job without 'benchmark:' here "
                                "(fit-params runs its criteria, each a job of its own: "
                                "job/benchmark_settings.h CriterionJob), got one");
  }
  JobRun run;
  // Columns read in a way the job did not state (e.g. held inputs).
  nlohmann::json input_notes = nlohmann::json::array();
  std::string input_markdown;
  for (const std::vector<FitExperiment>* list : {&job.experiments, &job.validate}) {
    for (const FitExperiment& e : *list) {
      for (const std::string& note : e.input_notes) {
        out << "  " << e.name << ": " << note << "\n";
        input_markdown += "- " + e.name + ": " + note + "\n";
        run.input_lines.push_back(e.name + ": " + note);
        input_notes.push_back({{"experiment", e.name}, {"note", note}});
      }
    }
  }
  if (discover) job.discover.enabled = true;
  // A stage of the run after the fit, on the progress line when `out` is
  // fit-params' progress stream (common/progress.h).
  ProgressStream* progress_line = dynamic_cast<ProgressStream*>(&out);
  const auto stage = [&](const char* what) {
    if (job.solver.progress && progress_line != nullptr) {
      progress_line->Status(what, std::numeric_limits<double>::quiet_NaN());
    }
  };
  const auto base_start = std::chrono::steady_clock::now();
  FitResult result = FitParameters(job, &out);
  const double base_fit_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - base_start).count();
  run.discovered = job.discover.enabled;
  if (run.discovered) {
    out << "\nBefore discovery:\n" << FormatParameterTable(result) << "\n"
        << FormatFitTable(result);
    // Diagnose the residual of the model as declared, before adding anything.
    run.diagnostics = DiagnoseResiduals(AtEstimate(job, result));
    out << "\n" << FormatDiagnostics(run.diagnostics);
    DiscoverySettings settings = job.discover;
    settings.enabled = true;
    run.discovery = Discover(settings, &job, &result, &out);
    run.discovery.base_fit_seconds = base_fit_seconds;
    out << "\nFinal model:\n" << FormatDiagnostics(run.discovery.final_diagnostics) << "\n"
        << FormatDiscovery(run.discovery);
    if (settings.force_map) {
      stage("force map");
      run.force_map = AddForceMap(settings, run.discovery, &job, &result, &out);
      ApplyRemovals(run.force_map, &run.discovery);
      out << "\n" << FormatForceMap(run.force_map);
    }
    out << "\nAfter discovery:";
  }
  // With the quasi-steady current loop: how far the approximation moves the
  // estimate on these records (estimation/current_loop_check.h); a note if by more
  // than half a standard error, and past simulation.full_loop_refit_above
  // standard errors (without discovery: its steps, tables and diagnostics
  // are the quasi-steady model's) a refit of the paper's full loop from
  // there (WithFullLoop; the job's optimum check and uncertainty method;
  // its initial values reported as the job's). A refit that fails keeps the
  // quasi-steady fit, with the note.
  if (job.model.structure.amplifier == Amplifier::kAnalogVelocityLoop &&
      job.model.structure.current_loop == CurrentLoop::kQuasiSteady &&
      result.abandoned_horizon == 0.0) {
    stage("checking the quasi-steady current loop against the full loop");
    const auto check_start = std::chrono::steady_clock::now();
    run.loop_check = CheckCurrentLoop(job, result);
    const double check_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - check_start).count();
    std::string refit_failed;
    if (!run.discovered && run.loop_check.largest > job.full_loop_refit_above) {
      stage("refitting with the full current loop");
      out << "\n" << run.loop_check.note << "\nRefitting with the full current loop at "
          << run.loop_check.full_step << " s from the quasi-steady estimate (simulation."
          << "full_loop_refit_above: " << job.full_loop_refit_above << ")\n";
      try {
        FitJob full = WithFullLoop(AtEstimate(job, result));
        full.solver.starts = 0;
        full.solver.auto_starts = 0;
        full.solver.first_horizon = 0.0;
        FitResult refit = FitParameters(full, &out);
        if (!std::isfinite(refit.final_cost) || !refit.converged) {
          throw std::runtime_error(refit.termination.empty() ? "no estimate" : refit.termination);
        }
        for (ParameterEstimate& e : refit.parameters) {
          for (const ParameterEstimate& before : result.parameters) {
            if (before.name == e.name) e.initial = before.initial;
          }
        }
        // The time and evaluations of the quasi-steady fit and the check
        // before this fit's own phases.
        double quasi_seconds = 0.0;
        int quasi_jacobians = 0;
        for (const FitPhase& f : result.phases) {
          quasi_seconds += f.seconds;
          quasi_jacobians += f.jacobians;
        }
        refit.phases.insert(refit.phases.begin(),
                            {FitPhase{"quasi-steady fit", quasi_seconds, result.simulations,
                                      quasi_jacobians},
                             FitPhase{"current loop check", check_seconds, 0, 0}});
        refit.simulations += result.simulations;
        refit.jacobian_evaluations += result.jacobian_evaluations;
        run.loop_check.refitted = true;
        std::ostringstream note;
        note << "fitted first with the quasi-steady current loop, which shifted the estimate by "
                "up to "
             << FormatNumber(run.loop_check.largest, 3)
             << " standard errors against the full loop on these records; the values, "
                "intervals and traces are the full loop's, refitted at "
             << run.loop_check.full_step
             << " s from there (simulation.full_loop_refit_above: " << job.full_loop_refit_above
             << "; the cost's initial value is the full loop's at the quasi-steady estimate)";
        refit.model_note += (refit.model_note.empty() ? "" : "; ") + note.str();
        if (!result.auto_starts_note.empty()) {
          refit.auto_starts_note = "in the quasi-steady fit: " + result.auto_starts_note;
        }
        job = std::move(full);
        result = std::move(refit);
      } catch (const std::exception& e) {
        refit_failed = std::string("; the full-loop refit failed (") + e.what() +
                       "): the values are the quasi-steady fit's";
      }
    }
    if (!run.loop_check.refitted && (!run.loop_check.note.empty() || !refit_failed.empty())) {
      const std::string note = run.loop_check.note.empty()
                                   ? refit_failed.substr(2)  // without its leading "; "
                                   : run.loop_check.note + refit_failed;
      result.model_note += (result.model_note.empty() ? "" : "; ") + note;
    }
  }
  // The fit's s² settled (the force map's, the full loop's): the warning.
  result.residual_note = ResidualNote(result.residual_variance);
  if (!run.discovered) {
    // The residual diagnostics of the fitted model, for report.html (with
    // discovery they are those of the declared model, above).
    stage("diagnosing the residuals");
    try {
      run.diagnostics = DiagnoseResiduals(AtEstimate(job, result));
    } catch (const std::runtime_error&) {
      run.diagnostics.clear();  // the fitted model does not simulate: no diagnostics
    }
  }
  ResidualBootstrap(job, &result, &out);
  std::string proposal_text;  // FormatProposal's, with `design:`
  if (job.design.enabled) {
    stage("designing the next experiment");
    try {
      run.proposal = ProposeExperiment(job, result, job.solver.progress ? &out : nullptr);
    } catch (const std::runtime_error& e) {
      // A simulation at the estimates failed: the fit's results stand.
      run.proposal = ExperimentProposal{};
      run.proposal.reason = std::string("no proposal: ") + e.what();
    }
    proposal_text = FormatProposal(run.proposal);
    out << "\n" << proposal_text;
  }
  out << "\n" << FormatParameterTable(result) << "\n" << FormatFitTable(result);
  out << "cost " << result.initial_cost << " -> " << result.final_cost
      << (result.converged ? " (converged)" : " (NOT converged)") << ", "
      << result.simulations << " simulations, " << result.jacobian_evaluations
      << " Jacobian evaluations\n";
  out << FormatPhases(result) << "\n";
  out << "integration: " << result.integration << "\n";
  if (!result.model_note.empty()) out << "note: " << result.model_note << "\n";
  if (!result.auto_starts_note.empty()) out << "starts: " << result.auto_starts_note << "\n";
  if (!result.residual_note.empty()) out << "warning: " << result.residual_note << "\n";
  out << result.optimum_check << "\n";
  out << "uncertainty: " << result.uncertainty_note << "\n";
  if (job.uncertainty.bootstrap > 0) out << FormatBootstrap(result);
  ReportSections& extra = run.sections;
  if (!input_markdown.empty()) {
    extra.markdown += "\n## Inputs\n\n" + input_markdown;
    extra.json["input_notes"] = input_notes;
  }
  if (run.loop_check.ran) {
    nlohmann::json shifts = nlohmann::json::object();
    for (size_t k = 0; k < run.loop_check.names.size(); ++k) {
      shifts[run.loop_check.names[k]] = {
          {"shift", JsonNumber<nlohmann::json>(run.loop_check.shift[k])},
          {"shift_in_std_errors", JsonNumber<nlohmann::json>(run.loop_check.shift_in_se[k])}};
    }
    extra.json["current_loop_check"] = {
        {"largest_shift_in_std_errors", JsonNumber<nlohmann::json>(run.loop_check.largest)},
        {"refitted_with_full_loop", run.loop_check.refitted},
        {"parameters", shifts},
        {"note", run.loop_check.note}};
    std::ostringstream line;
    line << "current loop: the quasi-steady fit of the full loop's trace at the estimate moves "
            "no parameter by more than "
         << FormatNumber(run.loop_check.largest, 3) << " standard errors";
    if (run.loop_check.measured && run.loop_check.note.empty()) out << line.str() << "\n";
  }
  if (job.published.present) {
    stage("simulating the published model");
    run.has_published = true;
    run.published = ComparePublished(job, result);
    const std::string table = FormatPublished(run.published);
    out << "\n" << table;
    extra.markdown += "\n## Published reference\n\n```\n" + table + "```\n";
    extra.json["published"] = PublishedToJson(run.published);
  }
  if (run.discovered) {
    extra.markdown += "\n## Residual diagnostics (model as declared)\n\n```\n" +
                      FormatDiagnostics(run.diagnostics) +
                      "```\n\n## Model discovery\n\n```\n" +
                      FormatDiscovery(run.discovery) + "```\n" +
                      "\n## Residual diagnostics (final model)\n\n```\n" +
                      FormatDiagnostics(run.discovery.final_diagnostics) + "```\n";
    extra.json["discovery"] = DiscoveryToJson(run.discovery);
    if (job.discover.force_map) {
      extra.markdown += "\n## Force map\n\n```\n" + FormatForceMap(run.force_map) + "```\n";
      extra.json["force_map"] = ForceMapToJson(run.force_map);
    }
  }
  if (job.design.enabled) {
    extra.markdown += "\n## Next experiment\n\n```\n" + proposal_text + "```\n";
    extra.json["next_experiment"] = ProposalToJson(run.proposal);
  }
  run.job = std::move(job);
  run.result = std::move(result);
  return run;
}

}  // namespace axis
