// libFuzzer target: the experiment loader (sim/config.h ParseExperiment) on
// arbitrary YAML text, relative paths resolved in configs/experiments (so
// that `model: ../axes/x_axis.yaml` of the seed corpus loads). Loading only:
// a loaded experiment is not simulated (its size is the memory check's
// business, sim/preflight.h).
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_common.h"
#include "sim/config.h"
#include "io/yaml_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  axis::fuzz::Expect(data, size, [](const std::string& text) {
    axis::ParseExperiment(axis::ParseYamlText(text, "fuzz.yaml"), "fuzz.yaml",
                          PROJECT_SOURCE_DIR "/configs/experiments");
  });
  return 0;
}
