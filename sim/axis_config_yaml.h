// A model config written back as YAML (the model with the effects the
// discovery loop added, fit-params --discover's model_discovered.yaml).
#ifndef SIM_AXIS_CONFIG_YAML_H_
#define SIM_AXIS_CONFIG_YAML_H_

#include <string>

#include "sim/axis_config.h"

namespace axis {

// The config as YAML that LoadAxisConfig reads back: structure, every
// parameter of MODEL.md §2, the enabled effects with their parameters, and
// the controller if any.
std::string AxisConfigToYaml(const AxisConfig& config);

}  // namespace axis

#endif  // SIM_AXIS_CONFIG_YAML_H_
