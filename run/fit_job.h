// A fit job (configs/jobs/*.yaml): what a user asks for, as one aggregate of
// the settings each layer owns — the estimation problem (the model, the
// recorded experiments mapped to MODEL.md §6 channels, the free parameters,
// the solver and uncertainty settings: estimation/estimation_problem.h), the
// full-loop refit (estimation/full_loop_refit.h), discovery
// (discovery/discovery_settings.h), the next experiment
// (design/design_settings.h), tuning (tune/tune_settings.h), the published
// reference (report/published_reference.h) and the benchmark
// (run/benchmark_settings.h) — and where the outputs go. One strict loader
// (run/load_fit_job.h) that calls each layer's own; the format is described
// in configs/README.md. A layer takes the part it uses, never the job.
#ifndef RUN_FIT_JOB_H_
#define RUN_FIT_JOB_H_

#include <string>

#include "design/design_settings.h"
#include "discovery/discovery_settings.h"
#include "discovery/frequency_response_settings.h"
#include "estimation/estimation_problem.h"
#include "estimation/full_loop_refit.h"
#include "report/published_reference.h"
#include "run/benchmark_settings.h"
#include "tune/tune_settings.h"

namespace axis {

struct FitJob {
  std::string title;
  EstimationProblem problem;  // problem.path: the job file
  FullLoopRefitSettings full_loop;  // `simulation:` keys full_loop_refit_above,
                                    // full_loop_intervals, quasi_steady_screen
  DiscoverySettings discover;       // `discover:` key (enabled if present)
  DesignSettings design;            // `design:` key (design/experiment_design.h)
  // `frequency_response:` key (discovery/frequency_response.h)
  FrequencyResponseSettings frequency_response;
  TuneSettings tune;                // `tune:` key (tune/analog_loop_tuning.h)
  PublishedReference published;     // `published:` key (report/published.h)
  BenchmarkSettings benchmark;      // `benchmark:` key (run/benchmark.h)
  std::string out_dir;  // from output.dir (relative to the job file) or --out
  // How the integration step was chosen where simulation.step is absent
  // (sim/auto_step.h AutoStepNote); empty where the job gives the step.
  std::string step_note;
};

}  // namespace axis

#endif  // RUN_FIT_JOB_H_
