#include "estimation/solver_settings.h"

#include "io/settings_reader.h"
#include "io/yaml_util.h"

namespace axis {

void ReadSolverSettings(YamlMap* map, SolverSettings* s) {
  ReadSettings(map, s);
  if (!(s->function_tolerance <= 1e-2)) {
    ThrowConfigError(map->file(), map->Optional("function_tolerance"),
                     map->KeyPath("function_tolerance"), "a relative tolerance in [0, 0.01]",
                     NumberText(s->function_tolerance));
  }
  map->Finish();
}

void ReadUncertaintySettings(YamlMap* map, UncertaintySettings* u) {
  ReadSettings(map, u);
  map->Finish();
}

}  // namespace axis
