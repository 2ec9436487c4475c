// The configs of sim/, one header each: model configs (sim/axis_config.h),
// the effects a model can switch on (sim/effect_table.h), what drives an
// experiment (sim/drive_config.h), experiment files
// (sim/experiment_config.h) and a model config written back as YAML
// (sim/axis_config_yaml.h). Include the one you use; this header gathers
// them for code that reads and writes all of them.
#ifndef SIM_CONFIG_H_
#define SIM_CONFIG_H_

#include "sim/axis_config.h"
#include "sim/axis_config_yaml.h"
#include "sim/drive_config.h"
#include "sim/effect_table.h"
#include "sim/experiment_config.h"

#endif  // SIM_CONFIG_H_
