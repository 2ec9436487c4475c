// Job key `design:` (configs/README.md): the settings of the search for the
// next experiment (design/experiment_design.h) and their strict loader.
#ifndef DESIGN_DESIGN_SETTINGS_H_
#define DESIGN_DESIGN_SETTINGS_H_

#include <string>

#include <yaml-cpp/yaml.h>

#include "io/yaml_util.h"

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

// Reads the job key `design:` (a mapping) into `d`, with enabled set:
// duration in [0.5, 60] s, max_voltage in (0, 10] V, travel [low, high] m
// (required, finite, low < high), rel_se ≥ 0. Throws std::invalid_argument
// naming file, line and key (io/yaml_util.h).
void ReadDesignSettings(const YAML::Node& node, const std::string& file, DesignSettings* d);

}  // namespace axis

#endif  // DESIGN_DESIGN_SETTINGS_H_
