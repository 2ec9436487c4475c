// Job key `design:` (configs/README.md): the search for the next experiment
// (design/experiment_design.h, issue 15 part 2). Kept apart from the design
// code so that job/fit_job.h need not include it.
#ifndef JOB_DESIGN_SETTINGS_H_
#define JOB_DESIGN_SETTINGS_H_

namespace axis {

struct DesignSettings {
  bool enabled = false;       // `design:` present in the job
  // s, length of the proposed record (the duration budget), 0.5..60.
  double duration = 4.0;
  // V, bound on |U|, the set-velocity voltage (the drive's ±10 V), (0, 10].
  double max_voltage = 10.0;
  // m, the travel the axis must stay inside (required with `design:`); the
  // proposed experiment starts at rest at its centre.
  double travel_low = 0.0;
  double travel_high = 0.0;
  // A D-optimal experiment is proposed when a free parameter's relative
  // standard error exceeds this (and no pair of candidates waits to be
  // told apart, which takes precedence); 0 never.
  double rel_se = 0.0;
};

}  // namespace axis

#endif  // JOB_DESIGN_SETTINGS_H_
